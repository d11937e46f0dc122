#!/usr/bin/env bash
# Fuzzes camsim for a bounded time: the scene parser (scene_file), the measured-profile
# path (measured_profile) and the core's model with arbitrary parameters (core_rhs),
# with libFuzzer through cargo-fuzz (fuzz/, its own cargo workspace).
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]   each target for SECONDS (default 20, CI's)
#   scripts/fuzz.sh --minimize [TARGET...]  minimize the local corpus (no fuzzing)
#   scripts/fuzz.sh --seed                  rewrite the seed inputs from scenes/
#   scripts/fuzz.sh --list                  the targets
#
# The long run (fuzz/README.md): scripts/fuzz.sh 1800.
#
# Installs cargo-fuzz (pinned) and a C++ compiler when missing; idempotent. The toolchain
# is stable: cargo-fuzz passes -Zsanitizer=address, which stable rustc accepts under
# RUSTC_BOOTSTRAP=1 (set here for these builds only). FUZZ_SANITIZER=none builds without
# AddressSanitizer (faster; camsim's own code forbids unsafe, the sanitizer watches the
# dependencies'). Debug assertions are on (integer overflow is a finding).
#
# Corpus: the repository keeps fuzz/corpus/<target>/ (the seeds, written from scenes/ by
# fuzz/seed, and a few minimized inputs such as past findings); libFuzzer reads it and
# writes what it finds to fuzz/target/corpus/<target>/ (not committed, kept between
# local runs). A crash stops the run with a non-zero status, its input saved under
# fuzz/artifacts/<target>/ and the command that reproduces it printed.
set -euo pipefail
cd "$(dirname "$0")/.."

CARGO_FUZZ_VERSION=0.13.2
TARGETS=(scene_file measured_profile core_rhs)
export PATH="$HOME/.cargo/bin:$PATH"
export RUSTC_BOOTSTRAP=1

step() { printf '\n==> %s\n' "$*"; }

mode=fuzz
seconds=20
case "${1:-}" in
    --minimize) mode=minimize; shift ;;
    --seed) mode=seed; shift ;;
    --list) printf '%s\n' "${TARGETS[@]}"; exit 0 ;;
    -h | --help) sed -n '2,23p' "$0"; exit 0 ;;
    '') ;;
    *)
        if [[ "$1" =~ ^[0-9]+$ ]] && [ "$1" -gt 0 ]; then
            seconds=$1
            shift
        elif [[ "$1" == -* ]]; then
            echo "fuzz.sh: unknown option $1 (see --help)" >&2
            exit 2
        fi
        ;;
esac
if [ $# -gt 0 ]; then
    for t in "$@"; do
        if [[ ! " ${TARGETS[*]} " =~ " $t " ]]; then
            echo "fuzz.sh: no target $t (targets: ${TARGETS[*]})" >&2
            exit 2
        fi
    done
    TARGETS=("$@")
fi

if [ "$mode" = seed ]; then
    step "seed inputs from scenes/"
    (cd fuzz && cargo run --quiet --release -p camsim-fuzz-seed -- ..)
    git status --short fuzz/corpus
    exit 0
fi

step "install what is missing"
if ! command -v c++ >/dev/null 2>&1; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq g++ >/dev/null
fi
if ! cargo fuzz --version 2>/dev/null | grep -q " $CARGO_FUZZ_VERSION\$"; then
    cargo install cargo-fuzz --version "$CARGO_FUZZ_VERSION" --locked
fi

flags=(-O -a --sanitizer "${FUZZ_SANITIZER:-address}")
step "build the fuzz targets (cargo fuzz build ${flags[*]})"
cargo fuzz build "${flags[@]}"

if [ "$mode" = minimize ]; then
    for t in "${TARGETS[@]}"; do
        work=fuzz/target/corpus/$t
        [ -d "$work" ] || continue
        before=$(find "$work" -type f | wc -l)
        cargo fuzz cmin "${flags[@]}" "$t" "$work" >/dev/null 2>&1
        echo "fuzz $t: local corpus $before -> $(find "$work" -type f | wc -l) inputs"
    done
    exit 0
fi

summary=()
for t in "${TARGETS[@]}"; do
    step "fuzz $t for $seconds s"
    work=fuzz/target/corpus/$t
    log=fuzz/target/fuzz-$t.log
    mkdir -p "$work"
    status=0
    cargo fuzz run "${flags[@]}" "$t" "$work" "fuzz/corpus/$t" -- \
        -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 \
        >"$log" 2>&1 || status=$?
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    if [ "$status" -ne 0 ]; then
        # libFuzzer's report: the panic, the input, how to reproduce it.
        grep -v '^#[0-9]' "$log" | tail -60 >&2
        echo "fuzz $t: FAILED after ${runs:-?} executions (status $status; log $log)" >&2
        exit 1
    fi
    line="fuzz $t: ${runs:-?} executions in $seconds s, no crash; local corpus $(find "$work" -type f | wc -l) inputs"
    echo "$line"
    summary+=("$line")
done
step "summary"
printf '%s\n' "${summary[@]}"
