#!/usr/bin/env bash
# Builds the camsim firmware (Cortex-M4F, release) and runs its binaries under QEMU
# mps2-an386 with -icount shift=0, decodes their defmt output and checks them:
# - predictor (the product): its memory line
#     product flash_bytes=.. ram_static_bytes=.. stack_peak_bytes=.. ram_bytes=.. boot_instr=.. max_instr_per_reading=..
#   host parity of every `parity ...` line (camsim predict --f32 --check-log), and the
#   reactions to the faults of the scripted machine (camsim_chip::CHIP_SCRIPT): for each
#   of a lost speed, a pulse faster than the machine's limit, a bounce, a missed pulse
#   and a speed outside the table's grid, its warning and a `reaction kind=.. alarm=asserted
#   pin=LED0 level=low` line (LED0 read back), never a released alarm on a reading that
#   does not vouch for the speed, and the alarm asserted when the script ends;
# - boot_fault (the product's boot with an impossible solver budget): exit status 1,
#   the error reported, the alarm asserted with LED0 read back low;
# - the release product ELF's panic call sites (scripts/panic-sites.sh): it fails if any
#   lies outside the logging transport (defmt-semihosting and its semihosting crate);
# - budget (the instruction probes): its budget line
#     budget flash_bytes=.. ram_static_bytes=.. stack_peak_bytes=.. ram_bytes=.. instr_per_rhs=.. instr_per_rev=.. realtime_factor=..
# For each image, flash and static RAM are cross-checked against `llvm-size -A` on its
# ELF, counting the same sections on both sides (see firmware/src/memory.rs):
#   flash      = .vector_table + .text + .rodata + .data (load image)
#   static RAM = .data + .bss + .uninit
# and checked against the budget in memory.x (flash <= FLASH, static RAM + stack peak
# <= RAM). The real-board build (`--features rtt`) is compiled and its sizes checked too
# (it is not run). Then a scene chosen at build time (CAMSIM_SCENE=scene file) is built,
# run and checked again, and a measured cam profile (CAMSIM_PROFILE=scenes/measured-wavy.csv)
# in the product: run, sized against the budget, panic sites and host parity
# (camsim predict --f32 --measured).
# Called by scripts/test-all.sh; run from anywhere (it cd's to the repository root).
set -euo pipefail
cd "$(dirname "$0")/.."

export PATH="$HOME/.cargo/bin:$PATH"

ELF_DIR=firmware/target/thumbv7em-none-eabihf/release
PREDICTOR_ELF=$ELF_DIR/predictor
BUDGET_ELF=$ELF_DIR/budget
BOOT_FAULT_ELF=$ELF_DIR/boot_fault
BOOT_FAULT_LOG=target/firmware-boot-fault.log   # the boot-failure test's log
# Crates whose code may hold the product's panic call sites: the logging transport.
TRANSPORT_ORIGINS='^(defmt-semihosting|semihosting)-[0-9]'
LOG=target/firmware-run.log              # the predictor's log (host parity reads it)
BUDGET_LOG=target/firmware-budget.log    # the budget probes' log
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

# The budget: LENGTH of FLASH and RAM in memory.x (the link fails beyond it; checked
# here too, so the reported figures are held against the same numbers).
region_bytes() {
    local len
    len=$(sed -n "s/^[[:space:]]*$1[[:space:]]*:.*LENGTH[[:space:]]*=[[:space:]]*\([0-9]*[KM]\{0,1\}\).*/\1/p" memory.x)
    case "$len" in
        *K) echo $(( ${len%K} * 1024 )) ;;
        *M) echo $(( ${len%M} * 1024 * 1024 )) ;;
        [0-9]*) echo "$len" ;;
        *) fail "no LENGTH for region $1 in memory.x" ;;
    esac
}
FLASH_BUDGET=$(region_bytes FLASH)
RAM_BUDGET=$(region_bytes RAM)
echo "firmware-ci: budget from memory.x: flash $FLASH_BUDGET B, RAM $RAM_BUDGET B"

