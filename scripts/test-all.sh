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
# GNU parallel runs the sharded Monte Carlo study of the smoke step (Debian's `parallel`).
if ! command -v parallel >/dev/null 2>&1; then
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq parallel >/dev/null
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
# Function length: core and chip at most 100 lines, host-sim and scene-file at most 80,
# firmware at most 100, except data tables; today's longer host, scene-file and firmware
# functions are a ratchet (scripts/longest-fns.allowed: they may shrink, not grow).
bash scripts/longest-fns.sh --check
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace

step "core builds no_std for thumbv7em-none-eabihf (libm, and micromath)"
cargo build -p camsim-core --release --target thumbv7em-none-eabihf
cargo build -p camsim-core --release --target thumbv7em-none-eabihf --features micromath

step "workspace tests"
cargo test --workspace
cargo test -p camsim-core --features micromath

step "every camsim command in release (smoke: exit status 0; with --json valid JSON, no null)"
cargo build --release -p camsim
# docs/CLI.md is generated from every command's --help: a synopsis that went stale fails here
# (regenerate with `bash scripts/cli-doc.sh`).
bash scripts/cli-doc.sh --check
# Every output block the docs quote beside a FIGURES.md link is still in FIGURES.md.
python3 scripts/check-quotes.py
# The measured tables of BENCHMARKS.md and FIRMWARE.md match the JSON they are generated from
# (docs/bench/*.json; regenerate with `python3 scripts/bench-doc.py`).
python3 scripts/bench-doc.py --check
studies=$(mktemp -d)
# The growth plot scripts/growth.sh draws, from the checked-in measurements.
cargo run --release -q -p camsim --example growth_plot -- docs/growth.csv "$studies/growth.png"
test -s "$studies/growth.png"
# The binary where cargo put it (scripts/camsim-bin.sh).
C="$(bash scripts/camsim-bin.sh)"
# A report never prints null (an absent value is left out, NaN or an infinity is an error):
# every --json output is parsed and searched for null.
check_json() {
    if command -v jq >/dev/null 2>&1; then
        jq -e '[.. | select(. == null)] | length == 0' "$1" >/dev/null \
            || { echo "smoke: $1 is not valid JSON or has a null" >&2; return 1; }
    else
        python3 -c '
import json, sys
def nulls(v, p):
    if v is None:
        yield p
    elif isinstance(v, dict):
        for k, x in v.items():
            yield from nulls(x, p + "." + k)
    elif isinstance(v, list):
        for i, x in enumerate(v):
            yield from nulls(x, p + "[%d]" % i)
found = list(nulls(json.load(open(sys.argv[1])), ""))
sys.exit("smoke: %s has null at %s" % (sys.argv[1], ", ".join(found[:5])) if found else 0)
' "$1"
    fi
}
# smoke NAME ARGS...: runs camsim ARGS (exit status 0 or the step fails), checks the JSON.
smoke() {
    local name=$1
    shift
    echo "smoke: camsim $*"
    "$C" "$@" > "$studies/$name.out"
    case " $* " in *" --json "*) check_json "$studies/$name.out" ;; esac
}
smoke laws laws --json
smoke modal modal --json
smoke contact contact --force 100 --json
smoke run run --revolutions 2 --json
smoke run-thesis-control run --revolutions 1 --step-control thesis --json
grep -qF 'step_control = \"thesis\"' "$studies/run-thesis-control.out" || { echo "smoke: run --step-control thesis is not echoed in the scene" >&2; exit 1; }
smoke run-csv run --revolutions 1 --csv "$studies/run-grid.csv" --csv-every-deg 1 --json
test "$(wc -l < "$studies/run-grid.csv")" -eq 362 || { echo "smoke: run --csv-every-deg 1 is not 360 rows and the end" >&2; exit 1; }
smoke run-csv-steps run --revolutions 1 --csv "$studies/run-steps.csv" --csv-every-step --json
smoke run-actual run --actual --revolutions 2 --json
jq -e '.profile.method == "per-cam" and (.profile.axis_offset_in | type == "number")' "$studies/run-actual.out" >/dev/null || { echo "smoke: run --actual does not default to the per-cam method" >&2; exit 1; }
smoke run-actual-thesis run --actual --revolutions 2 --profile-method thesis --json
smoke jump-speed jump-speed --resolution 10 --json
smoke scene scene --default
smoke scene-json scene --default --json --units si
# Issue 30: scene --new writes a template that reads back (scene --check lists where each
# value comes from: the file, derived, the reference) and runs, in either family.
smoke scene-new scene --new
smoke scene-new-si scene --new --units si
smoke scene-new-check scene --check "$studies/scene-new-si.out" --units si
grep -qF '# derived:' "$studies/scene-new-check.out" && grep -qF 'design.load_mass_kg = ' "$studies/scene-new-check.out" && grep -qF '# inherited from the reference design' "$studies/scene-new-check.out" || { echo "smoke: scene --check does not list the derived and inherited values" >&2; exit 1; }
smoke scene-new-run run "$studies/scene-new.out" --revolutions 1 --json
# A motor drive in a designer's terms: its gain is derived into the regulated drive's k_p.
printf '[design.drive.motor]\ngain_n_m_s_per_rad = 9.3\n' > "$studies/motor.toml"
smoke scene-motor-check scene --check "$studies/motor.toml" --units si
grep -qF '(from design.drive.motor.gain_n_m_s_per_rad: ' "$studies/scene-motor-check.out" || { echo "smoke: scene --check does not list the motor's gain as derived" >&2; exit 1; }
grep -qF '"moving_mass_lb": 4.5,' "$studies/scene-new-run.out" || { echo "smoke: run of scene --new's template does not move its 4.5 lb" >&2; exit 1; }
smoke run-si run --revolutions 1 --json --units si
smoke run-si-text run --revolutions 1 --units si
# An option given with its unit under --units si (a bare number there is refused).
smoke run-si-unit run --revolutions 1 --units si --spring-rate 35N/mm --preload-length 10mm
grep -q '^  spring:    35.00 N/mm' "$studies/run-si-unit.out" && grep -q 'preload F_p = 349.9. N' "$studies/run-si-unit.out" || { echo "smoke: run --spring-rate 35N/mm --preload-length 10mm does not run that spring (35 N/mm, about 350 N of preload)" >&2; exit 1; }
# The scene in SI keys reads back (scene --check) and runs; bench's text and plots in SI.
smoke scene-si scene --default --units si
"$C" scene --check "$studies/scene-si.out" > /dev/null
grep -q '^base_radius_mm = 38.1 ' "$studies/scene-si.out" || { echo "smoke: scene --units si does not write base_radius_mm" >&2; exit 1; }
# A scene in SI keys without --units answers in SI (its units line in mm and N).
smoke run-si-scene run "$studies/scene-new-si.out" --revolutions 1
grep -q '^units: mm, N, ' "$studies/run-si-scene.out" || { echo "smoke: run of an SI scene without --units does not answer in mm and N" >&2; exit 1; }
smoke bench-si bench --quick --repeat 1 --units si --plot "$studies/bench-si"
for f in error_vs_evals.png error_vs_time.png error_vs_cpu_time.png; do
    test -s "$studies/bench-si/$f" || { echo "smoke: bench --plot wrote no $f" >&2; exit 1; }
