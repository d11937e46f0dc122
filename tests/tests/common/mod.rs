//! Helpers shared by several integration tests (`mod common;` in each).
// Each test crate uses some of them.
#![allow(dead_code)]

/// Least-squares slope of log(y) against log(x) (a convergence order, a growth rate).
pub fn loglog_slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// A fresh empty directory for one test, named after the test crate, the process and
/// `name`.
pub fn scratch(name: &str) -> std::path::PathBuf {
    let krate = module_path!().split("::").next().unwrap_or("tests");
    let d = std::env::temp_dir().join(format!("camsim-{krate}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every name in `dir`, sorted.
pub fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The cheapest Monte Carlo study the tests run: the vertical scene at constant cam
/// speed (10 states), a coarse profile (no jumps, so the runs are short).
pub const CHEAP: [&str; 6] = [
    "--vertical",
    "--constant-cam-speed",
    "--interval-deg",
    "10",
    "--seed",
    "7",
];

/// Parses and runs a command line as the binary does (through `camsim::cli`): the
/// refusal's one line (as the binary prints it after `camsim: error: `), `usage: ...` for
/// one the parser refuses, or "OK".
pub fn outcome(args: &[&str]) -> String {
    use camsim::cli;
    let argv = std::iter::once("camsim").chain(args.iter().copied());
    match cli::parse_from(argv) {
        Err(e) => format!("usage: {}", cli::usage_message(&e)),
        Ok(c) => match cli::execute(c) {
            Ok(()) => "OK".into(),
            Err(e) => cli::error_line(&e),
        },
    }
}

/// A path as a command-line argument (the tests' scratch paths are UTF-8).
pub fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}
