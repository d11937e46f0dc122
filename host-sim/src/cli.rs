//! The command line: the command tree clap parses, the dispatch to [`crate::cmd`], and
//! usage errors folded to one line. `main.rs` is only [`main`]; the tests parse and run
//! exactly what the binary does.

use std::ffi::OsString;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

use crate::cmd;

/// Simulation of real cam-follower mechanisms (Kim 1982, eleven degrees of freedom).
#[derive(Parser, Debug)]
#[command(name = "camsim", version, about, long_about = None, after_long_help = UNITS_HELP)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
    /// Units of the output: inch (in, lb, psi) or si (mm, N, MPa); default: si for a scene
    /// file written in SI keys, else inch; with si a length, rate, force or stress option
    /// needs its unit (see `camsim --help`).
    #[arg(
        id = "units",
        long = "units",
        global = true,
        value_enum,
        value_name = "FAMILY",
        hide_possible_values = true
    )]
    pub units_option: Option<crate::units::Units>,
    /// The output's unit family, decided once by [`parse_from`] from `--units` and the
    /// scene file ([`crate::units::decide`]).
    #[arg(skip)]
    pub units: crate::units::Units,
    /// What decided [`Cli::units`].
    #[arg(skip)]
    pub units_from: crate::units::UnitsFrom,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
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
    /// Which model (full, vertical, reduced followers) is accurate enough for which question, and what it costs.
    Models(cmd::models::Args),
    /// The former name of `models` (prints a note and runs `models`).
    #[command(hide = true)]
    Scenes(cmd::models::Args),
    /// The firmware's jump/timing predictor on the host (same scene and scripted machine); --check-log for parity.
    Predict(cmd::predict::Args),
    /// Check the firmware's decoded QEMU logs: memory against llvm-size and memory.x, real-time factor, fault reactions, boot failure.
    FirmwareCheck(cmd::firmware_check::Args),
    /// Many actual cams in parallel: statistics of every per-period column and the jump probability; `montecarlo merge` combines the shards of a study.
    Montecarlo(cmd::montecarlo::Args),
    /// The cam as a drawing: surface, pitch curve and cutter path as DXF and CSV; the SVAJ plot.
    Profile(cmd::profile::Args),
    /// Every motion law on the theoretical and on an actual cam: the study of VI.4.2, ranked.
    Compare(cmd::compare::Args),
    /// The tolerance and waviness grid of VI.4.1 on the more stable program.
    ToleranceStudy(cmd::tolerance_study::Args),
    /// Masses, dampers and stiffnesses changed by -30 to +30 %: the sensitivity study of VI.4.3 (--per-key: every key's elasticity).
    Sensitivity(cmd::sensitivity::Args),
    /// The waviness (FPR) of an actual cam against its profile point interval, both profile methods, and the criteria of IV.2.3.
    Waviness(cmd::waviness::Args),
    /// The operating map: contact force, vibration, torque, stress and jumps at every speed
    /// of a grid, on the theoretical cam and (--actual) as P(jump) and bands over actual cams.
    Sweep(cmd::sweep::Args),
    /// What to build, found by search: `design spring` (the smallest return-spring rate
    /// holding contact with a margin, or P(jump) <= p on actual cams), `design speed` (the
    /// highest speed) and `design tolerance` (the loosest tolerance or roughest waviness)
    /// at P(jump) <= p.
    Design(cmd::design::Args),
}

/// `--units`, explained once (the end of `camsim --help`; each command's help gives
/// one line).
pub const UNITS_HELP: &str = "Units (--units inch|si, on every command):
  inch (the thesis's: in, lb, psi, lb in; `in` also reads) or si (mm, N, MPa, N m,
  N/mm, kg; `mm` also reads). Without --units, a command that reads a scene file
  answers in the file's family: si when every key with a unit in it is an SI one
  (base_radius_mm, spring_rate_n_per_mm), inch when its keys are inch, mix the two
  or have no unit; inch without a scene (scene --check lists an SI file in SI always).
  The family converts every --json key (each names its unit), every command's tables,
  the scene file of `scene` (SI keys), the --csv of run and sweep, profile's drawing
  and CSVs, and the plots; firmware-check prints bytes, instructions and rpm only, the
  same in either. The options with a length, spring rate, force or stress
  (--spring-rate, --preload-length, --atol, the tolerances, contact's --force, run's
  --allowable-stress, profile's --cutter-radius and --chord-error, design spring's
  --resolution) take a value with its unit in either family (17.5N/mm, 12.7mm, 1034MPa);
  a bare number is the inch family's, and with si (from --units or from the scene) it
  is refused: give the unit, or --units inch.";

