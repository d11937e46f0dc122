//! The firmware's decoded defmt logs read back and checked (`camsim firmware-check`, run
//! by scripts/firmware-ci.sh): the memory lines against `llvm-size -A` of the image and
//! the budget in memory.x, the real-time factor recomputed from the instruction count,
//! the reactions to the scripted machine's faults, and the boot-failure path. The lines'
//! formats are `camsim_chip`'s types ([`ProductLine`], [`BudgetLine`], [`ReactionLine`]),
//! the ones the firmware logs with defmt; this module only parses them.

use std::str::FromStr;

use anyhow::{bail, Context, Result};

use camsim_chip::{
    BudgetLine, MemoryFields, ProductLine, ReactionLine, CHIP_CLOCK_HZ, CHIP_NOMINAL_RPM,
};

/// The QEMU demonstration image's alarm pin (firmware/src/board/qemu.rs `ALARM_PIN`).
pub const QEMU_ALARM_PIN: &str = "LED0";

/// The faults of the scripted machine (`camsim_chip::CHIP_SCRIPT`) by their reading's
/// kind, each with the warning the firmware logs for it (`#`: one or more digits).
pub const SCRIPT_FAULTS: [(&str, &str); 5] = [
    ("lost", "speed lost: no index pulse for # ticks"),
    (
        "too_short",
        "pulse rejected: # ticks since the last, faster than # rpm",
    ),
    (
        "bounce",
        "pulse rejected: # ticks, under # % of the last period (bounce)",
    ),
    (
        "step",
        "period rejected: # ticks, more than # % off the last",
    ),
    (
        "out_of_range",
        "outside the table's #..# rpm: flagged, not extrapolated",
    ),
];

/// The value of `key=` in `line` (up to the next space), if any.
pub fn field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    line.split_whitespace()
        .find_map(|tok| tok.strip_prefix(key)?.strip_prefix('='))
}

/// `key=` of `line` parsed as a number; the error names the key and the line.
fn num<T: FromStr>(line: &str, key: &str) -> Result<T> {
    let v = field(line, key).with_context(|| format!("no {key}= in: {line}"))?;
    v.parse()
        .ok()
        .with_context(|| format!("{key}={v} is not a number, in: {line}"))
}

/// The last line of `log` with a `<what> flash_bytes=` memory line, from `what` on.
pub fn last_memory_line<'a>(log: &'a str, what: &str) -> Option<&'a str> {
    let tag = format!("{what} flash_bytes=");
    log.lines()
        .filter_map(|l| l.find(&tag).map(|i| l[i..].trim_end()))
        .next_back()
}

fn memory_fields(line: &str) -> Result<MemoryFields> {
    Ok(MemoryFields {
        flash_bytes: num(line, "flash_bytes")?,
        ram_static_bytes: num(line, "ram_static_bytes")?,
        stack_peak_bytes: num(line, "stack_peak_bytes")?,
        ram_bytes: num(line, "ram_bytes")?,
    })
}

/// Parses a `product ...` line (the text of [`ProductLine`]).
pub fn parse_product(line: &str) -> Result<ProductLine> {
    Ok(ProductLine {
        memory: memory_fields(line)?,
        boot_instr: num(line, "boot_instr")?,
        max_instr_per_reading: num(line, "max_instr_per_reading")?,
    })
}

/// Parses a `budget ...` line (the text of [`BudgetLine`]).
pub fn parse_budget(line: &str) -> Result<BudgetLine> {
    Ok(BudgetLine {
        memory: memory_fields(line)?,
        instr_per_rhs: num(line, "instr_per_rhs")?,
        instr_per_rev: num(line, "instr_per_rev")?,
        realtime_factor: num(line, "realtime_factor")?,
    })
}

/// The memory budget: LENGTH of FLASH and RAM in memory.x, bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget {
    /// FLASH's LENGTH.
    pub flash: u64,
    /// RAM's LENGTH.
    pub ram: u64,
}

