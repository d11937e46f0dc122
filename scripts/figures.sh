#!/usr/bin/env bash
# Prints every figure README.md and firmware/README.md quote, with the command that
# produces it, so a change that moves the physics is followed by one run of this script
# and a copy of what it prints (a stale figure is a defect).
#
#   bash scripts/figures.sh            # host figures (a few minutes: bench is most of it)
#   bash scripts/figures.sh --firmware # also the firmware's product/budget lines (QEMU)
#
# Timings are of the machine it runs on; run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo build --release -q -p camsim
# The binary where cargo put it (CARGO_TARGET_DIR or a config may move the target directory).
C="$(cargo metadata --format-version 1 --no-deps |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')/release/camsim"

show() {
    printf '\n$ camsim %s\n' "$*"
    "$C" "$@"
}

show run
for _ in 1 2; do "$C" run | grep '^run time'; done
show run --start static
show jump-speed
show jump-speed scenes/stable-4567-rise.toml
show jump-speed scenes/listed-spring-60.toml
show jump-speed scenes/undamped-printed.toml
show run scenes/undamped-printed.toml
show run --actual --seed 1
show run --actual --seed 1 --profile-method envelope
show run --actual --seed 1 --interval criteria
# docs/MODEL.md §9.6: FPR against the interval, both methods, and the criteria.
show waviness
# docs/MODEL.md §8.4: the thesis's method against the envelope, same seed.
for d in 2 0.5 0.25 0.1; do
    for tol in "" "--roller-tolerance 0 --eccentricity-tolerance 0"; do
        for m in thesis envelope; do
            # shellcheck disable=SC2086
            printf '%s deg, %s, [%s]: %s\n' "$d" "$m" "$tol" "$("$C" run --revolutions 1 --actual --seed 1 \
                --interval-deg "$d" --profile-method "$m" $tol | grep 'lift deviation')"
        done
    done
done
show laws
show modal
show contact --force 100
show predict --f32
show bench --quick
show models
# The studies at the default waviness (FPR 17) and the thesis's rougher cams (39, 57): README,
# "Studies" (a few minutes on 2 cores).
show compare
for scene in "" scenes/stable-4567-rise.toml; do
    for f in 17 39 57; do
        # shellcheck disable=SC2086
        printf '\n$ camsim montecarlo %s --samples 200 --waviness-fpr %s\n' "$scene" "$f"
        "$C" montecarlo $scene --samples 200 --waviness-fpr "$f" | grep -E '^profile:|FPR|jump anywhere|run time'
    done
done
show tolerance-study
# README "The sensitivity study": the groups of VI.4.3 and every key's elasticity (a few minutes).
show sensitivity --per-key

if [ "${1:-}" = "--firmware" ]; then
    printf '\n$ bash scripts/firmware-ci.sh\n'
    bash scripts/firmware-ci.sh | grep -E '(product|budget) flash_bytes=|jump_onset_rpm|parity OK|firmware-ci: OK|flash +=|static RAM ='
fi
