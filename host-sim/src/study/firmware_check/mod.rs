//! The checks of the firmware's decoded QEMU logs (the checks themselves are
//! [`crate::firmware_log`]'s): the memory budget of memory.x, each ELF's sections by
//! `llvm-size -A` ([`llvm_size`]), the demonstration image's and the budget probes' lines,
//! the boot failure. The study takes a [`Spec`] and returns a [`CheckReport`] (its text
//! in [`mod@report`]); `camsim firmware-check` (crate::cmd::firmware_check) builds the spec
//! from its arguments and prints the report.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result};

use crate::firmware_log::{
    check_boot_fault, check_budget, check_elf_fits, check_memory, check_product_log, check_profile,
    check_reactions, check_scene, last_memory_line, parse_budget, parse_llvm_size, parse_memory_x,
    ElfSizes, MemoryBudget,
};

pub mod llvm_size;
pub mod report;

pub use llvm_size::LLVM_SIZE_TIMEOUT_S;
pub use report::*;

/// A decoded log and the ELF that wrote it.
#[derive(Clone, Debug)]
pub struct LogAndElf {
    /// The decoded QEMU log.
    pub log: PathBuf,
    /// The ELF that ran.
    pub elf: PathBuf,
}

/// What the checks read and run.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The demonstration image's log and ELF (its `product` line, boot cost, reactions).
    pub product: Option<LogAndElf>,
    /// The budget probes' log and ELF (its `budget` line, the real-time factor).
    pub budget: Option<LogAndElf>,
    /// The boot-failure image's log.
    pub boot_fault: Option<PathBuf>,
    /// ELFs built but not run: flash and static RAM within memory.x.
    pub fits: Vec<PathBuf>,
    /// The build-time scene file's name the product and budget logs must report.
    pub scene: Option<String>,
    /// The build-time measured profile's name the product log must report.
    pub profile: Option<String>,
    /// The linker script holding the budget.
    pub memory_x: PathBuf,
    /// The `llvm-size` to run on the ELFs.
    pub llvm_size: String,
    /// How long one `llvm-size` run may take.
    pub llvm_size_timeout: Duration,
    /// Print each line to standard output as its check passes (the text output).
    pub print: bool,
}

/// A log or linker script, read through the firmware log's limit
/// ([`crate::cmd::predict::MAX_LOG_BYTES`], the same as `predict --check-log`).
fn read(path: &Path, what: &str) -> Result<String> {
    camsim_scene_file::read_text(path, crate::cmd::predict::MAX_LOG_BYTES, what)
        .map_err(anyhow::Error::msg)
}

/// `llvm-size -A` of `elf`, parsed.
fn elf_sizes(r: &mut CheckReport, spec: &Spec, elf: &Path) -> Result<ElfSizes> {
    let out = llvm_size::run_llvm_size(&spec.llvm_size, elf, spec.llvm_size_timeout)?;
    let sizes = parse_llvm_size(&out).with_context(|| elf.display().to_string())?;
    r.say(format!("  {}: {}", elf.display(), sizes.describe()?));
    r.images.push(ImageSizes {
        elf: elf.display().to_string(),
        flash_bytes: sizes.flash()?,
        ram_static_bytes: sizes.ram_static()?,
        vector_table_bytes: sizes.vector_table,
        text_bytes: sizes.text,
        rodata_bytes: sizes.rodata,
        data_bytes: sizes.data,
        bss_bytes: sizes.bss,
        uninit_bytes: sizes.uninit,
    });
    Ok(sizes)
}

/// The `cross-check ELF with llvm-size` line, the ELF's sizes and its memory line
/// `memory` checked against them and the budget.
fn cross_check(
    r: &mut CheckReport,
    spec: &Spec,
    elf: &Path,
    memory: &camsim_chip::MemoryFields,
    budget: &MemoryBudget,
) -> Result<()> {
    r.say(format!(
        "firmware-check: cross-check {} with {} -A",
        elf.display(),
        spec.llvm_size
    ));
    let sizes = elf_sizes(r, spec, elf)?;
    r.say(format!("  {}", check_memory(memory, &sizes, budget)?));
    Ok(())
}