done
"$C" scene --check scenes/stable-4567-rise.toml > /dev/null
smoke bench bench --quick --json
smoke models models --quick --json
smoke predict predict --json
smoke montecarlo montecarlo --samples 8 --json
# The two-level estimate (issue 34): every cam on the reduced model, 4 on the full one too.
smoke montecarlo-two-level montecarlo --samples 8 --two-level 4 --threads 2 --json
# The same kind of study as 2 shards under GNU parallel, merged: the result is the
# single-process run's bit for bit (every number as printed; only the timing differs).
smoke montecarlo-single montecarlo --samples 12 --seed 5 --json
parallel --will-cite --halt now,fail=1 "$C" montecarlo --samples 12 --seed 5 --shard {}/2 \
    --out "$studies/mc-shard-{}.json" --json ::: 1 2 > /dev/null
smoke montecarlo-merged montecarlo merge "$studies/mc-shard-1.json" "$studies/mc-shard-2.json" --json
python3 -c '
import json, sys
def study(f):
    d = json.load(open(f), parse_float=str)
    d.pop("timing", None)
    return d
a, b = study(sys.argv[1]), study(sys.argv[2])
sys.exit(0 if a == b else "smoke: montecarlo merge of 2 shards under GNU parallel differs from the single run")
' "$studies/montecarlo-single.out" "$studies/montecarlo-merged.out"
smoke montecarlo-one-model montecarlo --samples 4 --two-level 0 --json
smoke compare compare --quick --json
# An unworkable law (its run leaves the model's valid range) is named and the rest ranked:
# seed 4's actual cam (the thesis's per-point method) throws the straight-line follower off the cam (issue 31).
smoke compare-unworkable compare --seed 4 --profile-method thesis --json
smoke tolerance-study tolerance-study --quick --json
# The study plots in SI (every axis converts through units.rs): the tolerance plots, the
# Monte Carlo histograms and compare's charts.
smoke tolerance-plot-si tolerance-study --quick --plot "$studies/tol-si" --units si --json
for f in tolerance_grid.png tolerance_response.png; do
    test -s "$studies/tol-si/$f" || { echo "smoke: tolerance-study --plot wrote no $f" >&2; exit 1; }
