//! What `camsim firmware-check` reports ([`CheckReport`]): the budget, each image's
//! sections, the logs' numbers and every check's line; its text is those lines.

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
    pub(super) print: bool,
    /// The first failed write of a line to standard output (reported at the end).
    #[serde(skip)]
    pub(super) write_error: Option<std::io::Error>,
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

pub(super) fn memory_numbers(m: &camsim_chip::MemoryFields) -> MemoryNumbers {
    MemoryNumbers {
        flash_bytes: m.flash_bytes.into(),
        ram_static_bytes: m.ram_static_bytes.into(),
        stack_peak_bytes: m.stack_peak_bytes.into(),
        ram_bytes: m.ram_bytes.into(),
    }
}

impl CheckReport {
    /// Records a line (and prints it at once without --json).
    pub(super) fn say(&mut self, line: String) {
        if self.print && self.write_error.is_none() {
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            let written = writeln!(out, "{line}").and_then(|()| out.flush());
            self.write_error = written.err();
        }
        self.checks.push(line);
    }
}

impl crate::report::Report for CheckReport {
    fn text(&self, _units: crate::units::Units) -> String {
        self.checks.iter().map(|l| format!("{l}\n")).collect()
    }
}
