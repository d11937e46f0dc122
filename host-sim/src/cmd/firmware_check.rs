//! `camsim firmware-check`: the checks of the firmware's decoded QEMU logs that
//! scripts/firmware-ci.sh runs (the script only builds, runs QEMU, decodes and calls
//! this). The checks themselves are [`crate::firmware_log`]'s.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::ArgGroup;

use crate::firmware_log::{
    check_boot_fault, check_budget, check_elf_fits, check_memory, check_product_log, check_profile,
    check_reactions, check_scene, last_memory_line, parse_budget, parse_llvm_size, parse_memory_x,
    ElfSizes, MemoryBudget,
};

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

/// What `camsim firmware-check` reports: the budget and the checks, in order.
#[derive(Debug, Default, serde::Serialize)]
pub struct CheckReport {
    /// The version of camsim that checked.
    pub camsim_version: &'static str,
    /// The linker script read.
    pub memory_x: String,
    /// FLASH's LENGTH in it, bytes.
    pub flash_budget_bytes: u64,
    /// RAM's LENGTH in it, bytes.
    pub ram_budget_bytes: u64,
    /// Every ELF read with `llvm-size -A`, with its loaded sections, in the order checked.
    pub images: Vec<ImageSizes>,
    /// The demonstration image's `product` line, when `--product` was checked.
    pub product: Option<ProductNumbers>,
    /// The budget probes' `budget` line, when `--budget` was checked.
    pub budget: Option<BudgetNumbers>,
    /// Every line the checks print, in order (each a check passed, or what it measured).
    pub checks: Vec<String>,
    /// Whether to print each line as it comes (the text output).
    #[serde(skip)]
    print: bool,
    /// The first failed write of a line to standard output (reported at the end).
    #[serde(skip)]
    write_error: Option<std::io::Error>,
}

/// One ELF's loaded sections (`llvm-size -A`), bytes.
#[derive(Debug, serde::Serialize)]
pub struct ImageSizes {
    /// The ELF.
    pub elf: String,
    /// `.vector_table + .text + .rodata + .data`.
    pub flash_bytes: u64,
    /// `.data + .bss + .uninit`.
    pub ram_static_bytes: u64,
    /// `.vector_table`.
    pub vector_table_bytes: u64,
    /// `.text`.
    pub text_bytes: u64,
    /// `.rodata`.
    pub rodata_bytes: u64,
    /// `.data`.
    pub data_bytes: u64,
    /// `.bss`.
    pub bss_bytes: u64,
    /// `.uninit`.
    pub uninit_bytes: u64,
}

/// The numbers of the image's own memory report (its log line's fields).
#[derive(Debug, serde::Serialize)]
pub struct MemoryNumbers {
    /// Flash the image reports, bytes.
    pub flash_bytes: u64,
    /// Static RAM the image reports, bytes.
    pub ram_static_bytes: u64,
    /// Peak stack measured by the stack paint, bytes.
    pub stack_peak_bytes: u64,
    /// Static RAM plus peak stack, bytes.
    pub ram_bytes: u64,
}

/// The demonstration image's `product` line.
#[derive(Debug, serde::Serialize)]
pub struct ProductNumbers {
    /// Its memory report.
    pub memory: MemoryNumbers,
    /// Instructions from reset to the first prediction.
    pub boot_instr: u64,
    /// Most instructions one speed reading cost.
    pub max_instr_per_reading: u64,
}

/// The budget probes' `budget` line.
#[derive(Debug, serde::Serialize)]
pub struct BudgetNumbers {
    /// Its memory report.
    pub memory: MemoryNumbers,
    /// Instructions per right-hand-side evaluation of the chip's model.
    pub instr_per_rhs: u64,
    /// Instructions per simulated revolution at the chip's nominal speed.
    pub instr_per_rev: u64,
    /// Simulated time over instructions at the chip's clock, as the log printed it.
    pub realtime_factor: f64,
}

fn memory_numbers(m: &camsim_chip::MemoryFields) -> MemoryNumbers {
    MemoryNumbers {
        flash_bytes: m.flash_bytes.into(),
        ram_static_bytes: m.ram_static_bytes.into(),
        stack_peak_bytes: m.stack_peak_bytes.into(),
        ram_bytes: m.ram_bytes.into(),
    }
}

