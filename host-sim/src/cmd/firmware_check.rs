//! `camsim firmware-check`: the checks of the firmware's decoded QEMU logs that
//! scripts/firmware-ci.sh runs (the script only builds, runs QEMU, decodes and calls
//! this). The study is [`crate::study::firmware_check`] (the checks themselves are
//! [`crate::firmware_log`]'s); this command reads the arguments into its [`Spec`], runs
//! it and prints the report.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{bail, Result};
use clap::ArgGroup;

pub use crate::study::firmware_check::*;

/// Arguments of `camsim firmware-check`.
#[derive(clap::Args, Debug)]
#[command(group(ArgGroup::new("what").required(true).multiple(true).args(["product", "budget", "boot_fault", "fits"])))]
#[command(
    after_help = "Units: its lines are bytes, instructions, ratios and rpm, the same in either family: --units si changes nothing (and is accepted)."
)]
pub struct Args {
    /// The QEMU demonstration image's decoded log and its ELF: the `product` memory line
    /// against `llvm-size -A` and memory.x, the boot cost, the fault reactions.
    #[arg(long, num_args = 2, value_names = ["LOG", "ELF"])]
    pub product: Option<Vec<PathBuf>>,
    /// The budget probes' decoded log and ELF: the `budget` memory line, the instruction
    /// counts and the real-time factor recomputed from `instr_per_rev`.
    #[arg(long, num_args = 2, value_names = ["LOG", "ELF"])]
    pub budget: Option<Vec<PathBuf>>,
    /// The boot-failure image's decoded log: the error reported, the alarm left asserted.
    #[arg(long, value_name = "LOG")]
    pub boot_fault: Option<PathBuf>,
    /// An ELF built but not run (the real-board build): flash and static RAM within memory.x.
    #[arg(long, value_name = "ELF")]
    pub fits: Vec<PathBuf>,
    /// The build-time scene file's name the product and budget logs must report.
    #[arg(long, value_name = "NAME")]
    pub scene: Option<String>,
    /// The build-time measured profile's name the product log must report.
    #[arg(long, value_name = "NAME")]
    pub profile: Option<String>,
    /// The linker script holding the budget (LENGTH of FLASH and RAM).
    #[arg(long, value_name = "FILE", default_value = "memory.x")]
    pub memory_x: PathBuf,
    /// The `llvm-size` to run on the ELFs.
    #[arg(long, value_name = "TOOL", default_value = "llvm-size")]
    pub llvm_size: String,
    /// Seconds one `llvm-size` run may take before it is killed and the check fails
    /// (1 to 3600).
    #[arg(long, value_name = "SECONDS", default_value_t = LLVM_SIZE_TIMEOUT_S, value_parser = clap::value_parser!(u64).range(1..=3600))]
    pub llvm_size_timeout: u64,
    /// Print JSON (the budget and every check passed) instead of the lines, once all
    /// checks passed (a failure is the error line, as without --json).
    #[arg(long)]
    pub json: bool,
}

/// The (LOG, ELF) pair of `--product`/`--budget` (clap gives exactly two).
fn pair(v: &Option<Vec<PathBuf>>) -> Result<Option<LogAndElf>> {
    match v.as_deref() {
        None => Ok(None),
        Some([log, elf]) => Ok(Some(LogAndElf {
            log: log.clone(),
            elf: elf.clone(),
        })),
        Some(_) => bail!("expected LOG ELF"),
    }
}

/// The study's spec from the arguments.
pub fn spec(a: &Args) -> Result<Spec> {
    Ok(Spec {
        product: pair(&a.product)?,
        budget: pair(&a.budget)?,
        boot_fault: a.boot_fault.clone(),
        fits: a.fits.clone(),
        scene: a.scene.clone(),
        profile: a.profile.clone(),
        memory_x: a.memory_x.clone(),
        llvm_size: a.llvm_size.clone(),
        llvm_size_timeout: Duration::from_secs(a.llvm_size_timeout),
        print: !a.json,
    })
}

/// Runs the checks named by the arguments (printing each line as it passes, without
/// --json); the first failure is the error.
pub fn report(a: &Args) -> Result<CheckReport> {
    crate::study::firmware_check::report(&spec(a)?)
}

/// Runs the command: the checks, their lines as they pass (or with --json the report at
/// the end).
pub fn run(a: Args, units: crate::units::Units) -> Result<()> {
    let report = report(&a)?;
    if a.json {
        crate::report::print(&report, true, units)?;
    }
    Ok(())
}