/// What `camsim scenes` prints to standard error before it runs `models`.
pub const SCENES_RENAMED: &str =
    "camsim: note: `scenes` is now `models` (`scene` prints a scene file); `scenes` will be removed";

/// Parses a command line (the first item is the program name).
pub fn parse_from<I, T>(args: I) -> std::result::Result<Cli, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    parse_matches(args).map(|(cli, _)| cli)
}

/// [`parse_from`] with the matches clap made (for [`bare_in`]'s walk).
fn parse_matches<I, T>(args: I) -> std::result::Result<(Cli, clap::ArgMatches), clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    use clap::FromArgMatches;
    let matches = command().try_get_matches_from(args)?;
    let mut cli = Cli::from_arg_matches(&matches)?;
    let scene = scene_given(&command(), &matches);
    (cli.units, cli.units_from) = crate::units::decide(cli.units_option, scene.as_deref());
    Ok((cli, matches))
}

/// The scene file a command line gives: the first argument named `SCENE` (every
/// command's positional scene file, `predict --scene`) given a value, in the command or
/// the subcommand it runs.
fn scene_given(cmd: &clap::Command, m: &clap::ArgMatches) -> Option<std::path::PathBuf> {
    for arg in cmd.get_arguments() {
        // The name the usage shows: the value name, else the id (`[SCENE]`).
        let shown = match arg.get_value_names().and_then(|n| n.first()) {
            Some(n) => n.as_str().to_string(),
            None => arg.get_id().as_str().to_uppercase(),
        };
        let is_scene = shown == "SCENE";
        let id = arg.get_id().as_str();
        if !is_scene || m.value_source(id) != Some(clap::parser::ValueSource::CommandLine) {
            continue;
        }
        if let Some(v) = m.get_raw(id).into_iter().flatten().next() {
            return Some(v.into());
        }
    }
    let (name, sub) = m.subcommand()?;
    scene_given(cmd.find_subcommand(name)?, sub)
}

/// The command tree as clap builds it (its commands, options and help), every option
/// that takes a value taking a negative number as its value (`negatives_are_values`).
pub fn command() -> clap::Command {
    use clap::CommandFactory;
    negatives_are_values(Cli::command())
}

/// `cmd` and its subcommands with every value-taking option accepting a value that
/// looks like a negative number (`--seed -1`, `--shard -1/2`, `--rpm -100:100:3`), so
/// that it reaches the option's own rule and its message names the option, instead of
/// clap's "unexpected argument '-1' found".
fn negatives_are_values(cmd: clap::Command) -> clap::Command {
    let cmd = cmd.mut_args(|a| {
        if a.get_action().takes_values() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    });
    let names: Vec<String> = cmd
        .get_subcommands()
        .map(|s| s.get_name().to_string())
        .collect();
    names
        .into_iter()
        .fold(cmd, |c, n| c.mut_subcommand(n, negatives_are_values))
}

/// Runs a parsed command.
pub fn execute(cli: Cli) -> Result<()> {
    let units = cli.units;
    match cli.command {
        Command::Laws(a) => cmd::laws::run(a, units),
        Command::Modal(a) => cmd::modal::run(a, units),
        Command::Contact(a) => cmd::contact::run(a, units),
        Command::Run(a) => cmd::run::run(a, units),
        Command::JumpSpeed(a) => cmd::jump_speed::run(a, units),
        Command::Scene(a) => cmd::scene::run(a, units),
        Command::Bench(a) => cmd::bench::run(a, units),
        Command::Models(a) => cmd::models::run(a, units),
        Command::Scenes(a) => {
            report_error(SCENES_RENAMED);
            cmd::models::run(a, units)
        }
        Command::Predict(a) => cmd::predict::run(a, units),
        Command::FirmwareCheck(a) => cmd::firmware_check::run(a, units),
        Command::Montecarlo(a) => cmd::montecarlo::run(a, units),
        Command::Profile(a) => cmd::profile::run(a, units),
        Command::Compare(a) => cmd::compare::run(a, units),
        Command::ToleranceStudy(a) => cmd::tolerance_study::run(a, units),
        Command::Sensitivity(a) => cmd::sensitivity::run(a, units),
        Command::Waviness(a) => cmd::waviness::run(a, units),
        Command::Sweep(a) => cmd::sweep::run(a, units),
        Command::Design(a) => cmd::design::run(a, units),
    }
}

