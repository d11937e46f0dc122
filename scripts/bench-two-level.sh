#!/usr/bin/env bash
# The two-level Monte Carlo against the full model (issue 34): N actual cams of the reference
# design at 800 and 880 rpm on 2 threads, `camsim montecarlo` on the full model and
# `camsim montecarlo --two-level N/10` (docs/MODEL.md §9.7). Prints the Markdown rows of
# docs/BENCHMARKS.md ("Two-level Monte Carlo"): both answers for P(jump) with their 95 %
# intervals, the wall time of each as the command reports it, and whether the two-level
# estimate lies in the full model's interval, with the machine's core count and load.
#
#   bash scripts/bench-two-level.sh                  # 10 000 cams (about 30 minutes on 2 loaded cores)
#   bash scripts/bench-two-level.sh --samples 2000   # fewer cams
#   bash scripts/bench-two-level.sh --interval-deg 5 # cams cut on 5° intervals: some jump
set -euo pipefail
cd "$(dirname "$0")/.."
SAMPLES=10000
CAMS=()
while [ $# -gt 0 ]; do
    case "$1" in
    --samples)
        SAMPLES="${2:?--samples needs a number}"
        shift 2
        ;;
    --interval-deg)
        CAMS=(--interval-deg "${2:?--interval-deg needs a number}")
        shift 2
        ;;
    *)
        printf 'bench-two-level.sh: unknown argument %s (--samples N, --interval-deg D)\n' "$1" >&2
        exit 2
        ;;
    esac
done
case "$SAMPLES" in
'' | *[!0-9]*)
    printf 'bench-two-level.sh: --samples %s: must be a whole number of at least 20\n' "$SAMPLES" >&2
    exit 2
    ;;
esac
if [ "$SAMPLES" -lt 20 ]; then
    printf 'bench-two-level.sh: --samples %s: must be a whole number of at least 20\n' "$SAMPLES" >&2
    exit 2
fi
FULL_N=$((SAMPLES / 10))
cargo build --release -q -p camsim
C="$(bash scripts/camsim-bin.sh)"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
printf 'machine: %s cores, load average %s\n\n' "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)"
printf '| rpm | cams | full model: P(jump) [95 %%] | time, s | two-level (%s on the full model): P(jump) [95 %%] | time, s | in the full interval |\n' "$FULL_N"
printf '|---|---|---|---|---|---|---|\n'
for rpm in 800 880; do
    "$C" montecarlo --samples "$SAMPLES" --rpm "$rpm" --threads 2 "${CAMS[@]}" --two-level 0 --json >"$WORK/full.json"
    "$C" montecarlo --samples "$SAMPLES" --rpm "$rpm" --threads 2 "${CAMS[@]}" --two-level "$FULL_N" --json >"$WORK/two.json"
    full=$(jq -r '.summary.jump | "\(.p * 10000 | round / 10000) [\(.lo95 * 10000 | round / 10000), \(.hi95 * 10000 | round / 10000)]"' "$WORK/full.json")
    two=$(jq -r '.two_level.jump | "\(.value * 10000 | round / 10000) [\(.lo95 * 10000 | round / 10000), \(.hi95 * 10000 | round / 10000)]"' "$WORK/two.json")
    inside=$(jq -rn --slurpfile f "$WORK/full.json" --slurpfile t "$WORK/two.json" \
        '($t[0].two_level.jump.value) as $v | if $f[0].summary.jump.lo95 <= $v and $v <= $f[0].summary.jump.hi95 then "yes" else "no" end')
    printf '| %s | %s | %s | %.1f | %s | %.1f | %s |\n' "$rpm" "$SAMPLES" "$full" \
        "$(jq '.timing.wall_s' "$WORK/full.json")" "$two" "$(jq '.timing.wall_s' "$WORK/two.json")" "$inside"
done