/// The budget's region `name` (`FLASH`, `RAM`) by the one linker-script parser the
/// firmware's build uses too ([`camsim_chip::memory_map`]: comments, hex, K/M, checked).
fn region_length(text: &str, name: &str) -> Result<u64> {
    camsim_chip::memory_map::region(text, name)
        .map(|r| r.length)
        .map_err(|e| anyhow::anyhow!("{e}"))
}

/// Parses memory.x's FLASH and RAM lengths.
pub fn parse_memory_x(text: &str) -> Result<MemoryBudget> {
    Ok(MemoryBudget {
        flash: region_length(text, "FLASH")?,
        ram: region_length(text, "RAM")?,
    })
}

/// The sections of an ELF that take flash or RAM, from `llvm-size -A`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ElfSizes {
    /// `.vector_table`.
    pub vector_table: u64,
    /// `.text`.
    pub text: u64,
    /// `.rodata`.
    pub rodata: u64,
    /// `.data`.
    pub data: u64,
    /// `.bss`.
    pub bss: u64,
    /// `.uninit`.
    pub uninit: u64,
}

impl ElfSizes {
    /// Flash, as the firmware counts it (firmware/src/memory.rs): the load image. A sum
    /// past 64 bits is an error, never a wrap.
    pub fn flash(&self) -> Result<u64> {
        checked_sum(
            "flash (.vector_table + .text + .rodata + .data)",
            &[self.vector_table, self.text, self.rodata, self.data],
        )
    }

    /// Static RAM, as the firmware counts it (checked as [`ElfSizes::flash`]).
    pub fn ram_static(&self) -> Result<u64> {
        checked_sum(
            "static RAM (.data + .bss + .uninit)",
            &[self.data, self.bss, self.uninit],
        )
    }

    /// The sums, section by section.
    pub fn describe(&self) -> Result<String> {
        Ok(format!(
            "flash = .vector_table {} + .text {} + .rodata {} + .data {} = {}; static RAM = .data {} + .bss {} + .uninit {} = {}",
            self.vector_table, self.text, self.rodata, self.data, self.flash()?,
            self.data, self.bss, self.uninit, self.ram_static()?
        ))
    }

    /// The known section `name`'s field, if it is one.
    fn field_mut(&mut self, name: &str) -> Option<&mut u64> {
        Some(match name {
            ".vector_table" => &mut self.vector_table,
            ".text" => &mut self.text,
            ".rodata" => &mut self.rodata,
            ".data" => &mut self.data,
            ".bss" => &mut self.bss,
            ".uninit" => &mut self.uninit,
            _ => return None,
        })
    }
}

/// The sections firmware-check counts; `llvm-size -A` of a cortex-m-rt image lists each
/// exactly once (an empty one with size 0).
const KNOWN_SECTIONS: [&str; 6] = [
    ".vector_table",
    ".text",
    ".rodata",
    ".data",
    ".bss",
    ".uninit",
];

/// `what` as the sum of `parts`, or an error naming it when the sum passes 64 bits.
fn checked_sum(what: &str, parts: &[u64]) -> Result<u64> {
    parts
        .iter()
        .try_fold(0u64, |sum, p| sum.checked_add(*p))
        .with_context(|| format!("{what}: the sections' sizes add up past 2^64 - 1 bytes"))
}

/// Sections that take neither flash nor RAM (debug info, defmt's table, symbols).
fn section_is_not_loaded(name: &str) -> bool {
    name.starts_with(".debug_")
        || matches!(
            name,
            ".defmt" | ".comment" | ".ARM.attributes" | ".symtab" | ".strtab" | ".shstrtab"
        )
}

/// At most this many characters of an input line are quoted in an error.
const QUOTE_CHARS: usize = 80;

/// `line` quoted in an error, cut after [`QUOTE_CHARS`] characters.
fn quote(line: &str) -> String {
    let mut q: String = line.trim().chars().take(QUOTE_CHARS).collect();
    if line.trim().chars().nth(QUOTE_CHARS).is_some() {
        q.push('…');
    }
    format!("`{q}`")
}

