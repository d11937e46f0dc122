#!/usr/bin/env bash
# Builds the camsim firmware (Cortex-M4F, release), runs it under QEMU mps2-an386
# with -icount shift=0, decodes its defmt output, and checks its budget line:
#   budget flash_bytes=.. ram_static_bytes=.. stack_peak_bytes=.. ram_bytes=.. instr_per_rhs=.. instr_per_rev=..
# Flash and static RAM are cross-checked against `llvm-size -A` on the ELF, counting
# the same sections on both sides (see firmware/src/memory.rs):
#   flash      = .vector_table + .text + .rodata + .data (load image)
#   static RAM = .data + .bss + .uninit
# Called by scripts/test-all.sh; run from anywhere (it cd's to the repository root).
set -euo pipefail
cd "$(dirname "$0")/.."

export PATH="$HOME/.cargo/bin:$PATH"

ELF=firmware/target/thumbv7em-none-eabihf/release/predictor
LOG=target/firmware-run.log
QEMU_TIMEOUT_S=300

fail() { printf 'firmware-ci: FAIL: %s\n' "$*" >&2; exit 1; }

if command -v llvm-size >/dev/null 2>&1; then
    LLVM_SIZE=llvm-size
elif command -v llvm-size-14 >/dev/null 2>&1; then
    LLVM_SIZE=llvm-size-14
else
    fail "llvm-size not found (apt-get install llvm-14)"
fi
for tool in qemu-system-arm defmt-print timeout; do
    command -v "$tool" >/dev/null 2>&1 || fail "$tool not found"
done

echo "firmware-ci: build (release)"
(cd firmware && cargo build --release)
[ -f "$ELF" ] || fail "no ELF at $ELF"

# Runs the ELF under QEMU, decodes the defmt output into $2, fails unless QEMU exits 0.
run_qemu() {
    local elf=$1 log=$2
    echo "firmware-ci: run under QEMU (timeout ${QEMU_TIMEOUT_S}s) -> $log"
    mkdir -p "$(dirname "$log")"
    set +e
    timeout "$QEMU_TIMEOUT_S" qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic \
        -semihosting-config enable=on,target=native -icount shift=0 -kernel "$elf" </dev/null \
        | defmt-print -e "$elf" >"$log" 2>&1
    local status=("${PIPESTATUS[@]}")
    set -e
    cat "$log"
    [ "${status[0]}" -eq 124 ] && fail "QEMU timed out after ${QEMU_TIMEOUT_S}s"
    [ "${status[0]}" -eq 0 ] || fail "QEMU exited with status ${status[0]} (firmware panic or fault?)"
    [ "${status[1]}" -eq 0 ] || fail "defmt-print exited with status ${status[1]}"
}
run_qemu "$ELF" "$LOG"

budget=$(grep -o 'budget flash_bytes=[0-9]* ram_static_bytes=[0-9]* stack_peak_bytes=[0-9]* ram_bytes=[0-9]* instr_per_rhs=[0-9]* instr_per_rev=[0-9]*' "$LOG" | tail -n 1 || true)
[ -n "$budget" ] || fail "no budget line in $LOG"

field() { sed -n "s/.*[[:space:]]$1=\([0-9]*\).*/\1/p" <<<" $budget"; }
fw_flash=$(field flash_bytes)
fw_ram_static=$(field ram_static_bytes)
fw_stack=$(field stack_peak_bytes)
fw_ram=$(field ram_bytes)
fw_rhs=$(field instr_per_rhs)
fw_rev=$(field instr_per_rev)

[ "$fw_ram" -eq $((fw_ram_static + fw_stack)) ] || fail "ram_bytes $fw_ram != ram_static_bytes + stack_peak_bytes"
[ "$fw_stack" -gt 0 ] || fail "stack_peak_bytes is 0 (stack paint not working)"
[ "$fw_rhs" -gt 0 ] && [ "$fw_rev" -gt 0 ] || fail "instruction counts are 0 (SysTick calibration not working)"

echo "firmware-ci: cross-check with $LLVM_SIZE -A"
sizes=$("$LLVM_SIZE" -A "$ELF")
sec() { awk -v s="$1" '$1 == s { print $2; found = 1 } END { if (!found) print 0 }' <<<"$sizes"; }
# Any other section that takes flash or RAM must be added to both counts.
unexpected=$(awk 'NR > 2 && NF >= 3 && $2 > 0 && $1 !~ /^\.(vector_table|text|rodata|data|bss|uninit|defmt|debug_.*|comment|ARM\.attributes|symtab|strtab|shstrtab)$/ { print $1 }' <<<"$sizes")
[ -z "$unexpected" ] || fail "unexpected non-empty sections (count them in firmware/src/memory.rs and here): $unexpected"
ls_flash=$(( $(sec .vector_table) + $(sec .text) + $(sec .rodata) + $(sec .data) ))
ls_ram_static=$(( $(sec .data) + $(sec .bss) + $(sec .uninit) ))
printf '  flash      = .vector_table %s + .text %s + .rodata %s + .data %s = %s (firmware: %s)\n' \
    "$(sec .vector_table)" "$(sec .text)" "$(sec .rodata)" "$(sec .data)" "$ls_flash" "$fw_flash"
printf '  static RAM = .data %s + .bss %s + .uninit %s = %s (firmware: %s)\n' \
    "$(sec .data)" "$(sec .bss)" "$(sec .uninit)" "$ls_ram_static" "$fw_ram_static"
[ "$ls_flash" -eq "$fw_flash" ] || fail "flash: llvm-size $ls_flash != firmware $fw_flash"
[ "$ls_ram_static" -eq "$fw_ram_static" ] || fail "static RAM: llvm-size $ls_ram_static != firmware $fw_ram_static"

echo "firmware-ci: $budget"

# ---------------------------------------------------------------------------
# HOST PARITY CHECK: the host runs the same f32 scene through the same core code
# (`camsim predict --f32`) and compares every `parity ...` line of the log (table,
# jump onset, interpolation checks, every sample's margins, timing errors and alarm
# state, as raw f32 bits) bit for bit; it fails with a one-line error on a mismatch.
# ---------------------------------------------------------------------------
echo "firmware-ci: host parity (camsim predict --f32 --check-log $LOG)"
cargo build -q --release -p camsim
./target/release/camsim predict --f32 --check-log "$LOG" || fail "host parity: see the line above"

# ---------------------------------------------------------------------------
# A scene chosen at build time: generated from a scene file into a const record
# (never parsed on the chip), compiled in, run, and checked against the host again.
# ---------------------------------------------------------------------------
SCENE=scenes/stable-4567-rise.toml
SCENE_RS="$PWD/target/firmware-scene.rs"
SCENE_LOG=target/firmware-run-scene.log
echo "firmware-ci: build-time scene $SCENE"
./target/release/camsim scene --rust "$SCENE" >"$SCENE_RS"
(cd firmware && CAMSIM_SCENE_RS="$SCENE_RS" cargo build --release)
run_qemu "$ELF" "$SCENE_LOG"
grep -q "scene=generated" "$SCENE_LOG" || fail "the scene build did not report its generated scene"
./target/release/camsim predict --f32 --scene "$SCENE" --check-log "$SCENE_LOG" || fail "host parity (scene): see the line above"
# Leave the default (reference) firmware built, as a plain `cargo build` would.
(cd firmware && cargo build --release)

echo "firmware-ci: OK"
