//! `camsim`: the command line of the camsim harness.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use camsim::cmd;

/// Simulation of real cam-follower mechanisms (Kim 1982, eleven degrees of freedom).
#[derive(Parser)]
#[command(name = "camsim", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Peak dimensionless coefficients of every motion law (Table VI.9's quantities).
    Laws(cmd::laws::Args),
    /// Natural frequencies, modes and modal stiffness (Eqs. VI.6 and VI.7).
    Modal(cmd::modal::Args),
    /// Hertz contact stiffness, width and stress of the reference roller and cam at a force.
    Contact(cmd::contact::Args),
    /// Simulate a scene (the reference design by default): per-period table, jumps, solver statistics.
    Run(cmd::run::Args),
    /// Lowest cam speed at which the follower separates in steady state (bisection on the model).
    JumpSpeed(cmd::jump_speed::Args),
    /// Print the reference design as a scene file, or check one.
    Scene(cmd::scene::Args),
    /// Run time against error: tolerance ladder and reduced scenes against a tight reference.
    Bench(cmd::bench::Args),
    /// The firmware's jump/timing predictor on the host (same scene and profile); --check-log for parity.
    Predict(cmd::predict::Args),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            // --help and --version are not errors.
            if !e.use_stderr() {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            // Usage errors on one line too (clap's own text starts with "error: ").
            let text = e.render().to_string();
            let first = text.lines().next().unwrap_or("invalid arguments");
            eprintln!("camsim: {} (see camsim --help)", first.trim());
            return ExitCode::from(2);
        }
    };
    let result = match cli.command {
        Command::Laws(a) => cmd::laws::run(a),
        Command::Modal(a) => cmd::modal::run(a),
        Command::Contact(a) => cmd::contact::run(a),
        Command::Run(a) => cmd::run::run(a),
        Command::JumpSpeed(a) => cmd::jump_speed::run(a),
        Command::Scene(a) => cmd::scene::run(a),
        Command::Bench(a) => cmd::bench::run(a),
        Command::Predict(a) => cmd::predict::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line, no backtrace.
            eprintln!("camsim: error: {}", format!("{e:#}").replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}