/// A column of `llvm-size -A` (a decimal number of bytes), or an error naming the line.
fn decimal(v: &str, what: &str, n: usize, line: &str) -> Result<u64> {
    if !v.bytes().all(|b| b.is_ascii_digit()) {
        bail!("llvm-size line {n} {}: its {what} `{v}` is not a decimal number (llvm-size -A prints bytes in decimal)", quote(line));
    }
    v.parse().ok().with_context(|| {
        format!(
            "llvm-size line {n} {}: its {what} `{v}` is past 2^64 - 1",
            quote(line)
        )
    })
}

/// Parses `llvm-size -A` output: the `FILE  :` heading, the `section size addr` header,
/// one `SECTION SIZE ADDR` line per section in decimal, and `Total SIZE`, the sum of
/// them all. Refused, naming the line: any other line, a size that is not decimal, a
/// section listed twice, a known section missing, a total that is not the sum (checked,
/// never wrapped). Any other non-empty section would take flash or RAM the firmware does
/// not count: an error naming it.
pub fn parse_llvm_size(text: &str) -> Result<ElfSizes> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    let heading = lines.next().map_or("", |(_, l)| l);
    if !heading.trim_end().ends_with(':') {
        bail!(
            "llvm-size line 1 {}: not `llvm-size -A`'s `FILE  :` heading",
            quote(heading)
        );
    }
    let header = lines.next().map_or("", |(_, l)| l);
    if header.split_whitespace().ne(["section", "size", "addr"]) {
        bail!(
            "llvm-size line 2 {}: not `llvm-size -A`'s `section size addr` header",
            quote(header)
        );
    }
    let mut s = ElfSizes::default();
    let mut seen = [None::<usize>; KNOWN_SECTIONS.len()];
    let (mut sum, mut total) = (0u64, None);
    let mut unexpected = Vec::new();
    for (n, line) in lines {
        let cols: Vec<&str> = line.split_whitespace().collect();
        let (name, size) = match cols[..] {
            [] => continue,
            ["Total", t] if total.is_none() => {
                total = Some((decimal(t, "total", n, line)?, n));
                continue;
            }
            [name, size, addr] if total.is_none() => {
                decimal(addr, "address", n, line)?;
                (name, decimal(size, "size", n, line)?)
            }
            _ => bail!(
                "llvm-size line {n} {}: not a `SECTION SIZE ADDR` line before one `Total SIZE`",
                quote(line)
            ),
        };
        sum = sum.checked_add(size).with_context(|| {
            format!(
                "llvm-size line {n} {}: the sizes add up past 2^64 - 1 bytes",
                quote(line)
            )
        })?;
        if let Some(i) = KNOWN_SECTIONS.iter().position(|k| *k == name) {
            if let Some(first) = seen[i].replace(n) {
                bail!(
                    "llvm-size line {n} {}: section {name} is listed twice (first on line {first})",
                    quote(line)
                );
            }
        }
        match s.field_mut(name) {
            Some(field) => *field = size,
            None if size > 0 && !section_is_not_loaded(name) => unexpected.push(name.to_string()),
            None => {}
        }
    }
    check_sections(&seen, total, sum, &unexpected)?;
    s.flash()?;
    s.ram_static()?;
    Ok(s)
}

/// The end of [`parse_llvm_size`]: every known section seen, the total the sum, no
/// unexpected loaded section.
fn check_sections(
    seen: &[Option<usize>; KNOWN_SECTIONS.len()],
    total: Option<(u64, usize)>,
    sum: u64,
    unexpected: &[String],
) -> Result<()> {
    if let Some((name, _)) = KNOWN_SECTIONS.iter().zip(seen).find(|(_, s)| s.is_none()) {
        bail!("llvm-size lists no {name} section (a cortex-m-rt image has each of {}, an empty one as 0)", KNOWN_SECTIONS.join(" "));
    }
    let Some((total, n)) = total else {
        bail!("llvm-size output has no `Total SIZE` line (cut short?)");
    };
    if total != sum {
        bail!("llvm-size line {n}: Total {total} is not the sum of the sections listed, {sum} (output garbled?)");
    }
    if !unexpected.is_empty() {
        bail!(
            "unexpected non-empty sections (count them in firmware/src/memory.rs and in host-sim/src/firmware_log.rs): {}",
            unexpected.join(" ")
        );
    }
    Ok(())
}

