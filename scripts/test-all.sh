#!/usr/bin/env bash
# Runs every camsim test on a fresh machine: installs what it lacks (idempotent),
# builds the no_std core for the Cortex-M4F, runs the workspace tests, then builds
# the firmware (product and budget binaries, and the real-board rtt build), runs it under
# QEMU and checks its memory and budget lines against llvm-size and memory.x, and host parity.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n==> %s\n' "$*"; }

step "install what is missing"
for comp in rustfmt clippy; do
    if ! rustup component list --installed | grep -q "^$comp"; then
        rustup component add "$comp"
    fi
done
if ! rustup target list --installed | grep -qx thumbv7em-none-eabihf; then
    rustup target add thumbv7em-none-eabihf
fi
if ! command -v qemu-system-arm >/dev/null 2>&1; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq qemu-system-arm >/dev/null
fi
if ! command -v defmt-print >/dev/null 2>&1; then
    cargo install defmt-print --locked
fi
if ! command -v llvm-size >/dev/null 2>&1 && ! command -v llvm-size-14 >/dev/null 2>&1; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq llvm-14 >/dev/null
fi

step "gates: format, lints (warnings denied), docs"
cargo fmt --all -- --check
(cd firmware && cargo fmt -- --check)
cargo clippy --workspace --all-targets -- -D warnings
# core outside its tests: no unwrap, expect, panic or unchecked indexing on any input.
cargo clippy -p camsim-core --lib -- -D warnings -D clippy::indexing_slicing \
    -D clippy::unwrap_used -D clippy::expect_used -D clippy::panic
cargo clippy -p camsim-core --lib --features micromath -- -D warnings -D clippy::indexing_slicing \
    -D clippy::unwrap_used -D clippy::expect_used -D clippy::panic
(cd firmware && cargo clippy --release -- -D warnings)
# the real-board build (defmt over RTT, panic-probe); scripts/firmware-ci.sh builds it too
(cd firmware && cargo clippy --release --no-default-features --features rtt -- -D warnings)
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace

step "core builds no_std for thumbv7em-none-eabihf (libm, and micromath)"
cargo build -p camsim-core --release --target thumbv7em-none-eabihf
cargo build -p camsim-core --release --target thumbv7em-none-eabihf --features micromath

step "workspace tests"
cargo test --workspace
cargo test -p camsim-core --features micromath

step "bench --quick (run time against error, a few points; full runs in BENCHMARKS.md)"
cargo run --release -q -p camsim -- bench --quick
step "studies in release: a small Monte Carlo and compare --quick (exit status, JSON)"
cargo build --release -p camsim
studies=$(mktemp -d)
./target/release/camsim montecarlo --samples 8 --json > "$studies/montecarlo.json"
./target/release/camsim compare --quick --json > "$studies/compare.json"
# The reduced scenes against the full model (README, "Reduced scenes"): every scene that
# claims the jump onset within 1 % of the full model's does so.
./target/release/camsim scenes --quick --json > "$studies/scenes.json"
if command -v jq >/dev/null 2>&1; then
    jq -e '.summary.samples == 8 and (.summary.jump.p | type == "number")' "$studies/montecarlo.json" >/dev/null
    jq -e '(.laws | length) == 12 and all(.laws[]; .ranks.overall >= 1)' "$studies/compare.json" >/dev/null
    jq -e '(.rows | length) == 12 and all(.rows[]; (.ok_onset | not) or ((.onset_err_pct | fabs) <= 1 and (.model_onset_err_pct | fabs) <= 1))
           and any(.rows[]; .scene == "quasi-static-rod" and .rtol == 0.01 and .ok_onset)' "$studies/scenes.json" >/dev/null
else
    python3 -m json.tool "$studies/montecarlo.json" >/dev/null
    python3 -m json.tool "$studies/compare.json" >/dev/null
    python3 -m json.tool "$studies/scenes.json" >/dev/null
fi
# The drawing and the scene-taking commands (issue 17): profile --out/--plot (and its
# surface read back by run --measured), modal/contact/predict SCENE, jump-speed --actual.
./target/release/camsim scene --default > "$studies/ref.toml"
./target/release/camsim profile "$studies/ref.toml" --out "$studies/cam" --plot "$studies/cam" \
    --cutter-radius 0.5 --units in --json > "$studies/profile.json"
./target/release/camsim profile --actual --seed 3 --units mm --json > "$studies/profile-actual.json"
./target/release/camsim run --measured "$studies/cam/surface_radius.csv" --revolutions 1 --json > "$studies/roundtrip.json"
./target/release/camsim modal "$studies/ref.toml" --json > "$studies/modal.json"
./target/release/camsim contact "$studies/ref.toml" --force 50 --json > "$studies/contact.json"
./target/release/camsim predict "$studies/ref.toml" --json > "$studies/predict.json"
./target/release/camsim jump-speed --actual --samples 2 --threads 2 --follower quasi-static-rod \
    --resolution 20 --json > "$studies/jump-actual.json"
for f in profile profile-actual roundtrip modal contact predict jump-actual; do
    python3 -m json.tool "$studies/$f.json" >/dev/null
done
python3 -c "import json,sys; p=json.load(open(sys.argv[1])); r=json.load(open(sys.argv[2]));
assert r['profile']['max_abs_deviation_in'] <= p['chord_error_bound'], (r['profile'], p['chord_error_bound'])" \
    "$studies/profile.json" "$studies/roundtrip.json"
rm -rf "$studies"
step "fuzz each target for 20 s (scene parser, measured profile, core model; fuzz/README.md)"
bash scripts/fuzz.sh 20

if [ -x scripts/firmware-ci.sh ]; then
    step "firmware under QEMU"
    scripts/firmware-ci.sh
fi
step "real-board image (Nucleo-F446RE, no hardware): build, budget, panic call sites"
bash scripts/board-ci.sh