impl CheckReport {
    /// Records a line (and prints it at once without --json).
    fn say(&mut self, line: String) {
        if self.print && self.write_error.is_none() {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            let written = writeln!(out, "{line}").and_then(|()| out.flush());
            self.write_error = written.err();
        }
        self.checks.push(line);
    }
}

/// Default of `--llvm-size-timeout`: 60 s. `llvm-size -A` of a firmware ELF (about 1 MB)
/// takes milliseconds; a minute leaves room for a loaded CI machine and still ends a tool
/// that never answers (a wrong `--llvm-size`, a FIFO given as the ELF) instead of hanging
/// camsim and the firmware CI with it.
pub const LLVM_SIZE_TIMEOUT_S: u64 = 60;

/// Most bytes of `llvm-size`'s standard error kept for a failure's message.
const MAX_STDERR_BYTES: u64 = 64 * 1024;

/// A log or linker script, read through the firmware log's limit
/// ([`crate::cmd::predict::MAX_LOG_BYTES`], the same as `predict --check-log`).
fn read(path: &Path, what: &str) -> Result<String> {
    camsim_scene_file::read_text(path, crate::cmd::predict::MAX_LOG_BYTES, what)
        .map_err(anyhow::Error::msg)
}

/// A child's output read on a thread: at most `max` bytes, and whether there was more
/// (`over`, set as soon as the limit is passed).
struct CappedRead {
    thread: std::thread::JoinHandle<Vec<u8>>,
    over: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

/// Starts reading at most `max` bytes of `from` on a thread.
fn capped_reader(from: Option<impl std::io::Read + Send + 'static>, max: u64) -> CappedRead {
    let over = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = over.clone();
    let thread = std::thread::spawn(move || {
        use std::io::Read;
        let mut bytes = Vec::new();
        if let Some(from) = from {
            let _ = from.take(max.saturating_add(1)).read_to_end(&mut bytes);
        }
        if bytes.len() as u64 > max {
            flag.store(true, std::sync::atomic::Ordering::SeqCst);
            bytes.truncate(usize::try_from(max).unwrap_or(usize::MAX));
        }
        bytes
    });
    CappedRead { thread, over }
}

impl CappedRead {
    fn over(&self) -> bool {
        self.over.load(std::sync::atomic::Ordering::SeqCst)
    }