/// Checks an image's memory line against its ELF's sections and the budget; returns the
/// summary (`flash .. B of .. (.. %), RAM .. B of .. (.. %)`).
pub fn check_memory(m: &MemoryFields, elf: &ElfSizes, budget: &MemoryBudget) -> Result<String> {
    let (flash, ram_static, stack, ram) = (
        u64::from(m.flash_bytes),
        u64::from(m.ram_static_bytes),
        u64::from(m.stack_peak_bytes),
        u64::from(m.ram_bytes),
    );
    // The fields are u32, so their sum in u64 cannot wrap.
    if ram != ram_static + stack {
        bail!("ram_bytes {ram} != ram_static_bytes {ram_static} + stack_peak_bytes {stack}");
    }
    if stack == 0 {
        bail!("stack_peak_bytes is 0 (stack paint not working)");
    }
    let (elf_flash, elf_ram) = (elf.flash()?, elf.ram_static()?);
    if elf_flash != flash {
        bail!("flash: llvm-size {elf_flash} != firmware {flash}");
    }
    if elf_ram != ram_static {
        bail!("static RAM: llvm-size {elf_ram} != firmware {ram_static}");
    }
    check_fits(flash, ram, budget)?;
    Ok(format!(
        "flash {flash} B of {} ({} %), RAM {ram} B of {} ({} %)",
        budget.flash,
        flash * 100 / budget.flash.max(1),
        budget.ram,
        ram * 100 / budget.ram.max(1)
    ))
}

/// Flash within FLASH and RAM within RAM of memory.x.
fn check_fits(flash: u64, ram: u64, budget: &MemoryBudget) -> Result<()> {
    if flash > budget.flash {
        bail!("flash {flash} B > budget {} B (memory.x)", budget.flash);
    }
    if ram > budget.ram {
        bail!("RAM {ram} B > budget {} B (memory.x)", budget.ram);
    }
    Ok(())
}

/// An image that is built but not run (the real-board build): its flash within FLASH
/// and its static RAM below RAM (the stack needs some).
pub fn check_elf_fits(elf: &ElfSizes, budget: &MemoryBudget) -> Result<()> {
    let ram_static = elf.ram_static()?;
    check_fits(elf.flash()?, ram_static, budget)?;
    if ram_static >= budget.ram {
        bail!(
            "static RAM {} B leaves no stack in {} B (memory.x)",
            ram_static,
            budget.ram
        );
    }
    Ok(())
}

/// The real-time factor a budget line should carry for its `instr_per_rev`
/// ([`camsim_chip::realtime_factor`], in f64).
pub fn expected_realtime_factor(instr_per_rev: u64) -> f64 {
    (CHIP_CLOCK_HZ * 60 / CHIP_NOMINAL_RPM) as f64 / instr_per_rev.max(1) as f64
}

/// The budget line's instruction counts are non-zero and its real-time factor is
/// recomputed from `instr_per_rev` (to 1e-3, the f32 and its printed digits).
pub fn check_budget(b: &BudgetLine) -> Result<()> {
    if b.instr_per_rhs == 0 || b.instr_per_rev == 0 {
        bail!("instruction counts are 0 (SysTick calibration not working)");
    }
    let e = expected_realtime_factor(b.instr_per_rev);
    let f = f64::from(b.realtime_factor);
    if !(f > 0.0 && (f - e).abs() < 1e-3 * e) {
        bail!(
            "realtime_factor {f} does not match instr_per_rev {}: {CHIP_CLOCK_HZ} Hz x 60 / {CHIP_NOMINAL_RPM} rpm / instr_per_rev = {e}",
            b.instr_per_rev
        );
    }
    Ok(())
}

