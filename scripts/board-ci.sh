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
#     inlined frame outside Rust's own library (llvm-addr2line -i). It fails if any lies
#     in camsim's own sources (core/, firmware/); HAL, transport and core-library sites
#     are printed and counted. The QEMU image's are counted too, for comparison, if built.
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
OBJDUMP=$(tool llvm-objdump)
ADDR2LINE=$(tool llvm-addr2line)

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
# Panic entry points (demangled, without hash): core::panicking::*, any panic_* item,
# Option/Result unwrap and expect failures, slice and str index failures, the handler.
PANIC_RE='^(core::panicking::|core::option::(unwrap|expect)_failed|core::result::unwrap_failed|core::slice::index::[a-z_]*_fail|core::str::slice_error_fail|core::cell::panic_|(__rustc::)?rust_begin_unwind$)|(^|::)panic_[a-z_]*$'

# panic_sites ELF: prints the count and one line per call site; sets PANIC_OWN to the
# number whose responsible code is camsim's own.
panic_sites() {
    local elf=$1 sites
    # "address<TAB>callee<TAB>caller" for each branch to a panic entry point from code that
    # is not itself one (branches inside a function, <f+0x..>, are not calls).
    sites=$("$OBJDUMP" -d --no-show-raw-insn -C "$elf" | awk -v re="$PANIC_RE" '
        # A label starts a function, except the ARM mapping symbols ($t, $d: Thumb code, data).
        /^[0-9a-f]+ <.*>:$/ { l = $0; sub(/^[0-9a-f]+ </, "", l); sub(/>:$/, "", l); if (l !~ /^\$/) fn = l; next }
        $2 ~ /^b/ && match($0, /<[^>]*>/) {
            callee = substr($0, RSTART + 1, RLENGTH - 2)
            if (callee ~ /\+0x[0-9a-f]+$/) next
            if (callee ~ re && fn !~ re) { a = $1; sub(/:$/, "", a); printf "%s\t%s\t%s\n", a, callee, fn }
        }')
    PANIC_OWN=0
    if [ -z "$sites" ]; then
        echo "  0 panic call sites"
        return
    fi
    # The responsible frame of each site: the innermost inlined frame whose file is not
    # Rust's own library (/rustc/...), else the innermost frame.
    local frames
    frames=$(cut -f1 <<<"$sites" | sed 's/^/0x/' | "$ADDR2LINE" -a -f -i -e "$elf" | awk '
        function flush() { if (a != "") print a "\t" (pick != "" ? pick : first) }
        /^0x[0-9a-f]+$/ { flush(); a = $0; first = ""; pick = ""; n = 0; next }
        { n++; if (n % 2 == 1) { f = $0; next }
          fr = $0 "\t" f
          if (first == "") first = fr
          if (pick == "" && $0 !~ /^\/rustc\// && $0 !~ /^\?\?/) pick = fr }
        END { flush() }')
    paste <(cut -f2,3 <<<"$sites") <(cut -f2,3 <<<"$frames") | awk -F '\t' -v root="$ROOT/" '
        {
            callee = $1; caller = $2; file = $3
            if (index(file, root) == 1) { origin = "camsim"; file = substr(file, length(root) + 1); own++ }
            else if (file ~ /\/\.cargo\/registry\/src\/[^\/]*\//) {
                origin = file; sub(/.*\/\.cargo\/registry\/src\/[^\/]*\//, "", origin); sub(/\/.*/, "", origin)
                sub(/.*\/\.cargo\/registry\/src\/[^\/]*\/[^\/]*\//, "", file)
            } else if (file ~ /^\/rustc\//) { origin = "core library"; sub(/^\/rustc\/[^\/]*\/library\//, "", file) }
            else origin = "unknown"
            count[origin]++; total++
            printf "    %-14s %-42s <- %s (in %s)\n", origin, callee, file, caller
        }
        END {
            line = ""
            for (o in count) line = line sprintf("%s%s %d", (line == "" ? "" : ", "), o, count[o])
            printf "  %d panic call sites (%s)\n", total, line
            exit own > 0 ? 3 : 0
        }' || { [ $? -eq 3 ] && PANIC_OWN=1; }
    return 0
}

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