    /// The bytes read and whether there was more, once the thread ends, waiting until
    /// `deadline` at most (a child's child may hold the pipe open after the child exits).
    fn join_by(self, deadline: Instant) -> Option<(Vec<u8>, bool)> {
        while !self.thread.is_finished() {
            if Instant::now() >= deadline {
                return None;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let bytes = self.thread.join().ok()?;
        Some((bytes, self.over.load(std::sync::atomic::Ordering::SeqCst)))
    }
}

/// Runs `tool -A elf` within `timeout`, its standard output read through the log limit;
/// its output, or why not (cannot run, over the limit, no answer in time: killed, failed
/// with its exit status and standard error).
fn run_llvm_size(tool: &str, elf: &Path, timeout: Duration) -> Result<String> {
    let what = format!("--llvm-size {tool} -A {}", elf.display());
    let mut child = Command::new(tool)
        .arg("-A")
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .with_context(|| format!("--llvm-size {tool}: cannot run it"))?;
    let max = crate::cmd::predict::MAX_LOG_BYTES;
    let out = capped_reader(child.stdout.take(), max);
    let err = capped_reader(child.stderr.take(), MAX_STDERR_BYTES);
    let deadline = Instant::now() + timeout;
    let status = loop {
        if let Some(status) = child.try_wait()? {
            break status;
        }
        let over = out.over();
        if over || Instant::now() >= deadline {
            let _ = child.kill();
            let _ = child.wait();
            if over {
                bail!("{what}: its output is larger than the limit of {max} bytes (killed, read no further)");
            }
            bail!(
                "{what}: no answer in {} s (--llvm-size-timeout): killed",
                timeout.as_secs()
            );
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let (stdout, over) = out.join_by(deadline).unwrap_or_default();
    // Over the limit first: the child may have died of the pipe closed at the limit.
    if over {
        bail!("{what}: its output is larger than the limit of {max} bytes (read no further)");
    }
    if !status.success() {
        let (stderr, _) = err.join_by(deadline).unwrap_or_default();
        let stderr = String::from_utf8_lossy(&stderr);
        let said = match stderr.trim() {
            "" => "nothing on standard error".to_string(),
            s => s.lines().next().unwrap_or(s).chars().take(200).collect(),
        };
        bail!("{what}: it failed ({status}): {said}");
    }
    Ok(String::from_utf8_lossy(&stdout).into_owned())
}

/// `llvm-size -A` of `elf`, parsed.
fn elf_sizes(r: &mut CheckReport, a: &Args, elf: &Path) -> Result<ElfSizes> {
    let timeout = Duration::from_secs(a.llvm_size_timeout);
    let out = run_llvm_size(&a.llvm_size, elf, timeout)?;
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

/// The (LOG, ELF) pair of `--product`/`--budget` (clap gives exactly two).
fn pair(v: &[PathBuf]) -> Result<(&Path, &Path)> {
    match v {
        [log, elf] => Ok((log, elf)),
        _ => bail!("expected LOG ELF"),
    }
}

fn product(
    r: &mut CheckReport,
    a: &Args,
    log_path: &Path,
    elf: &Path,
    budget: &MemoryBudget,
) -> Result<()> {
    let log = read(log_path, "the firmware log")?;
    let p = check_product_log(&log)?;
    r.say(format!(
        "firmware-check: cross-check {} with {} -A",
        elf.display(),
        a.llvm_size
    ));
    let sizes = elf_sizes(r, a, elf)?;
    r.say(format!("  {}", check_memory(&p.memory, &sizes, budget)?));
    r.say(format!(
        "firmware-check: fault reactions in {}",
        log_path.display()
    ));
    for line in check_reactions(&log)? {
        r.say(format!("  {line}"));
    }
    if let Some(name) = &a.scene {
        check_scene(&log, name)?;
    }
    if let Some(name) = &a.profile {
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
    a: &Args,
    log_path: &Path,
    elf: &Path,
    budget: &MemoryBudget,
) -> Result<()> {
    let log = read(log_path, "the firmware log")?;
    let line = last_memory_line(&log, "budget").context("no 'budget flash_bytes=..' line")?;
    let b = parse_budget(line)?;
    r.say(format!(
        "firmware-check: cross-check {} with {} -A",
        elf.display(),
        a.llvm_size
    ));
    let sizes = elf_sizes(r, a, elf)?;
    r.say(format!("  {}", check_memory(&b.memory, &sizes, budget)?));
    check_budget(&b)?;
    if let Some(name) = &a.scene {
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

/// Runs the command: the checks, their lines as they pass (or with --json the report at
/// the end).
pub fn run(a: Args, units: crate::units::Units) -> Result<()> {
    let report = report(&a)?;
    if a.json {
        crate::report::print(&report, true, units)?;
    }
    Ok(())
}

/// Runs the checks named by the arguments (printing each line as it passes, without
/// --json); the first failure is the error.
pub fn report(a: &Args) -> Result<CheckReport> {
    let budget = parse_memory_x(&read(&a.memory_x, "the linker script")?)
        .map_err(|e| anyhow::anyhow!("--memory-x {}: {e}", a.memory_x.display()))?;
    let mut report = CheckReport {
        camsim_version: env!("CARGO_PKG_VERSION"),
        memory_x: a.memory_x.display().to_string(),
        flash_budget_bytes: budget.flash,
        ram_budget_bytes: budget.ram,
        images: Vec::new(),
        product: None,
        budget: None,
        checks: Vec::new(),
        print: !a.json,
        write_error: None,
    };
    let r = &mut report;
    r.say(format!(
        "firmware-check: budget from {}: flash {} B, RAM {} B",
        a.memory_x.display(),
        budget.flash,
        budget.ram
    ));
    for elf in &a.fits {
        let sizes = elf_sizes(r, a, elf)?;
        check_elf_fits(&sizes, &budget).with_context(|| elf.display().to_string())?;
    }
    if let Some(v) = &a.product {
        let (log, elf) = pair(v)?;
        product(r, a, log, elf, &budget).with_context(|| log.display().to_string())?;
    }
    if let Some(v) = &a.budget {
        let (log, elf) = pair(v)?;
        budget_image(r, a, log, elf, &budget).with_context(|| log.display().to_string())?;
    }
    if let Some(log) = &a.boot_fault {
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

impl crate::report::Report for CheckReport {
    fn text(&self, _units: crate::units::Units) -> String {
        self.checks.iter().map(|l| format!("{l}\n")).collect()
    }
}