done
smoke montecarlo-plot-si montecarlo --samples 8 --plot "$studies/mc-si" --units si --json
# The studies' text in SI (issue 18): montecarlo's tables and design's answer in mm, N.
smoke montecarlo-si-text montecarlo --samples 8 --units si
grep -qF '  rms_a, mm/s^2 ' "$studies/montecarlo-si-text.out" || { echo "smoke: montecarlo --units si prints no mm/s^2 column" >&2; exit 1; }
smoke design-si-text design spring --quick --units si
grep -q '^  spring to build: ' "$studies/design-si-text.out" && grep -q '^      wire_diameter_mm = ' "$studies/design-si-text.out" || { echo "smoke: design spring --units si does not give a spring to build in mm" >&2; exit 1; }
# [design.spring]: a spring given as a part (SI keys) runs, and the verdict judges its stress and solid height.
printf '[design.spring]\nwire_diameter_mm = 6.3\nmean_diameter_mm = 63\nactive_coils = 3.25\nmaterial = "music-wire"\nfree_length_mm = 91.5\n' > "$studies/spring-part.toml"
smoke run-spring-part run "$studies/spring-part.toml" --revolutions 2 --units si
grep -q '^             \[design.spring\]: wire 6.30 mm, mean coil 63.00 mm' "$studies/run-spring-part.out" && grep -q 'shear stress .* MPa (Wahl)' "$studies/run-spring-part.out" && grep -q 'not solid' "$studies/run-spring-part.out" || { echo "smoke: run with [design.spring] does not judge the part" >&2; exit 1; }
smoke design-spring-si-json design spring --quick --json --units si
grep -q '"rates_tried_n_per_mm"' "$studies/design-spring-si-json.out" || { echo "smoke: design spring --json --units si does not name the tried rates' unit" >&2; exit 1; }
grep -qE '^camsim design spring: [0-9.]+ N/mm at preload length 12.7 mm' "$studies/design-si-text.out" || { echo "smoke: design spring --units si does not answer in N/mm and mm" >&2; exit 1; }
smoke compare-plot compare --quick --plot "$studies/compare" --json
smoke waviness waviness --seeds 1 --json
smoke waviness-measured waviness --measured scenes/measured-wavy.csv --json
jq -e '.fpr == 30 and .waviness_fpr == 30 and (.equivalent_tolerance_in > 0)' "$studies/waviness-measured.out" >/dev/null || { echo "smoke: waviness --measured does not report scenes/measured-wavy.csv's FPR 30" >&2; exit 1; }
smoke sensitivity sensitivity --quick --json
# The drawing and the scene-taking commands (issue 17): profile --out/--plot (and its
# surface read back by run --measured), modal/contact/predict SCENE, jump-speed --actual.
"$C" scene --default > "$studies/ref.toml"
smoke profile profile "$studies/ref.toml" --out "$studies/cam" --plot "$studies/cam" \
    --cutter-radius 0.5 --units inch --json