/// A usage error on one line: clap's message (without its "error: ") with what it
/// adds below it (the possible values, a missing argument, a tip) joined on, the usage
/// and help pointers left out.
pub fn usage_line(e: &clap::Error) -> String {
    let text = e.render().to_string();
    let mut parts: Vec<&str> = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
        if !line.is_empty() {
            parts.push(line);
        }
    }
    let line = parts.join(" ");
    let line = line.strip_prefix("error: ").unwrap_or(&line);
    if line.is_empty() {
        "invalid arguments".to_string()
    } else {
        line.to_string()
    }
}

/// The one-line message of a usage error: clap's ([`usage_line`]), except that a missing
/// command (bare `camsim`) says so and lists the commands instead of printing the tool's
/// description as if it were the error.
pub fn usage_message(e: &clap::Error) -> String {
    if e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
        let cmd = command();
        let names: Vec<&str> = cmd
            .get_subcommands()
            .filter(|c| !c.is_hide_set())
            .map(|c| c.get_name())
            .collect();
        return format!("a command is required: {}", names.join(", "));
    }
    usage_line(e)
}

/// Whether `e` comes from writing to a closed pipe (`camsim ... | head`): the reader has
/// what it wanted, which is not an error.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// The one line the binary prints (after `camsim: error: `) for a failed command: the
/// error and its causes, joined, with control characters escaped ([`one_line`]).
pub fn error_line(e: &anyhow::Error) -> String {
    one_line(&format!("{e:#}"))
}

/// A message made safe for a terminal and kept on one line: line breaks become spaces,
/// every other control character (an escape sequence in a file name, a NUL) is written
/// escaped (`\u{1b}`), so that no input can clear the screen or forge a line.
pub fn one_line(msg: &str) -> String {
    msg.chars()
        .map(|c| match c {
            '\n' => " ".to_string(),
            c if c.is_control() => c.escape_debug().to_string(),
            c => c.to_string(),
        })
        .collect()
}

/// Writes one line to standard error (a closed standard error is not worth a panic).
fn report_error(line: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// Under an SI output (`--units si`, or a scene in SI keys without `--units`), the first
/// option that takes an inch-family quantity (its value name `IN`, `LB_PER_IN`, `LB` or
/// `PSI`) and was given a bare number: the message refusing it. A bare number there is
/// inch (as the option's help says), which a command line in SI would not mean; with its
/// unit (`17.5N/mm`, `100lb/in`) it is read either way.
pub fn bare_inch_number(args: &[OsString]) -> Option<String> {
    let (cli, matches) = parse_matches(args).ok()?;
    bare_number_refusal(&cli, &matches)
}

/// [`bare_inch_number`] for a parsed command line.
fn bare_number_refusal(cli: &Cli, matches: &clap::ArgMatches) -> Option<String> {
    use crate::units::{Units, UnitsFrom};
    if cli.units != Units::Si {
        return None;
    }
    let (option, value, unit) = bare_in(&command(), matches)?;
    let (si, inch) = (unit.si_symbol, unit.inch_symbol);
    Some(match &cli.units_from {
        UnitsFrom::Scene(p) => format!(
            "--{option} {value}: give its unit, {value}{si} or {value}{inch}: the output is SI because the scene file {} is written in SI keys (or give --units inch, where a bare number is {inch}, this option's unit)",
            p.display()
        ),
        _ => format!(
            "--{option} {value}: with --units si give its unit, {value}{si} or {value}{inch} (a bare number is {inch}, this option's unit)"
        ),
    })
}

/// The first option with an inch-family value name given a bare number: its long name,
/// the value and its unit.
fn bare_in(
    cmd: &clap::Command,
    m: &clap::ArgMatches,
) -> Option<(String, String, camsim_scene_file::units::Unit)> {
    use camsim_scene_file::units::{LENGTH, STIFFNESS};
    for arg in cmd.get_arguments() {
        let unit = match arg
            .get_value_names()
            .and_then(|n| n.first())
            .map(|n| n.as_str())
        {
            Some("IN") => LENGTH,
            Some("LB_PER_IN") => STIFFNESS,
            Some("LB") => crate::units::FORCE,
            Some("PSI") => camsim_scene_file::units::STRESS,
            _ => continue,
        };
        let id = arg.get_id().as_str();
        if m.value_source(id) != Some(clap::parser::ValueSource::CommandLine) {
            continue;
        }
        let long = arg.get_long().unwrap_or(id);
        for raw in m.get_raw(id).into_iter().flatten() {
            let v = raw.to_string_lossy();
            if crate::args::unit_of(&v).is_none() {
                return Some((long.to_string(), v.into_owned(), unit));
            }
        }
    }
    let (name, sub) = m.subcommand()?;
    bare_in(cmd.find_subcommand(name)?, sub)
}

/// The binary: parse, run, print any error on one line (exit 2 for usage errors, clap's
/// and the commands' [`crate::args::UsageError`]s, 1 for failures; a closed standard
/// output ends the run quietly with 0).
pub fn main() -> ExitCode {
    ExitCode::from(main_from(std::env::args_os()))
}

/// The stack of the thread every command runs on: 64 MiB of address space (pages are
/// taken only as they are touched). The main thread's stack is the shell's `ulimit -s`
/// (8 MiB by default, 256 KiB on some systems and in some containers), which the
/// solvers' state on the stack and the parsers' recursion must not depend on.
pub const WORKER_STACK_BYTES: usize = 64 << 20;

/// [`main`] for a given command line (the first item is the program name), returning the
/// exit status: what the binary does, callable from tests. The command runs on a worker
/// thread with a stack of [`WORKER_STACK_BYTES`] (a panic on it is raised again here).
pub fn main_from<I, T>(args: I) -> u8
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let args: Vec<OsString> = args.into_iter().map(Into::into).collect();
    let worker = std::thread::Builder::new()
        .name("camsim".into())
        .stack_size(WORKER_STACK_BYTES)
        .spawn(move || main_on_worker(&args));
    match worker.map(|w| w.join()) {
        Ok(Ok(code)) => code,
        Ok(Err(panic)) => std::panic::resume_unwind(panic),
        Err(e) => {
            report_error(&format!(
                "camsim: error: cannot start the worker thread ({} of stack): {e}",
                crate::output::human_bytes(WORKER_STACK_BYTES as u64)
            ));
            1
        }
    }
}