# Flash and static RAM of an ELF from `llvm-size -A`, the same sections the firmware counts.
# Sets ls_flash and ls_ram_static; fails on any other non-empty loadable section.
llvm_sizes() {
    local elf=$1 sizes unexpected
    sizes=$("$LLVM_SIZE" -A "$elf")
    sec() { awk -v s="$1" '$1 == s { print $2; found = 1 } END { if (!found) print 0 }' <<<"$sizes"; }
    # Any other section that takes flash or RAM must be added to both counts.
    unexpected=$(awk 'NR > 2 && NF >= 3 && $2 > 0 && $1 !~ /^\.(vector_table|text|rodata|data|bss|uninit|defmt|debug_.*|comment|ARM\.attributes|symtab|strtab|shstrtab)$/ { print $1 }' <<<"$sizes")
    [ -z "$unexpected" ] || fail "$elf: unexpected non-empty sections (count them in firmware/src/memory.rs and here): $unexpected"
    ls_flash=$(( $(sec .vector_table) + $(sec .text) + $(sec .rodata) + $(sec .data) ))
    ls_ram_static=$(( $(sec .data) + $(sec .bss) + $(sec .uninit) ))
    printf '  %s: flash = .vector_table %s + .text %s + .rodata %s + .data %s = %s; static RAM = .data %s + .bss %s + .uninit %s = %s\n' \
        "$elf" "$(sec .vector_table)" "$(sec .text)" "$(sec .rodata)" "$(sec .data)" "$ls_flash" \
        "$(sec .data)" "$(sec .bss)" "$(sec .uninit)" "$ls_ram_static"
}

# The real board's build (defmt over RTT, panic-probe): it must compile and fit; it is
# not run (no probe here). Built first: it shares the target directory with the QEMU build.
echo "firmware-ci: build the real-board image (release, --no-default-features --features rtt)"
(cd firmware && cargo build --release --no-default-features --features rtt)
for elf in "$PREDICTOR_ELF" "$BUDGET_ELF"; do
    llvm_sizes "$elf"
    [ "$ls_flash" -le "$FLASH_BUDGET" ] || fail "$elf (rtt): flash $ls_flash > $FLASH_BUDGET"
    [ "$ls_ram_static" -lt "$RAM_BUDGET" ] || fail "$elf (rtt): static RAM $ls_ram_static >= $RAM_BUDGET"
done

echo "firmware-ci: build (release)"
(cd firmware && cargo build --release)
for elf in "$PREDICTOR_ELF" "$BUDGET_ELF" "$BOOT_FAULT_ELF"; do
    [ -f "$elf" ] || fail "no ELF at $elf"
done