smoke profile-actual profile --actual --seed 3 --units si --json
smoke roundtrip run --measured "$studies/cam/surface_radius.csv" --revolutions 1 --json
smoke profile-si profile "$studies/ref.toml" --out "$studies/cam-si" --units si --json
grep -qx 'angle_deg,radius_mm' "$studies/cam-si/surface_radius.csv" || { echo "smoke: profile --units si does not write radius_mm" >&2; exit 1; }
smoke roundtrip-si run --measured "$studies/cam-si/surface_radius.csv" --revolutions 1 --json
smoke profile-every profile "$studies/ref.toml" --out "$studies/cam-deg" --every-deg 1 --units si --json
jq -e '.every_deg == 1' "$studies/profile-every.out" >/dev/null || { echo "smoke: profile --every-deg 1 does not report its step" >&2; exit 1; }
smoke roundtrip-every run --measured "$studies/cam-deg/surface_radius.csv" --revolutions 1 --json
smoke modal-scene modal "$studies/ref.toml" --json
smoke contact-scene contact "$studies/ref.toml" --force 50 --json
smoke predict-scene predict "$studies/ref.toml" --json
smoke jump-actual jump-speed --actual --samples 2 --threads 2 --follower quasi-static-rod \
    --resolution 20 --json
python3 -c "import json,sys; p=json.load(open(sys.argv[1])); r=json.load(open(sys.argv[2]));
assert r['profile']['max_abs_deviation_in'] <= p['chord_error_bound_in'], (r['profile'], p['chord_error_bound_in'])" \
    "$studies/profile.out" "$studies/roundtrip.out"
python3 -c "import json,sys; i=json.load(open(sys.argv[1]))['profile']; s=json.load(open(sys.argv[2]))['profile'];
assert abs(i['max_abs_deviation_in'] - s['max_abs_deviation_in']) <= 1e-4, (i, s)" \
    "$studies/roundtrip.out" "$studies/roundtrip-si.out"
smoke design design spring --quick --json
smoke design-actual design spring --actual --quick --json
smoke design-speed design speed --quick --json
jq -e '(.speeds_tried_rpm | length > 0) and (has("tried") | not)' "$studies/design-speed.out" >/dev/null || { echo "smoke: design speed's tried speeds do not name their unit (speeds_tried_rpm)" >&2; exit 1; }
smoke design-tolerance design tolerance --quick --json
jq -e 'all(.[]; (.tolerance_factors_tried | length > 0) and (has("tried") | not))' "$studies/design-tolerance.out" >/dev/null || { echo "smoke: design tolerance's tried factors do not name their unit (tolerance_factors_tried)" >&2; exit 1; }
smoke design-preload design spring --preload --quick --json
smoke design-waviness design tolerance --waviness --quick --json
jq -e 'all(.[]; (.waviness_fprs_tried | length > 0) and (has("tried") | not))' "$studies/design-waviness.out" >/dev/null || { echo "smoke: design tolerance --waviness's tried FPRs do not name their unit" >&2; exit 1; }
smoke design-tolerance-fprs design tolerance --waviness-fpr 17,57 --quick --json
smoke sweep sweep --rpm 700:1000:4 --csv "$studies/sweep.csv" --plot "$studies/sweep" --json
smoke sweep-actual sweep --rpm 850:950:3 --actual --samples 4 --threads 2 --json
smoke laws-plot laws --plot "$studies/laws"
# Standard output and the stack on the binary itself (issue 33): --version and --help into
# a full disk fail, a closed pipe on --csv /dev/stdout ends quietly, a 256 KiB main stack runs.
! "$C" --version > /dev/full 2> /dev/null || { echo "smoke: camsim --version > /dev/full exits 0" >&2; exit 1; }
! "$C" --help > /dev/full 2> /dev/null || { echo "smoke: camsim --help > /dev/full exits 0" >&2; exit 1; }
"$C" run --revolutions 1 --csv /dev/stdout 2> "$studies/pipe.err" | head -c 100 > /dev/null \
    && ! test -s "$studies/pipe.err" || { echo "smoke: camsim run --csv /dev/stdout | head -c 100 does not end quietly" >&2; exit 1; }