/// The product log: its last `product` line, with a non-zero boot cost, and no budget
/// line (the probes belong to the budget image).
pub fn check_product_log(log: &str) -> Result<ProductLine> {
    let line = last_memory_line(log, "product").context("no 'product flash_bytes=..' line")?;
    let p = parse_product(line)?;
    if p.boot_instr == 0 {
        bail!("boot_instr is 0 (SysTick calibration not working)");
    }
    if last_memory_line(log, "budget").is_some() {
        bail!("the product log has a budget line (the probes belong to the budget binary)");
    }
    Ok(p)
}

/// Whether `text` holds `pattern`, where `#` in the pattern stands for one or more ASCII
/// digits and every other character for itself.
pub fn contains_pattern(text: &str, pattern: &str) -> bool {
    fn at(t: &[u8], p: &[u8]) -> bool {
        match p.split_first() {
            None => true,
            Some((b'#', rest)) => {
                let n = t.iter().take_while(|c| c.is_ascii_digit()).count();
                n > 0 && at(&t[n..], rest)
            }
            Some((c, rest)) => t.first() == Some(c) && at(&t[1..], rest),
        }
    }
    let (t, p) = (text.as_bytes(), pattern.as_bytes());
    (0..=t.len()).any(|i| at(&t[i..], p))
}

/// The reactions to the scripted machine's faults ([`SCRIPT_FAULTS`]): each fault has its
/// warning and at least one reaction with the alarm asserted and the pin read back low;
/// no reaction leaves the alarm released or the pin high; the alarm is asserted (pin
/// low) when the script ends. Returns one summary line per fault.
pub fn check_reactions(log: &str) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for (kind, warning) in SCRIPT_FAULTS {
        let want = ReactionLine {
            kind,
            asserted: true,
            pin: QEMU_ALARM_PIN,
            low: true,
        }
        .to_string();
        let n = log.lines().filter(|l| l.contains(&want)).count();
        if n == 0 {
            bail!("no '{want}' line (the script's {kind} fault)");
        }
        if !log.lines().any(|l| contains_pattern(l, warning)) {
            bail!("no warning matching '{warning}' (the script's {kind} fault)");
        }
        out.push(format!(
            "fault {kind:<12} {n} reading(s), each: alarm asserted, {QEMU_ALARM_PIN} read back low"
        ));
    }
    let safe = ReactionLine {
        kind: "",
        asserted: true,
        pin: QEMU_ALARM_PIN,
        low: true,
    };
    let tail = format!(
        " alarm={} pin={} level={}",
        safe.alarm_word(),
        safe.pin,
        safe.level_word()
    );
    if let Some(bad) = log
        .lines()
        .find(|l| l.contains("reaction kind=") && !l.trim_end().ends_with(&tail))
    {
        bail!("a reading that does not vouch for the speed left the alarm released or {QEMU_ALARM_PIN} high: {}", bad.trim());
    }
    let end = format!("alarm_at_end=asserted ({QEMU_ALARM_PIN} low)");
    if !log
        .lines()
        .any(|l| l.contains("predictor readings=") && l.contains(&end))
    {
        bail!("the alarm is not asserted ({QEMU_ALARM_PIN} low) when the pulses have stopped");
    }
    Ok(out)
}

/// The boot-failure image's log: the solver failure reported as an error, the alarm left
/// asserted with the pin read back low, and nothing after the failed boot.
pub fn check_boot_fault(log: &str) -> Result<()> {
    let error_with = |text: &str| log.lines().any(|l| l.contains("ERROR") && l.contains(text));
    if !error_with("boot: table build failed: step budget exceeded") {
        bail!("boot_fault: the solver failure is not reported");
    }
    if !error_with(&format!(
        "alarm asserted ({QEMU_ALARM_PIN} low: true), stopped: boot failed"
    )) {
        bail!("boot_fault: the alarm is not left asserted ({QEMU_ALARM_PIN} low) after the failed boot");
    }
    if log
        .lines()
        .any(|l| l.contains("table rpm=") || l.contains("predictor readings="))
    {
        bail!("boot_fault: it went on after the failed boot");
    }
    Ok(())
}