# Runs the ELF under QEMU, decodes the defmt output into $2, fails unless QEMU exits with
# status $3 (default 0).
run_qemu() {
    local elf=$1 log=$2 expect=${3:-0}
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
    [ "${status[0]}" -eq "$expect" ] || fail "QEMU exited with status ${status[0]}, expected $expect (firmware panic or fault?)"
    [ "${status[1]}" -eq 0 ] || fail "defmt-print exited with status ${status[1]}"
}
# The last line of $2 that starts with "$1 " (e.g. "product", "budget"), or fail.
last_line() {
    local what=$1 log=$2 line
    line=$(grep -o "$what flash_bytes=[0-9]* .*" "$log" | tail -n 1 || true)
    [ -n "$line" ] || fail "no '$what ...' line in $log"
    printf '%s\n' "$line"
}
# A numeric field of a line: field LINE NAME.
field() {
    local v
    v=$(sed -n "s/.*[[:space:]]$2=\([0-9][0-9]*\).*/\1/p" <<<" $1")
    [ -n "$v" ] || fail "no numeric $2= in: $1"
    printf '%s\n' "$v"
}
# Checks the memory fields of a `product`/`budget` line against the image's ELF and memory.x.
check_memory() {
    local line=$1 elf=$2 flash ram_static stack ram
    flash=$(field "$line" flash_bytes)
    ram_static=$(field "$line" ram_static_bytes)
    stack=$(field "$line" stack_peak_bytes)
    ram=$(field "$line" ram_bytes)
    [ "$ram" -eq $((ram_static + stack)) ] || fail "$elf: ram_bytes $ram != ram_static_bytes $ram_static + stack_peak_bytes $stack"
    [ "$stack" -gt 0 ] || fail "$elf: stack_peak_bytes is 0 (stack paint not working)"
    echo "firmware-ci: cross-check $elf with $LLVM_SIZE -A"
    llvm_sizes "$elf"
    [ "$ls_flash" -eq "$flash" ] || fail "$elf: flash: llvm-size $ls_flash != firmware $flash"
    [ "$ls_ram_static" -eq "$ram_static" ] || fail "$elf: static RAM: llvm-size $ls_ram_static != firmware $ram_static"
    [ "$flash" -le "$FLASH_BUDGET" ] || fail "$elf: flash $flash B > budget $FLASH_BUDGET B (memory.x)"
    [ "$ram" -le "$RAM_BUDGET" ] || fail "$elf: RAM $ram B > budget $RAM_BUDGET B (memory.x)"
    printf '  flash %s B of %s (%s %%), RAM %s B of %s (%s %%)\n' "$flash" "$FLASH_BUDGET" \
        $((flash * 100 / FLASH_BUDGET)) "$ram" "$RAM_BUDGET" $((ram * 100 / RAM_BUDGET))
}
# The product's reactions to the scripted machine's faults, from its log $1.
check_reactions() {
    local log=$1 kind n bad
    for kind in lost too_short bounce step out_of_range; do
        n=$(grep -c "reaction kind=$kind alarm=asserted pin=LED0 level=low" "$log" || true)
        [ "$n" -ge 1 ] || fail "$log: no 'reaction kind=$kind alarm=asserted pin=LED0 level=low' line (the script's $kind fault)"
        printf '  fault %-12s %s reading(s), each: alarm asserted, LED0 read back low\n' "$kind" "$n"
    done
    bad=$(grep 'reaction kind=' "$log" | grep -v 'alarm=asserted pin=LED0 level=low' || true)
    [ -z "$bad" ] || fail "$log: a reading that does not vouch for the speed left the alarm released or LED0 high: $bad"
    # Each fault's warning names it (the flagged speed is never extrapolated).
    for text in 'speed lost: no index pulse for [0-9]* ticks' \
                'pulse rejected: [0-9]* ticks since the last, faster than [0-9]* rpm' \
                'pulse rejected: [0-9]* ticks, under [0-9]* % of the last period (bounce)' \
                'period rejected: [0-9]* ticks, more than [0-9]* % off the last' \
                'outside the table.s [0-9]*\.\.[0-9]* rpm: flagged, not extrapolated'; do
        grep -q "$text" "$log" || fail "$log: no warning matching '$text'"
    done
    grep -q 'predictor readings=.* alarm_at_end=asserted (LED0 low)' "$log" \
        || fail "$log: the alarm is not asserted (LED0 low) when the pulses have stopped"
}
# Runs both binaries (product log $1, budget log $2) and checks their lines.
run_and_check() {
    local log=$1 budget_log=$2 product budget
    run_qemu "$PREDICTOR_ELF" "$log"
    run_qemu "$BUDGET_ELF" "$budget_log"

    product=$(last_line product "$log")
    check_memory "$product" "$PREDICTOR_ELF"
    [ "$(field "$product" boot_instr)" -gt 0 ] || fail "boot_instr is 0 (SysTick calibration not working)"
    grep -q 'budget flash_bytes=' "$log" && fail "the product log has a budget line (the probes belong to the budget binary)"
    echo "firmware-ci: fault reactions in $log"
    check_reactions "$log"

    budget=$(last_line budget "$budget_log")
    check_memory "$budget" "$BUDGET_ELF"
    [ "$(field "$budget" instr_per_rhs)" -gt 0 ] && [ "$(field "$budget" instr_per_rev)" -gt 0 ] \
        || fail "instruction counts are 0 (SysTick calibration not working)"
    # The real-time factor is 168e6 * 60 / 800 / instr_per_rev (workload::CLOCK_HZ): check it.
    rt=$(sed -n 's/.*[[:space:]]realtime_factor=\([0-9.eE+-]*\).*/\1/p' <<<" $budget")
    [ -n "$rt" ] || fail "no realtime_factor= in: $budget"
    awk -v f="$rt" -v i="$(field "$budget" instr_per_rev)" \
        'BEGIN { e = 12600000 / i; exit !(f > 0 && (f - e) < 1e-3 * e && (e - f) < 1e-3 * e) }' \
        || fail "realtime_factor does not match instr_per_rev"

    echo "firmware-ci: $product"
    echo "firmware-ci: $budget"
}
run_and_check "$LOG" "$BUDGET_LOG"

# ---------------------------------------------------------------------------
# A solver failure at boot: the product's boot (board::qemu::boot_or_stop) with an
# impossible step budget must report the error and stop with the alarm asserted.
# ---------------------------------------------------------------------------
echo "firmware-ci: boot failure (boot_fault: the product's boot with 1 solver step per revolution)"
run_qemu "$BOOT_FAULT_ELF" "$BOOT_FAULT_LOG" 1
grep -q 'ERROR *boot: table build failed: step budget exceeded' "$BOOT_FAULT_LOG" \
    || fail "boot_fault: the solver failure is not reported"
grep -q 'ERROR *alarm asserted (LED0 low: true), stopped: boot failed' "$BOOT_FAULT_LOG" \
    || fail "boot_fault: the alarm is not left asserted (LED0 low) after the failed boot"
grep -q 'table rpm=\|predictor readings=' "$BOOT_FAULT_LOG" \
    && fail "boot_fault: it went on after the failed boot"

