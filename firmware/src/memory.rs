//! Flash and RAM budget measured on the running image.
//!
//! Static sizes come from cortex-m-rt's `link.x` section symbols; the peak
//! stack comes from painting the free RAM between the end of the static data
//! (`__sheap`, which is also `_stack_end`) and the stack pointer at start-up with
//! [`PAINT`], and scanning at the end for the lowest word that was overwritten.
//!
//! Sections counted (scripts/firmware-ci.sh counts the same ones from `llvm-size -A`):
//! - flash = `.vector_table` + `.text` + `.rodata` + `.data` (its load image);
//! - static RAM = `.data` + `.bss` + `.uninit`.
//!
//! `.gnu.sgstubs` (TrustZone veneers) is always empty on an ARMv7-M, and `.defmt`
//! and the debug sections are not loaded, so none of them is counted.

use core::ptr::addr_of;

/// Word written over the free stack area before the program runs.
pub const PAINT: u32 = 0xC0FF_EE55;

// Symbols defined by cortex-m-rt's link.x. Only their ADDRESSES are used; the
// bytes behind them are never read through these declarations.
extern "C" {
    static __vector_table: u8;
    static __etext: u8;
    static __srodata: u8;
    static __erodata: u8;
    static __sdata: u8;
    static __edata: u8;
    static __sbss: u8;
    static __ebss: u8;
    static __suninit: u8;
    static __euninit: u8;
    static __sheap: u8;
    static _stack_start: u8;
}

/// Section start/end addresses of the running image, read from the linker symbols.
#[derive(Clone, Copy, Debug, defmt::Format)]
pub struct Sections {
    /// Start of `.vector_table` (= ORIGIN(FLASH)).
    pub vector_table: u32,
    /// End of `.text` (`.text` follows `.vector_table` directly).
    pub etext: u32,
    /// Start of `.rodata`.
    pub srodata: u32,
    /// End of `.rodata`.
    pub erodata: u32,
    /// Start of `.data` (RAM address).
    pub sdata: u32,
    /// End of `.data`.
    pub edata: u32,
    /// Start of `.bss`.
    pub sbss: u32,
    /// End of `.bss`.
    pub ebss: u32,
    /// Start of `.uninit`.
    pub suninit: u32,
    /// End of `.uninit`.
    pub euninit: u32,
    /// First free RAM word above the static data (lowest address the stack may reach).
    pub stack_end: u32,
    /// Initial stack pointer (top of RAM).
    pub stack_start: u32,
}

impl Sections {
    /// Reads the section symbols of the running image.
    pub fn get() -> Self {
        // Taking the address of an extern static is safe (no read happens).
        Self {
            vector_table: addr_of!(__vector_table) as u32,
            etext: addr_of!(__etext) as u32,
            srodata: addr_of!(__srodata) as u32,
            erodata: addr_of!(__erodata) as u32,
            sdata: addr_of!(__sdata) as u32,
            edata: addr_of!(__edata) as u32,
            sbss: addr_of!(__sbss) as u32,
            ebss: addr_of!(__ebss) as u32,
            suninit: addr_of!(__suninit) as u32,
            euninit: addr_of!(__euninit) as u32,
            stack_end: addr_of!(__sheap) as u32,
            stack_start: addr_of!(_stack_start) as u32,
        }
    }

    /// Bytes of flash: `.vector_table` + `.text` + `.rodata` + `.data` load image.
    pub fn flash_bytes(&self) -> u32 {
        (self.etext - self.vector_table) + (self.erodata - self.srodata) + (self.edata - self.sdata)
    }

    /// Bytes of statically allocated RAM: `.data` + `.bss` + `.uninit`.
    pub fn ram_static_bytes(&self) -> u32 {
        (self.edata - self.sdata) + (self.ebss - self.sbss) + (self.euninit - self.suninit)
    }

    /// Bytes of RAM left for the stack (`_stack_start - __sheap`).
    pub fn stack_room_bytes(&self) -> u32 {
        self.stack_start - self.stack_end
    }
}

/// Fills the free RAM from `__sheap` up to the current stack pointer with [`PAINT`].
///
/// Call it first thing in `main`: everything above the stack pointer at that
/// moment (the reset handler's and main's frames) counts as used.
#[inline(never)]
pub fn paint_stack() {
    let bottom = Sections::get().stack_end;
    // SAFETY: the loop stores only to [__sheap, sp), which is RAM below the live
    // stack that no Rust object occupies (the static data ends at __sheap, and
    // nothing lives below the stack pointer). It touches no register but its
    // own operands and does not use the stack.
    unsafe {
        core::arch::asm!(
            "mov {top}, sp",
            "2:",
            "cmp {p}, {top}",
            "bhs 3f",
            "str {pat}, [{p}], #4",
            "b 2b",
            "3:",
            p = inout(reg) bottom => _,
            top = out(reg) _,
            pat = in(reg) PAINT,
            options(nostack),
        );
    }
}

/// Peak stack use in bytes since [`paint_stack`]: from the top of RAM down to the
/// lowest word that no longer holds [`PAINT`].
#[inline(never)]
pub fn stack_peak_bytes() -> u32 {
    let s = Sections::get();
    let mut p = s.stack_end;
    while p < s.stack_start {
        // SAFETY: p is 4-byte aligned (link.x aligns __sheap to 4) and lies in
        // [__sheap, _stack_start), i.e. in the RAM region; a volatile read of a
        // plain RAM word has no side effects.
        let w = unsafe { core::ptr::read_volatile(p as *const u32) };
        if w != PAINT {
            break;
        }
        p += 4;
    }
    s.stack_start - p
}

/// What a binary reports about its own image at the end of a run.
#[derive(Clone, Copy, Debug, defmt::Format)]
pub struct MemoryReport {
    /// Flash of this image ([`Sections::flash_bytes`]).
    pub flash_bytes: u32,
    /// Static RAM of this image ([`Sections::ram_static_bytes`]).
    pub ram_static_bytes: u32,
    /// Peak stack since [`paint_stack`] ([`stack_peak_bytes`]).
    pub stack_peak_bytes: u32,
    /// RAM left for the stack ([`Sections::stack_room_bytes`]).
    pub stack_room_bytes: u32,
}

impl MemoryReport {
    /// Reads the sections and the stack peak, and logs the section addresses.
    pub fn measure() -> Self {
        let s = Sections::get();
        defmt::info!(
            "sections text_end={=u32:#x} rodata={=u32:#x}..{=u32:#x} data={=u32:#x}..{=u32:#x} bss={=u32:#x}..{=u32:#x} uninit={=u32:#x}..{=u32:#x} stack={=u32:#x}..{=u32:#x}",
            s.etext, s.srodata, s.erodata, s.sdata, s.edata, s.sbss, s.ebss, s.suninit, s.euninit,
            s.stack_end, s.stack_start
        );
        Self {
            flash_bytes: s.flash_bytes(),
            ram_static_bytes: s.ram_static_bytes(),
            stack_peak_bytes: stack_peak_bytes(),
            stack_room_bytes: s.stack_room_bytes(),
        }
    }

    /// RAM used: static data + peak stack.
    pub fn ram_bytes(&self) -> u32 {
        self.ram_static_bytes + self.stack_peak_bytes
    }

    /// True when the stack reached the end of its room (the peak is then a lower bound
    /// and static data may have been overwritten): the run is void. Logs the error.
    pub fn stack_overflowed(&self) -> bool {
        let over = self.stack_peak_bytes >= self.stack_room_bytes;
        if over {
            defmt::error!("stack overflowed its {=u32} bytes", self.stack_room_bytes);
        }
        over
    }
}