/// The log names the build-time scene (`scene=NAME`).
pub fn check_scene(log: &str, name: &str) -> Result<()> {
    let want = format!("scene={name}");
    if !log.lines().any(|l| l.split_whitespace().any(|t| t == want)) {
        bail!("the log does not report its scene (no '{want}')");
    }
    Ok(())
}

/// The product log names the build-time measured profile and a non-zero knot count
/// (`scene=reference profile=NAME profile_knots=N;`).
pub fn check_profile(log: &str, name: &str) -> Result<()> {
    let want = format!("scene=reference profile={name} profile_knots=");
    let ok = log.lines().any(|l| {
        l.find(&want).is_some_and(|i| {
            let rest = &l[i + want.len()..];
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            !digits.is_empty() && !digits.starts_with('0') && rest[digits.len()..].starts_with(';')
        })
    });
    if !ok {
        bail!("the log does not report its profile ({name}) and knots (no '{want}N;')");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const MEMORY_X: &str = "/* FLASH : LENGTH = 1K in a comment */\nMEMORY\n{\n  FLASH : ORIGIN = 0x00000000, LENGTH = 128K\n  RAM   : ORIGIN = 0x20000000, LENGTH = 32K\n}\n";

    const SIZES: &str = "predictor  :\nsection              size        addr\n.vector_table        1024           0\n.text               80000        1024\n.rodata              8900       81024\n.data                   0   536870912\n.bss                   24   536870912\n.uninit                 0   536870936\n.defmt                 12           0\n.debug_info         99999           0\n.comment              153           0\nTotal              190112\n";

    fn product_log(extra: &str) -> String {
        let mut log = String::from("0.000 INFO scene=reference profile=theoretical profile_knots=0; alarm asserted (LED0 low): booting\n");
        for (kind, _) in SCRIPT_FAULTS {
            log.push_str(&format!(
                "WARN  x\nINFO  reaction kind={kind} alarm=asserted pin=LED0 level=low\n"
            ));
        }
        log.push_str(
            "WARN  speed lost: no index pulse for 120000 ticks (a revolution at 250 rpm)\n",
        );
        log.push_str("WARN  pulse rejected: 20 ticks since the last, faster than 2400 rpm (noise or bounce)\n");
        log.push_str("WARN  pulse rejected: 9000 ticks, under 25 % of the last period (bounce)\n");
        log.push_str("WARN  period rejected: 150000 ticks, more than 25 % off the last (missed pulse or step)\n");
        log.push_str(
            "WARN  speed 1500 rpm outside the table's 500..1200 rpm: flagged, not extrapolated\n",
        );
        log.push_str(extra);
        log.push_str("INFO  predictor readings=40 counts=.. alarm_at_end=asserted (LED0 low)\n");
        log.push_str("INFO  product flash_bytes=89924 ram_static_bytes=24 stack_peak_bytes=7248 ram_bytes=7272 boot_instr=372791149 max_instr_per_reading=480\n");
        log
    }

    #[test]
    fn memory_x_lengths_in_bytes() {
        let b = parse_memory_x(MEMORY_X).unwrap();
        assert_eq!((b.flash, b.ram), (128 * 1024, 32 * 1024));
        assert!(parse_memory_x("MEMORY { RAM : LENGTH = 32K }").is_err());
        assert!(parse_memory_x("FLASH : LENGTH = 12Q\nRAM : LENGTH = 1").is_err());
    }

    #[test]
    fn llvm_size_sums_and_unexpected_sections() {
        let s = parse_llvm_size(SIZES).unwrap();
        assert_eq!(s.flash().unwrap(), 1024 + 80000 + 8900);
        assert_eq!(s.ram_static().unwrap(), 24);
        let bad = SIZES.replace(".comment ", ".ramfunc ");
        let e = parse_llvm_size(&bad).unwrap_err().to_string();
        assert!(e.contains(".ramfunc"), "{e}");
    }

    #[test]
    fn llvm_size_lines_refused_by_their_number() {
        let err = |text: &str| parse_llvm_size(text).unwrap_err().to_string();
        // A size in hex, a garbage size, a section twice (its total adjusted), a known
        // section renamed, a wrong total, a line of other columns: each names its line.
        let e = err(&SIZES.replace("80000", "0x13880"));
        assert!(
            e.contains("line 4") && e.contains("`0x13880` is not a decimal"),
            "{e}"
        );
        let e = err(&SIZES.replace("  8900 ", "  89e2 "));
        assert!(e.contains("line 5") && e.contains("89e2"), "{e}");
        let twice = SIZES.replace(".bss ", ".data").replace("190112", "190088");
        let e = err(&twice);
        assert!(
            e.contains("line 7") && e.contains(".data is listed twice (first on line 6)"),
            "{e}"
        );
        let e = err(&SIZES.replace(".uninit", ".uninot"));
        assert!(e.contains("no .uninit section"), "{e}");
        let e = err(&SIZES.replace("190112", "190111"));
        assert!(e.contains("line 12") && e.contains("not the sum"), "{e}");
        let e = err(&SIZES.replace(".defmt                 12", ".defmt 12 0 extra"));
        assert!(e.contains("line 9"), "{e}");
        let e = err("garbage\n");
        assert!(e.contains("line 1"), "{e}");
        // Sizes whose sum passes 2^64: refused, not wrapped.
        let big = u64::MAX - 1000;
        let e = err(&SIZES.replace("80000", &big.to_string()));
        assert!(e.contains("past 2^64 - 1"), "{e}");
        let s = ElfSizes {
            text: u64::MAX,
            rodata: 1,
            ..ElfSizes::default()
        };
        assert!(s.flash().unwrap_err().to_string().contains("flash"));
        assert_eq!(s.ram_static().unwrap(), 0);
    }

    #[test]
    fn memory_line_against_elf_and_budget() {
        let budget = parse_memory_x(MEMORY_X).unwrap();
        let elf = parse_llvm_size(SIZES).unwrap();
        let log = product_log("");
        let p = check_product_log(&log).unwrap();
        // The line is the type's own text.
        assert_eq!(p.to_string(), last_memory_line(&log, "product").unwrap());
        let s = check_memory(&p.memory, &elf, &budget).unwrap();
        assert!(s.starts_with("flash 89924 B of 131072 (68 %)"), "{s}");
        // One byte off llvm-size, a wrong RAM sum, a zero stack, over budget: each fails.
        let mut m = p.memory;
        m.flash_bytes += 1;
        assert!(check_memory(&m, &elf, &budget).is_err());
        let mut m = p.memory;
        m.ram_bytes += 1;
        assert!(check_memory(&m, &elf, &budget).is_err());
        let mut m = p.memory;
        m.ram_bytes -= m.stack_peak_bytes;
        m.stack_peak_bytes = 0;
        assert!(check_memory(&m, &elf, &budget).is_err());
        let small = MemoryBudget {
            flash: 89_923,
            ram: budget.ram,
        };
        assert!(check_memory(&p.memory, &elf, &small).is_err());
        let small = MemoryBudget {
            flash: budget.flash,
            ram: 7_271,
        };
        assert!(check_memory(&p.memory, &elf, &small).is_err());
        assert!(check_elf_fits(&elf, &budget).is_ok());
        let tiny = MemoryBudget {
            flash: 1 << 20,
            ram: 24,
        };
        assert!(check_elf_fits(&elf, &tiny).is_err());
    }

    #[test]
    fn product_log_needs_its_line_a_boot_cost_and_no_budget_line() {
        assert!(check_product_log("INFO nothing\n").is_err());
        let log = product_log("").replace("boot_instr=372791149", "boot_instr=0");
        assert!(check_product_log(&log).is_err());
        let log = product_log("INFO budget flash_bytes=1 ram_static_bytes=0 stack_peak_bytes=1 ram_bytes=1 instr_per_rhs=1 instr_per_rev=1 realtime_factor=1\n");
        assert!(check_product_log(&log).is_err());
    }

    #[test]
    fn realtime_factor_recomputed_from_instr_per_rev() {
        // 168e6 * 60 / 800 = 12.6e6 cycles a revolution at 800 rpm.
        assert_eq!(expected_realtime_factor(12_600_000), 1.0);
        let mut b = BudgetLine {
            memory: MemoryFields::default(),
            instr_per_rhs: 1851,
            instr_per_rev: 10_789_077,
            realtime_factor: camsim_chip::realtime_factor(10_789_077),
        };
        // The line as printed and read back passes.
        let back = parse_budget(&b.to_string()).unwrap();
        assert_eq!(back, b);
        check_budget(&back).unwrap();
        assert!((f64::from(b.realtime_factor) - 12.6e6 / 10_789_077.0).abs() < 1e-6);
        b.realtime_factor *= 1.01;
        assert!(check_budget(&b).is_err());
        b.realtime_factor = camsim_chip::realtime_factor(10_789_077);
        b.instr_per_rhs = 0;
        assert!(check_budget(&b).is_err());
    }

    #[test]
    fn reactions_of_every_fault() {
        let lines = check_reactions(&product_log("")).unwrap();
        assert_eq!(lines.len(), SCRIPT_FAULTS.len());
        // A released alarm, a pin read back high, a fault without its reaction or its
        // warning, the alarm released at the end: each fails.
        let released = "INFO  reaction kind=lost alarm=released pin=LED0 level=high\n";
        assert!(check_reactions(&product_log(released)).is_err());
        let high = "INFO  reaction kind=step alarm=asserted pin=LED0 level=high\n";
        assert!(check_reactions(&product_log(high)).is_err());
        let no_bounce = product_log("").replace("reaction kind=bounce", "reaction kind=lost");
        assert!(check_reactions(&no_bounce).is_err());
        let no_warning = product_log("").replace("(bounce)\n", "\n");
        assert!(check_reactions(&no_warning).is_err());
        let released_at_end =
            product_log("").replace("alarm_at_end=asserted", "alarm_at_end=released");
        assert!(check_reactions(&released_at_end).is_err());
    }

    #[test]
    fn digit_patterns() {
        assert!(contains_pattern("x 12 ticks y", "# ticks"));
        assert!(!contains_pattern("x  ticks y", "# ticks"));
        assert!(contains_pattern("500..1200 rpm", "#..# rpm"));
        assert!(!contains_pattern("500..x rpm", "#..# rpm"));
    }

    #[test]
    fn boot_fault_path() {
        let ok = "ERROR boot: table build failed: step budget exceeded\nERROR alarm asserted (LED0 low: true), stopped: boot failed\n";
        check_boot_fault(ok).unwrap();
        assert!(check_boot_fault(&ok.replace("ERROR boot", "INFO  boot")).is_err());
        assert!(check_boot_fault(&ok.replace("low: true", "low: false")).is_err());
        let went_on = format!("{ok}INFO  table rpm=500\n");
        assert!(check_boot_fault(&went_on).is_err());
    }

    #[test]
    fn scene_and_profile_names() {
        let log = "INFO scene=stable-4567-rise.toml profile=theoretical profile_knots=0; ...\n";
        check_scene(log, "stable-4567-rise.toml").unwrap();
        assert!(check_scene(log, "stable-4567").is_err());
        let log = "INFO scene=reference profile=measured-wavy.csv profile_knots=361; alarm\n";
        check_profile(log, "measured-wavy.csv").unwrap();
        assert!(check_profile(log, "other.csv").is_err());
        let zero = log.replace("=361;", "=0;");
        assert!(check_profile(&zero, "measured-wavy.csv").is_err());
    }
}