(ulimit -s 256 && exec "$C" run --revolutions 1 > /dev/null) || { echo "smoke: camsim run under ulimit -s 256 fails" >&2; exit 1; }
# Every command camsim lists is smoke-tested above (a new command must be added here).
for c in $("$C" --help | awk '/^Commands:/{on=1; next} on && /^  [a-z]/{print $1} /^$/{on=0}'); do
    # firmware-check reads the firmware's QEMU logs: the firmware step below runs it.
    case "$c" in help | firmware-check) continue ;; esac
    [ -e "$studies/$c.out" ] || { echo "smoke: camsim $c is not smoke-tested in scripts/test-all.sh" >&2; exit 1; }
done
if command -v jq >/dev/null 2>&1; then
    jq -e '.summary.samples == 8 and (.summary.jump | (.p | type == "number") and .lo95 <= .p and .p <= .hi95) and .two_level.full_samples == 8' "$studies/montecarlo.out" >/dev/null
    jq -e '.two_level == null and .study.one_model == "the full model alone (--two-level 0)"' "$studies/montecarlo-one-model.out" >/dev/null
    jq -e '.two_level.full_samples == 4 and (.two_level.jump | .lo95 <= .value and .value <= .hi95 and .value == ([0, ([1, .reduced + .correction] | min)] | max))' "$studies/montecarlo-two-level.out" >/dev/null
    jq -e '(.laws | length) == 12 and all(.laws[]; .ranks.overall >= 1)' "$studies/compare.out" >/dev/null
    jq -e '(.laws | length) == 11 and ([.not_workable[].name] == ["straight-line"]) and (.not_workable[0].reason | test("valid range"))' \
        "$studies/compare-unworkable.out" >/dev/null
    jq -e '(.rows | length) == 12 and all(.rows[]; (.ok_onset | not) or ((.onset_err_pct | fabs) <= 1 and (.model_onset_err_pct | fabs) <= 1))
           and any(.rows[]; .scene == "quasi-static-rod" and .rtol == 0.01 and .ok_onset)' "$studies/models.out" >/dev/null
    # VI.4.3's groups at +-30 % on both cams, a baseline per cam at change 0, every output a number.
    jq -e '(.baseline | length) == 2 and all(.baseline[]; .change_pct == 0) and (.cases | length) == 12
           and all(.baseline[], .cases[]; [.rms_displacement_in, .rms_velocity_in_per_s, .rms_acceleration_in_per_s2,
               .rms_angular_velocity_rad_per_s, .contact_stress_avg_psi] | all(type == "number" and . >= 0))
           and ([.cases[].group] | unique) == ["damping", "mass", "stiffness"]' "$studies/sensitivity.out" >/dev/null
    # The verdict opens run; each design search states its answer, bracket, runs and model.
    jq -e '.verdict.contact.holds == true and (.verdict.contact.min_contact_force_lb > 0)
           and (.verdict.loads.peak_contact_stress_psi > 0) and (.verdict.geometry.max_pressure_angle_deg > 0)' "$studies/run.out" >/dev/null
    jq -e '(.spring_rate_lb_per_in > 0) and (.bracket_lb_per_in >= 0) and (.model_runs > 0) and (.model | type == "string")
           and (.jump_onset_rpm > .checked_at_rpm)' "$studies/design.out" >/dev/null
    jq -e '(.spring_rate_lb_per_in > 0) and (.p_jump.hi95 <= 0.1) and .samples == 35' "$studies/design-actual.out" >/dev/null
    jq -e '(.cells | length) == 9 and all(.cells[]; (.fpr | type == "number") and .summary.jump.lo95 <= .summary.jump.hi95)' "$studies/tolerance-study.out" >/dev/null
fi
rm -rf "$studies"
step "fuzz each target for 20 s (scene parser, measured profile, core model; fuzz/README.md)"
bash scripts/fuzz.sh 20

if [ -x scripts/firmware-ci.sh ]; then
    step "firmware under QEMU"
    scripts/firmware-ci.sh
fi
step "real-board image (Nucleo-F446RE, no hardware): build, budget, panic call sites"
bash scripts/board-ci.sh