/// Writes clap's `--help` or `--version` text to standard output: 0, or 1 with a message
/// naming standard output when the write fails (a full disk, `> /dev/full`, a closed
/// descriptor); a closed pipe (`camsim --help | head -1`) ends quietly with 0.
fn print_clap_output(e: &clap::Error) -> u8 {
    use std::io::{IsTerminal, Write};
    let mut out = std::io::stdout().lock();
    // Styled on a terminal, as clap prints it; plain text into a file or a pipe.
    let text = match out.is_terminal() {
        true => e.render().ansi().to_string(),
        false => e.render().to_string(),
    };
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => 0,
        Err(e) => stdout_failure(&e),
    }
}

/// The exit status and message of a failed write to standard output: a closed pipe is
/// the reader's choice (0, nothing printed); anything else is an error (1).
fn stdout_failure(e: &std::io::Error) -> u8 {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        return 0;
    }
    report_error(&format!(
        "camsim: error: standard output: write failed: {}",
        one_line(&e.to_string())
    ));
    1
}

/// [`main_from`]'s work, on the worker thread.
fn main_on_worker(args: &[OsString]) -> u8 {
    let code = run_command_line(args);
    // Whatever is still buffered for standard output is written now, so that a failure
    // is reported (and the exit status says so) instead of being lost at exit.
    use std::io::Write;
    match std::io::stdout().lock().flush() {
        Ok(()) => code,
        Err(e) => stdout_failure(&e).max(code),
    }
}

/// Parses and runs one command line; the exit status.
fn run_command_line(args: &[OsString]) -> u8 {
    let cli = match parse_matches(args) {
        Ok((c, matches)) => match bare_number_refusal(&c, &matches) {
            Some(line) => {
                report_error(&format!(
                    "camsim: error: {} (see camsim --help)",
                    one_line(&line)
                ));
                return 2;
            }
            None => c,
        },
        Err(e) => {
            // --help and --version are not errors.
            if !e.use_stderr() {
                return print_clap_output(&e);
            }
            report_error(&format!(
                "camsim: error: {} (see camsim --help)",
                one_line(&usage_message(&e))
            ));
            return 2;
        }
    };
    match execute(cli) {
        Ok(()) => 0,
        Err(e) if is_broken_pipe(&e) => 0,
        Err(e) if crate::args::is_usage(&e) => {
            report_error(&format!(
                "camsim: error: {} (see camsim --help)",
                error_line(&e)
            ));
            2
        }
        Err(e) => {
            // One line, no backtrace.
            report_error(&format!("camsim: error: {}", error_line(&e)));
            1
        }
    }
}