fn product(
    r: &mut CheckReport,
    spec: &Spec,
    pair: &LogAndElf,
    budget: &MemoryBudget,
) -> Result<()> {
    let log = read(&pair.log, "the firmware log")?;
    let p = check_product_log(&log)?;
    cross_check(r, spec, &pair.elf, &p.memory, budget)?;
    r.say(format!(
        "firmware-check: fault reactions in {}",
        pair.log.display()
    ));
    for line in check_reactions(&log)? {
        r.say(format!("  {line}"));
    }
    if let Some(name) = &spec.scene {
        check_scene(&log, name)?;
    }
    if let Some(name) = &spec.profile {
        check_profile(&log, name)?;
    }
    r.say(format!("firmware-check: {p}"));
    r.product = Some(ProductNumbers {
        memory: memory_numbers(&p.memory),
        boot_instr: p.boot_instr,
        max_instr_per_reading: p.max_instr_per_reading,
    });
    Ok(())
}

fn budget_image(
    r: &mut CheckReport,
    spec: &Spec,
    pair: &LogAndElf,
    budget: &MemoryBudget,
) -> Result<()> {
    let log = read(&pair.log, "the firmware log")?;
    let line = last_memory_line(&log, "budget").context("no 'budget flash_bytes=..' line")?;
    let b = parse_budget(line)?;
    cross_check(r, spec, &pair.elf, &b.memory, budget)?;
    check_budget(&b)?;
    if let Some(name) = &spec.scene {
        check_scene(&log, name)?;
    }
    // The line as read (its realtime_factor as the log printed it).
    r.say(format!("firmware-check: {line}"));
    r.budget = Some(BudgetNumbers {
        memory: memory_numbers(&b.memory),
        instr_per_rhs: b.instr_per_rhs,
        instr_per_rev: b.instr_per_rev,
        realtime_factor: f64::from(b.realtime_factor),
    });
    Ok(())
}

/// Runs the checks the spec names (printing each line as it passes with `spec.print`);
/// the first failure is the error.
pub fn report(spec: &Spec) -> Result<CheckReport> {
    let budget = parse_memory_x(&read(&spec.memory_x, "the linker script")?)
        .map_err(|e| anyhow::anyhow!("--memory-x {}: {e}", spec.memory_x.display()))?;
    let mut report = CheckReport {
        camsim_version: env!("CARGO_PKG_VERSION"),
        memory_x: spec.memory_x.display().to_string(),
        flash_budget_bytes: budget.flash,
        ram_budget_bytes: budget.ram,
        print: spec.print,
        ..CheckReport::default()
    };
    let r = &mut report;
    r.say(format!(
        "firmware-check: budget from {}: flash {} B, RAM {} B",
        spec.memory_x.display(),
        budget.flash,
        budget.ram
    ));
    for elf in &spec.fits {
        let sizes = elf_sizes(r, spec, elf)?;
        check_elf_fits(&sizes, &budget).with_context(|| elf.display().to_string())?;
    }
    if let Some(p) = &spec.product {
        product(r, spec, p, &budget).with_context(|| p.log.display().to_string())?;
    }
    if let Some(p) = &spec.budget {
        budget_image(r, spec, p, &budget).with_context(|| p.log.display().to_string())?;
    }
    if let Some(log) = &spec.boot_fault {
        check_boot_fault(&read(log, "the firmware log")?)
            .with_context(|| log.display().to_string())?;
        r.say(
            "firmware-check: boot failure reported, alarm left asserted (LED0 low), stopped"
                .to_string(),
        );
    }
    if let Some(e) = report.write_error.take() {
        return Err(e).context("standard output: write failed");
    }
    Ok(report)
}
