//! `camsim`: the command line of the camsim harness ([`camsim::cli`]).

fn main() -> std::process::ExitCode {
    camsim::cli::main()
}