# ---------------------------------------------------------------------------
# No panic on the chip: every panic call site of the release product ELF lies in the
# logging transport. The lister must see them: with nothing allowed it counts them all.
# ---------------------------------------------------------------------------
# shellcheck source=scripts/panic-sites.sh
source scripts/panic-sites.sh
echo "firmware-ci: panic call sites in $PREDICTOR_ELF (responsible code <- file:line (in the function holding the call))"
panic_sites "$PREDICTOR_ELF" "$TRANSPORT_ORIGINS"
[ "$PANIC_OUTSIDE" -eq 0 ] || fail "$PANIC_OUTSIDE panic call site(s) of the product outside the logging transport (listed above)"
[ "$PANIC_TOTAL" -gt 0 ] || fail "no panic call site found: the transport has 6; is the lister broken?"
panic_sites "$PREDICTOR_ELF" >/dev/null
[ "$PANIC_OUTSIDE" -eq "$PANIC_TOTAL" ] || fail "the panic lister's filter is broken"
echo "firmware-ci: product panic call sites: $PANIC_TOTAL, all in the logging transport"

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
# A scene chosen at build time: firmware/build.rs reads the scene file (CAMSIM_SCENE)
# with the host's reader, narrows its design to f32 and compiles it in as postcard
# (decoded at boot, never parsed as text on the chip); run, and checked against the
# host again (`camsim predict --f32 --scene`, the same reader and the same narrowing).
# ---------------------------------------------------------------------------
SCENE=scenes/stable-4567-rise.toml
SCENE_NAME=$(basename "$SCENE")
SCENE_LOG=target/firmware-run-scene.log
SCENE_BUDGET_LOG=target/firmware-budget-scene.log
echo "firmware-ci: build-time scene $SCENE"
SCENE_PATH="$PWD/$SCENE"   # absolute: build.rs runs in firmware/
(cd firmware && CAMSIM_SCENE="$SCENE_PATH" cargo build --release)
run_and_check "$SCENE_LOG" "$SCENE_BUDGET_LOG"
grep -q "scene=$SCENE_NAME" "$SCENE_LOG" || fail "the scene build did not report its scene ($SCENE_NAME)"
grep -q "scene=$SCENE_NAME" "$SCENE_BUDGET_LOG" || fail "the scene's budget image did not report its scene ($SCENE_NAME)"
./target/release/camsim predict --f32 --scene "$SCENE" --check-log "$SCENE_LOG" || fail "host parity (scene): see the line above"
# ---------------------------------------------------------------------------
# A measured cam profile compiled in (CAMSIM_PROFILE): firmware/build.rs reads the CSV with
# the host's reader (camsim_scene_file::measured), turns it into the deviation knots on the
# design, narrows them to f32 and compiles them into flash; the product splines them at
# boot and builds its table with the roller on that cam. Only the product carries it (the
# budget probes do not: see firmware/README.md). Checked: the run, its memory against
# llvm-size and memory.x, the fault reactions, the panic sites, and host parity with
# `camsim predict --f32 --measured` (the same reader, knots, narrowing and spline).
# ---------------------------------------------------------------------------
PROFILE=scenes/measured-wavy.csv
PROFILE_NAME=$(basename "$PROFILE")
PROFILE_LOG=target/firmware-run-profile.log
echo "firmware-ci: build-time measured profile $PROFILE (product)"
PROFILE_PATH="$PWD/$PROFILE"   # absolute: build.rs runs in firmware/
(cd firmware && CAMSIM_PROFILE="$PROFILE_PATH" cargo build --release --bin predictor)
run_qemu "$PREDICTOR_ELF" "$PROFILE_LOG"
grep -q "scene=reference profile=$PROFILE_NAME profile_knots=[1-9][0-9]*;" "$PROFILE_LOG" \
    || fail "the profile build did not report its profile ($PROFILE_NAME) and knots"
product=$(last_line product "$PROFILE_LOG")
check_memory "$product" "$PREDICTOR_ELF"
echo "firmware-ci: fault reactions in $PROFILE_LOG"
check_reactions "$PROFILE_LOG"
panic_sites "$PREDICTOR_ELF" "$TRANSPORT_ORIGINS"
[ "$PANIC_OUTSIDE" -eq 0 ] || fail "$PANIC_OUTSIDE panic call site(s) of the profile product outside the logging transport (listed above)"
echo "firmware-ci: profile product: $product"
./target/release/camsim predict --f32 --measured "$PROFILE" --check-log "$PROFILE_LOG" \
    || fail "host parity (measured profile): see the line above"

# Leave the default (reference) firmware built, as a plain `cargo build` would.
(cd firmware && cargo build --release)

echo "firmware-ci: OK"
