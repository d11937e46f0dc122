#!/usr/bin/env bash
# Builds the camsim firmware (Cortex-M4F, release), runs its binaries under QEMU
# mps2-an386 with -icount shift=0 and decodes their defmt output; the checks of the
# decoded logs are Rust, `camsim firmware-check` (host-sim/src/firmware_log.rs, unit-tested
# on sample logs), reading the lines in the formats of camsim_chip's log-line types
# (ProductLine, BudgetLine, ReactionLine, ParityLine: defmt::Format on the chip, Display
# on the host). This script only builds, runs, decodes and calls the checkers:
# - predictor (the QEMU demonstration image; the product is board_f446): its `product`
#   memory line, its boot cost, the reactions to the faults of the scripted machine
#   (camsim_chip::CHIP_SCRIPT: each fault's warning and a `reaction kind=.. alarm=asserted
#   pin=LED0 level=low` line, never a released alarm, the alarm asserted at the end)
#   (camsim firmware-check --product), and host parity of every `parity ...` line
#   (camsim predict --f32 --check-log);
# - budget (the instruction probes): its `budget` line, the real-time factor recomputed
#   from instr_per_rev and camsim_chip's clock (camsim firmware-check --budget);
# - boot_fault (the demonstration image's boot with an impossible solver budget): exit
#   status 1, the error reported, the alarm asserted with LED0 read back low
#   (camsim firmware-check --boot-fault);
# - the release predictor ELF's panic call sites (scripts/panic-sites.sh): it fails if any
#   lies outside the logging transport (defmt-semihosting and its semihosting crate).
# For each image, flash and static RAM are cross-checked against `llvm-size -A` on its
# ELF (the same sections as firmware/src/memory.rs) and held to the budget in memory.x.
# The real-board build (`--features rtt`) is compiled and its sizes checked too
# (camsim firmware-check --fits; it is not run). Then a scene chosen at build time
# (CAMSIM_SCENE=scene file) is built, run and checked again, and a measured cam profile
# (CAMSIM_PROFILE=scenes/measured-wavy.csv) in the demonstration image: run, sized
# against the budget, panic sites and host parity (camsim predict --f32 --measured).
# Called by scripts/test-all.sh; run from anywhere (it cd's to the repository root).
set -euo pipefail
cd "$(dirname "$0")/.."
# The binary where cargo put it (scripts/camsim-bin.sh).
CAMSIM="$(bash scripts/camsim-bin.sh)"

export PATH="$HOME/.cargo/bin:$PATH"

ELF_DIR=firmware/target/thumbv7em-none-eabihf/release
PREDICTOR_ELF=$ELF_DIR/predictor
BUDGET_ELF=$ELF_DIR/budget
BOOT_FAULT_ELF=$ELF_DIR/boot_fault
BOOT_FAULT_LOG=target/firmware-boot-fault.log   # the boot-failure test's log
# Crates whose code may hold the demonstration image's panic call sites: the logging transport.
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

# The checks of the decoded logs (memory against llvm-size and memory.x, real-time factor,
# fault reactions, boot failure) are `camsim firmware-check` (host-sim/src/firmware_log.rs):
# this script builds, runs QEMU, decodes and calls it.
echo "firmware-ci: build the host checker (camsim)"
cargo build -q --release -p camsim
check() { "$CAMSIM" firmware-check --memory-x memory.x --llvm-size "$LLVM_SIZE" "$@"; }

# The real board's build (defmt over RTT, panic-probe): it must compile and fit; it is
# not run (no probe here). Built first: it shares the target directory with the QEMU build.
echo "firmware-ci: build the real-board image (release, --no-default-features --features rtt)"
(cd firmware && cargo build --release --no-default-features --features rtt)
check --fits "$PREDICTOR_ELF" --fits "$BUDGET_ELF" || fail "real-board image (rtt): see the line above"

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
# Runs both binaries (demonstration image log $1, budget log $2) and checks their lines.
run_and_check() {
    local log=$1 budget_log=$2
    shift 2
    run_qemu "$PREDICTOR_ELF" "$log"
    run_qemu "$BUDGET_ELF" "$budget_log"
    check --product "$log" "$PREDICTOR_ELF" --budget "$budget_log" "$BUDGET_ELF" "$@" \
        || fail "firmware checks: see the line above"
    # The same checks' JSON beside the log, for the tables of docs/FIRMWARE.md (scripts/bench-doc.py).
    check --json --product "$log" "$PREDICTOR_ELF" --budget "$budget_log" "$BUDGET_ELF" "$@" \
        >"${log%.log}.json" || fail "firmware checks (--json): see the line above"
}
run_and_check "$LOG" "$BUDGET_LOG"

