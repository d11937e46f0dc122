#!/usr/bin/env bash
# The real-board image (Nucleo-F446RE, firmware feature `stm32f446`, binary board_f446),
# checked without hardware:
#  1. it builds in release (the same command as `cargo board-build` in firmware/) and
#     passes clippy with warnings denied;
#  2. its link layout is the board's (flash at 0x0800_0000, RAM at 0x2000_0000) and its
#     flash and static RAM, from `llvm-size -A` with the sections scripts/firmware-ci.sh
#     counts, fit the budget in the root memory.x:
#       flash      = .vector_table + .text + .rodata + .data (load image)
#       static RAM = .data + .bss + .uninit
#  3. its panic call sites (branches to core::panicking::*, panic_*, unwrap/expect_failed,
#     slice index failures) are listed with the code responsible for each: the innermost
#     inlined frame outside Rust's own library (llvm-addr2line -i; scripts/panic-sites.sh,
#     shared with firmware-ci.sh). It fails if any lies in camsim's own sources (core/,
#     chip/, firmware/); HAL, transport and core-library sites are printed and counted.
#     The QEMU image's are counted too, for comparison, if built.
# Called by scripts/test-all.sh after the firmware step; run from anywhere.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD

export PATH="$HOME/.cargo/bin:$PATH"

ELF=firmware/target/thumbv7em-none-eabihf/release/board_f446
QEMU_ELF=firmware/target/thumbv7em-none-eabihf/release/predictor
BUDGET=memory.x
FLASH_ORIGIN=$((0x08000000))
RAM_ORIGIN=$((0x20000000))

fail() { printf 'board-ci: FAIL: %s\n' "$*" >&2; exit 1; }

# An LLVM tool, plain or versioned (apt's llvm-14).
tool() {
    if command -v "$1" >/dev/null 2>&1; then echo "$1"
    elif command -v "$1-14" >/dev/null 2>&1; then echo "$1-14"
    else fail "$1 not found (apt-get install llvm-14)"
    fi
}
LLVM_SIZE=$(tool llvm-size)
# The panic lister (scripts/panic-sites.sh) needs these two; checked here for the message.
tool llvm-objdump >/dev/null
tool llvm-addr2line >/dev/null

echo "board-ci: build (release, --no-default-features --features stm32f446 --bin board_f446) and lints"
(cd firmware && cargo build --release --no-default-features --features stm32f446 --bin board_f446)
(cd firmware && cargo clippy --release --no-default-features --features stm32f446 --all-targets -- -D warnings)
[ -f "$ELF" ] || fail "no ELF at $ELF"

# ---------------------------------------------------------------------------
# Budget: the LENGTHs of FLASH and RAM in the root memory.x (what build.rs puts at the
# board's origins), in bytes.
# ---------------------------------------------------------------------------
budget_bytes() {
    local v
    v=$(sed -n -E "s/^[[:space:]]*$1[[:space:]]*(\([^)]*\))?[[:space:]]*:.*LENGTH[[:space:]]*=[[:space:]]*([0-9A-Fa-fxX]+[KkMm]?).*/\2/p" "$BUDGET" | head -n 1)
    [ -n "$v" ] || fail "$BUDGET has no LENGTH for region $1"
    local mul=1
    case $v in
        *[Kk]) mul=1024; v=${v%?} ;;
        *[Mm]) mul=$((1024 * 1024)); v=${v%?} ;;
    esac
    echo $((v * mul))
}
budget_flash=$(budget_bytes FLASH)
budget_ram=$(budget_bytes RAM)

echo "board-ci: sizes ($LLVM_SIZE -A $ELF)"
sizes=$("$LLVM_SIZE" -A "$ELF")
sec() { awk -v s="$1" '$1 == s { print $2; found = 1 } END { if (!found) print 0 }' <<<"$sizes"; }
addr() { awk -v s="$1" '$1 == s { print $3; found = 1 } END { if (!found) print -1 }' <<<"$sizes"; }
unexpected=$(awk 'NR > 2 && NF >= 3 && $2 > 0 && $1 !~ /^\.(vector_table|text|rodata|data|bss|uninit|defmt|debug_.*|comment|ARM\.attributes|symtab|strtab|shstrtab)$/ { print $1 }' <<<"$sizes")
[ -z "$unexpected" ] || fail "unexpected non-empty sections (count them in firmware/src/memory.rs, scripts/firmware-ci.sh and here): $unexpected"
[ "$(addr .vector_table)" -eq "$FLASH_ORIGIN" ] || fail ".vector_table at $(addr .vector_table), not the board's flash origin $FLASH_ORIGIN"
[ "$(addr .data)" -eq "$RAM_ORIGIN" ] || fail ".data at $(addr .data), not the board's RAM origin $RAM_ORIGIN"
flash=$(( $(sec .vector_table) + $(sec .text) + $(sec .rodata) + $(sec .data) ))
ram_static=$(( $(sec .data) + $(sec .bss) + $(sec .uninit) ))
printf '  flash      = .vector_table %s + .text %s + .rodata %s + .data %s = %s of %s (%s %%)\n' \
    "$(sec .vector_table)" "$(sec .text)" "$(sec .rodata)" "$(sec .data)" "$flash" "$budget_flash" \
    $((100 * flash / budget_flash))
printf '  static RAM = .data %s + .bss %s + .uninit %s = %s of %s (%s bytes left for the stack)\n' \
    "$(sec .data)" "$(sec .bss)" "$(sec .uninit)" "$ram_static" "$budget_ram" $((budget_ram - ram_static))
[ "$flash" -le "$budget_flash" ] || fail "flash $flash > budget $budget_flash"
[ "$ram_static" -le "$budget_ram" ] || fail "static RAM $ram_static > budget $budget_ram"
echo "board-ci: board flash_bytes=$flash ram_static_bytes=$ram_static"

# ---------------------------------------------------------------------------
# Panic call sites.
# ---------------------------------------------------------------------------
# The lister is shared with scripts/firmware-ci.sh (which holds the QEMU product to a
# stricter rule: every site in the logging transport).
# shellcheck source=scripts/panic-sites.sh
source scripts/panic-sites.sh

echo "board-ci: panic call sites in $ELF (responsible code <- file:line (in the function holding the call))"
panic_sites "$ELF"
if [ -f "$QEMU_ELF" ]; then
    echo "board-ci: for comparison, the QEMU image $QEMU_ELF"
    saved=$PANIC_OWN
    panic_sites "$QEMU_ELF"
    PANIC_OWN=$saved
fi
[ "$PANIC_OWN" -eq 0 ] || fail "panic call sites in camsim's own code (origin camsim above)"

echo "board-ci: OK"
