#!/usr/bin/env bash
# How camsim's run time grows (issue 21 point 6): with the revolutions simulated, the cam
# speed, the Monte Carlo samples and the worker threads. Prints Markdown tables of what it
# measured (wall time as each command reports it, and the solver's work), with the machine's
# core count and load, for docs/BENCHMARKS.md ("How the run time grows").
#
#   bash scripts/growth.sh          # samples up to 10 000 (a few minutes on 2 cores)
#   bash scripts/growth.sh --long   # also 100 000 samples (about 25 more minutes)
#
# Run it on a quiet machine: the times are of the machine it runs on. It also writes the
# measurements to docs/growth.csv and draws docs/growth.png from them
# (host-sim/examples/growth_plot.rs).
set -euo pipefail
cd "$(dirname "$0")/.."
LONG=0
for arg in "$@"; do
    case "$arg" in
    --long) LONG=1 ;;
    *)
        printf 'growth.sh: unknown argument %s (--long)\n' "$arg" >&2
        exit 2
        ;;
    esac
done
cargo build --release -q -p camsim
# The binary where cargo put it (scripts/camsim-bin.sh).
C="$(bash scripts/camsim-bin.sh)"

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
CSV="$WORK/growth.csv"
printf 'table,x,threads,value\n' >"$CSV"

# field JSON KEY: one top-level or dotted key of a JSON document on standard input.
field() {
    python3 -c 'import json, sys
v = json.load(sys.stdin)
for k in sys.argv[1].split("."):
    v = v[k]
print(v)' "$1"
}

printf 'Measured %s on commit %s, %s cores, load average %s (release build).\n\n' \
    "$(date -u +'%Y-%m-%d %H:%M UTC')" "$(git rev-parse --short HEAD)" "$(nproc)" \
    "$(cut -d' ' -f1-3 /proc/loadavg)"

printf '### Revolutions (full model, 800 rpm, static start)\n\n'
printf '`camsim run --start static --revolutions R --json`: `wall_ms`, `steps`, `rhs_evals`.\n\n'
printf '| revolutions | run time, ms | ms a revolution | steps | evaluations |\n| ---: | ---: | ---: | ---: | ---: |\n'
for r in 1 2 4 8 16; do
    j="$("$C" run --start static --revolutions "$r" --json)"
    ms="$(field wall_ms <<<"$j")"
    printf 'revolutions,%s,1,%s\n' "$r" "$ms" >>"$CSV"
    printf '| %s | %.1f | %.1f | %s | %s |\n' "$r" "$ms" "$(python3 -c "print($ms / $r)")" \
        "$(field steps <<<"$j")" "$(field rhs_evals <<<"$j")"
done

printf '\n### Cam speed (full model, static start, 2 revolutions)\n\n'
printf '`camsim run --start static --revolutions 2 --rpm RPM --json`.\n\n'
printf '| rpm | run time, ms | steps | evaluations | contact holds |\n| ---: | ---: | ---: | ---: | --- |\n'
for rpm in 300 600 900 1200; do
    # Past the jump the follower may be thrown out of the model's valid range: a refusal.
    if j="$("$C" run --start static --revolutions 2 --rpm "$rpm" --json 2>"$WORK/err")"; then
        printf 'rpm,%s,1,%s\n' "$rpm" "$(field wall_ms <<<"$j")" >>"$CSV"
        printf '| %s | %.1f | %s | %s | %s |\n' "$rpm" "$(field wall_ms <<<"$j")" "$(field steps <<<"$j")" \
            "$(field rhs_evals <<<"$j")" "$(field verdict.contact.holds <<<"$j")"
    else
        printf '| %s | — | — | — | refused: %s |\n' "$rpm" "$(sed 's/^camsim: error: //; s/|/\\|/g' "$WORK/err")"
        printf 'refused,%s,1,1\n' "$rpm" >>"$CSV"
    fi
done

MC=(montecarlo --follower quasi-static-cantilever --max-step-fraction 0.01 --rtol 1e-4 --atol 1e-8 --json)
printf '\n### Samples and threads (Monte Carlo at the default waviness, quasi-static cantilever)\n\n'
printf '`camsim montecarlo --samples N --threads T --follower quasi-static-cantilever --max-step-fraction 0.01 --rtol 1e-4 --atol 1e-8 --json`: `timing.wall_s`.\n\n'
printf '| samples | threads | wall time, s | samples/s | P(jump) |\n| ---: | ---: | ---: | ---: | ---: |\n'
SAMPLES="100 1000 10000"
[ "$LONG" = 1 ] && SAMPLES="$SAMPLES 100000"
for n in $SAMPLES; do
    for t in 1 2; do
        # One thread only up to 1 000 samples (the larger studies double its time).
        if [ "$t" = 1 ] && [ "$n" -gt 1000 ]; then continue; fi
        j="$("$C" "${MC[@]}" --samples "$n" --threads "$t" 2>/dev/null)"
        printf 'samples,%s,%s,%s\n' "$n" "$t" "$(field timing.wall_s <<<"$j")" >>"$CSV"
        printf '| %s | %s | %.2f | %.1f | %.4f |\n' "$n" "$t" "$(field timing.wall_s <<<"$j")" \
            "$(field timing.samples_per_s <<<"$j")" "$(field summary.jump.p <<<"$j")"
    done
done

printf '\n### The full model beside it (same study, 200 samples, 2 threads)\n\n'
j="$("$C" montecarlo --samples 200 --json 2>/dev/null)"
printf '`camsim montecarlo --samples 200 --json`: %.2f s, %.1f samples/s, P(jump) %.4f.\n' \
    "$(field timing.wall_s <<<"$j")" "$(field timing.samples_per_s <<<"$j")" "$(field summary.jump.p <<<"$j")"

# The plot of these measurements (docs/BENCHMARKS.md links it).
cp "$CSV" docs/growth.csv
cargo run --release -q -p camsim --example growth_plot -- docs/growth.csv docs/growth.png
printf '\nPlot: [growth.png](growth.png) (data: [growth.csv](growth.csv)).\n'