# ---------------------------------------------------------------------------
# A solver failure at boot: the demonstration image's boot (board::qemu::boot_or_stop) with an
# impossible step budget must report the error and stop with the alarm asserted.
# ---------------------------------------------------------------------------
echo "firmware-ci: boot failure (boot_fault: the demonstration image's boot with 1 solver step per revolution)"
run_qemu "$BOOT_FAULT_ELF" "$BOOT_FAULT_LOG" 1
check --boot-fault "$BOOT_FAULT_LOG" || fail "boot_fault: see the line above"

# ---------------------------------------------------------------------------
# No panic on the chip: every panic call site of the release predictor ELF lies in the
# logging transport. The lister must see them: with nothing allowed it counts them all.
# ---------------------------------------------------------------------------
# shellcheck source=scripts/panic-sites.sh
source scripts/panic-sites.sh
echo "firmware-ci: panic call sites in $PREDICTOR_ELF (responsible code <- file:line (in the function holding the call))"
panic_sites "$PREDICTOR_ELF" "$TRANSPORT_ORIGINS"
[ "$PANIC_OUTSIDE" -eq 0 ] || fail "$PANIC_OUTSIDE panic call site(s) of the demonstration image outside the logging transport (listed above)"
[ "$PANIC_TOTAL" -gt 0 ] || fail "no panic call site found: the transport has 6; is the lister broken?"
panic_sites "$PREDICTOR_ELF" >/dev/null
[ "$PANIC_OUTSIDE" -eq "$PANIC_TOTAL" ] || fail "the panic lister's filter is broken"
echo "firmware-ci: demonstration image panic call sites: $PANIC_TOTAL, all in the logging transport"

# ---------------------------------------------------------------------------
# HOST PARITY CHECK: the host runs the same f32 scene through the same core code
# (`camsim predict --f32`) and compares every `parity ...` line of the log (table,
# jump onset, interpolation checks, every sample's margins, timing errors and alarm
# state, as raw f32 bits) bit for bit; it fails with a one-line error on a mismatch.
# ---------------------------------------------------------------------------
echo "firmware-ci: host parity (camsim predict --f32 --check-log $LOG)"
"$CAMSIM" predict --f32 --check-log "$LOG" || fail "host parity: see the line above"

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
run_and_check "$SCENE_LOG" "$SCENE_BUDGET_LOG" --scene "$SCENE_NAME"
"$CAMSIM" predict --f32 --scene "$SCENE" --check-log "$SCENE_LOG" || fail "host parity (scene): see the line above"
# ---------------------------------------------------------------------------
# A measured cam profile compiled in (CAMSIM_PROFILE): firmware/build.rs reads the CSV with
# the host's reader (camsim_scene_file::measured), turns it into the deviation knots on the
# design, narrows them to f32 and compiles them into flash; the demonstration image splines them at
# boot and builds its table with the roller on that cam. Only that image carries it (the
# budget probes do not: see docs/FIRMWARE.md). Checked: the run, its memory against
# llvm-size and memory.x, the fault reactions, the panic sites, and host parity with
# `camsim predict --f32 --measured` (the same reader, knots, narrowing and spline).
# ---------------------------------------------------------------------------
PROFILE=scenes/measured-wavy.csv
PROFILE_NAME=$(basename "$PROFILE")
PROFILE_LOG=target/firmware-run-profile.log
echo "firmware-ci: build-time measured profile $PROFILE (demonstration image)"
PROFILE_PATH="$PWD/$PROFILE"   # absolute: build.rs runs in firmware/
(cd firmware && CAMSIM_PROFILE="$PROFILE_PATH" cargo build --release --bin predictor)
run_qemu "$PREDICTOR_ELF" "$PROFILE_LOG"
check --product "$PROFILE_LOG" "$PREDICTOR_ELF" --profile "$PROFILE_NAME" \
    || fail "profile image: see the line above"
check --json --product "$PROFILE_LOG" "$PREDICTOR_ELF" --profile "$PROFILE_NAME" \
    >"${PROFILE_LOG%.log}.json" || fail "profile image (--json): see the line above"
panic_sites "$PREDICTOR_ELF" "$TRANSPORT_ORIGINS"
[ "$PANIC_OUTSIDE" -eq 0 ] || fail "$PANIC_OUTSIDE panic call site(s) of the profile image outside the logging transport (listed above)"
"$CAMSIM" predict --f32 --measured "$PROFILE" --check-log "$PROFILE_LOG" \
    || fail "host parity (measured profile): see the line above"

# Leave the default (reference) firmware built, as a plain `cargo build` would.
(cd firmware && cargo build --release)

echo "firmware-ci: OK"
