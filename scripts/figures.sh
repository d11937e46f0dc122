#!/usr/bin/env bash
# Writes docs/FIGURES.md: every measured figure the docs quote, each under an anchor with the
# command that produced it and that command's output. The other docs link here
# ("docs/FIGURES.md#run") instead of copying a number, so a change that moves the physics is
# followed by one run of this script and a commit of the file (a stale figure is a defect).
#
#   bash scripts/figures.sh              # the quick host sections (about 2 minutes)
#   bash scripts/figures.sh --long       # also the studies, the design searches and the full bench
#   bash scripts/figures.sh --firmware   # also the firmware and board sections (QEMU, defmt-print)
#   bash scripts/figures.sh --all        # everything (15-25 minutes on 2 busy cores)
#   bash scripts/figures.sh --only run,jump-speed   # just these sections
#
# A section that is not run keeps its previous text (and its own date and commit line), so the
# file can be refreshed piecewise. Timings are of the machine it runs on: each section states
# the machine's core count and load average when it ran.
set -euo pipefail
cd "$(dirname "$0")/.."

LONG=0
FIRMWARE=0
ONLY=""
for arg in "$@"; do
    case "$arg" in
    --long) LONG=1 ;;
    --firmware) FIRMWARE=1 ;;
    --all) LONG=1 FIRMWARE=1 ;;
    --only=*) ONLY="${arg#--only=}" ;;
    --only) ONLY="next" ;;
    *)
        if [ "$ONLY" = next ]; then ONLY="$arg"; else
            printf 'figures.sh: unknown argument %s (--long, --firmware, --all, --only A,B)\n' "$arg" >&2
            exit 2
        fi
        ;;
    esac
done

cargo build --release -q -p camsim
# The binary where cargo put it (CARGO_TARGET_DIR or a config may move the target directory).
C="$(cargo metadata --format-version 1 --no-deps |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')/release/camsim"

OUT=docs/FIGURES.md
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
COMMIT="$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- . ':!docs/FIGURES.md' || echo '+changes')"
CURRENT=""

# want KIND NAME: whether the section NAME (quick, long or firmware) runs this time.
want() {
    if [ -n "$ONLY" ] && [ "$ONLY" != next ]; then
        case ",$ONLY," in *",$2,"*) return 0 ;; *) return 1 ;; esac
    fi
    case "$1" in
    quick) return 0 ;;
    long) [ "$LONG" = 1 ] ;;
    firmware) [ "$FIRMWARE" = 1 ] ;;
    esac
}

# begin NAME "Title" "what it is": opens a section (a transcript block follows).
begin() {
    CURRENT="$WORK/$1.md"
    printf '  figures: %s\n' "$1" >&2
    {
        printf '<!-- figure:%s -->\n' "$1"
        printf '<a id="%s"></a>\n\n## %s\n\n%s\n\n' "$1" "$2" "$3"
        printf 'Measured %s on commit %s, %s cores, load average %s (release build).\n\n' \
            "$(date -u +'%Y-%m-%d %H:%M UTC')" "$COMMIT" "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)"
        printf '```text\n'
    } >"$CURRENT"
}
end() {
    printf '```\n<!-- /figure -->\n' >>"$CURRENT"
}
# show ARGS...: runs camsim ARGS and records the command line and its whole output.
show() {
    printf '$ camsim %s\n' "$*" >>"$CURRENT"
    "$C" "$@" >>"$CURRENT" 2>&1
    printf '\n' >>"$CURRENT"
}
# filtered REGEX ARGS...: runs camsim ARGS and records only the lines matching REGEX.
filtered() {
    local re="$1"
    shift
    printf '$ camsim %s | grep -E %q\n' "$*" "$re" >>"$CURRENT"
    "$C" "$@" 2>&1 | grep -E "$re" >>"$CURRENT"
    printf '\n' >>"$CURRENT"
}
# Every section's name, in the order the file lists them.
ORDER="run run-static jump-speed run-undamped run-actual waviness profile-methods laws modal contact
profile predict bench-quick scenes compare tolerance-study montecarlo sensitivity design bench
firmware board"

if want quick run; then
    begin run "The reference design: \`camsim run\`" \
        "The built-in reference design (VI.1 with K_rs = 100 lb/in and the contact damping, docs/MODEL.md §6) at 800 rpm, 3 revolutions from the thesis's start: the verdict, revolution 2's table and the solver statistics; then the run time of two more runs."
    show run
    for _ in 1 2; do filtered '^run time' run; done
    end
fi
if want quick run-static; then
    begin run-static "From static equilibrium: \`camsim run --start static\`" \
        "The same run started from the static equilibrium instead of the thesis's start."
    show run --start static
    end
fi
if want quick jump-speed; then
    begin jump-speed "Jump onset: \`camsim jump-speed\`" \
        "The lowest speed with steady-state separation (static start, bisection to 1 rpm), for the reference design and the example scenes."
    show jump-speed
    show jump-speed scenes/stable-4567-rise.toml
    show jump-speed scenes/listed-spring-60.toml
    show jump-speed scenes/undamped-printed.toml
    end
fi
if want quick run-undamped; then
    begin run-undamped "The printed, undamped model" \
        "\`scenes/undamped-printed.toml\`: no damping at the Hertz contact or the roller bearing."
    show run scenes/undamped-printed.toml
    end
fi
if want quick run-actual; then
    begin run-actual "An actual (machined) cam: \`camsim run --actual\`" \
        "Sample 0 of seed 1 at VI.1's tolerances: the default waviness (FPR 17), the exact envelope, and the interval the criteria of IV.2.3 choose."
    show run --actual --seed 1
    show run --actual --seed 1 --profile-method envelope
    show run --actual --seed 1 --interval criteria
    end
fi
if want quick waviness; then
    begin waviness "Waviness against the interval: \`camsim waviness\`" \
        "docs/MODEL.md §9.6: the FPR against the profile point interval, both methods, and the criteria."
    show waviness
    end
fi
if want quick profile-methods; then
    begin profile-methods "The thesis's profile method against the envelope" \
        "docs/MODEL.md §8.4: the lift deviation of seed 1's cam at four intervals, with and without the roller and eccentricity tolerances."
    for d in 2 0.5 0.25 0.1; do
        for tol in "" "--roller-tolerance 0 --eccentricity-tolerance 0"; do
            for m in thesis envelope; do
                # shellcheck disable=SC2086
                filtered 'lift deviation' run --revolutions 1 --actual --seed 1 --interval-deg "$d" \
                    --profile-method "$m" $tol
            done
        done
    done
    end
fi
if want quick laws; then
    begin laws "Motion laws: \`camsim laws\`" "Table VI.9's peak coefficients."
    show laws
    end
fi
if want quick modal; then
    begin modal "Modal analysis: \`camsim modal\`" "Natural frequencies of the reference design (VI.2)."
    show modal
    end
fi
if want quick contact; then
    begin contact "Hertz contact: \`camsim contact\`" "The reference roller on the cam at 100 lb."
    show contact --force 100
    end
fi
if want quick profile; then
    begin profile "The cam as a drawing: \`camsim profile\`" \
        "The reference cam's drawing with a 0.5 in cutter, then its surface read back as a measured profile (2 revolutions)."
    P="$WORK/profile"
    mkdir -p "$P"
    printf '$ camsim profile --out DIR --cutter-radius 0.5\n' >>"$CURRENT"
    "$C" profile --out "$P" --cutter-radius 0.5 2>&1 | sed "s|$P|DIR|g" >>"$CURRENT"
    printf '\n$ camsim run --revolutions 2 --measured DIR/surface_radius.csv\n' >>"$CURRENT"
    "$C" run --revolutions 2 --measured "$P/surface_radius.csv" 2>&1 | sed "s|$P|DIR|g" >>"$CURRENT"
    printf '\n' >>"$CURRENT"
    end
fi
if want quick predict; then
    begin predict "The chip's predictor on the host: \`camsim predict --f32\`" \
        "The firmware's jump and timing predictor, same scene and scripted machine, in f32."
    show predict --f32
    end
fi
if want quick bench-quick; then
    begin bench-quick "Run time against error, quick: \`camsim bench --quick\`" \
        "What CI runs: three tolerances in f64, one in f32, the full model and the chip's scene, with the ratios at equal error and the memory of a simulation. Wall and CPU times vary with the load; the counts and errors do not."
    show bench --quick
    end
fi
if want quick scenes; then
    # The command is being renamed to `models` (scenes stays a hidden alias).
    if "$C" models --help >/dev/null 2>&1; then SC=models; else SC=scenes; fi
    begin scenes "Reduced scenes: \`camsim $SC\`" \
        "Every scene of the regulated drive at the chip's tolerance against the full model: cost, error, and which question each answers."
    show "$SC"
    end
fi
if want quick compare; then
    begin compare "The motion-law study: \`camsim compare\`" \
        "Every motion law on the theoretical and on an actual cam (sample 0 of seed 1, default waviness), ranked (VI.4.2)."
    show compare
    end
fi
if want quick tolerance-study; then
    begin tolerance-study "The tolerance study: \`camsim tolerance-study\`" \
        "The tolerance and waviness grid of VI.4.1 on the more stable program, 8 cams a cell."
    show tolerance-study
    end
fi
if want long montecarlo; then
    begin montecarlo "Monte Carlo: \`camsim montecarlo\`" \
        "200 actual cams of each program at the default waviness (FPR 17) and the thesis's rougher cams (39, 57); seed 1, full model, 800 rpm."
    for scene in "" scenes/stable-4567-rise.toml; do
        for f in 17 39 57; do
            # shellcheck disable=SC2086
            filtered '^profile:|FPR|jump anywhere|smallest|run time' montecarlo $scene --samples 200 \
                --waviness-fpr "$f"
        done
    done
    end
fi
if want long sensitivity; then
    begin sensitivity "The sensitivity study: \`camsim sensitivity --per-key\`" \
        "VI.4.3's groups at ±10 and ±30 %, and every design key's elasticity (a few minutes)."
    show sensitivity --per-key
    end
fi
if want long design; then
    begin design "What to build: \`camsim design\`" \
        "The smallest spring rate with a 15 % speed margin, and with P(jump) <= 0.01 on actual cams; the highest speed and the loosest tolerance at P(jump) <= 0.01 (default waviness, then FPR 39)."
    show design spring --margin 15
    show design spring --actual --p-max 0.01
    show design speed --p-max 0.01
    show design tolerance --p-max 0.01
    show design tolerance --p-max 0.01 --waviness-fpr 39
    end
fi
if want long bench; then
    begin bench "Run time against error, full sweep: \`camsim bench\`" \
        "The full tolerance ladder of docs/BENCHMARKS.md (a few minutes)."
    show bench
    end
fi
if want firmware firmware; then
    begin firmware "Firmware under QEMU: \`bash scripts/firmware-ci.sh\`" \
        "The QEMU demonstration image's product line (image size, static RAM, peak stack, boot instructions), the instruction probes' budget line (instructions per right-hand side and per revolution, real-time factor at 168 MHz), the host parity and the build-time scene and measured-profile images."
    printf '$ bash scripts/firmware-ci.sh | grep -E ...\n' >>"$CURRENT"
    bash scripts/firmware-ci.sh 2>&1 |
        grep -E '(product|budget) flash_bytes=|jump_onset_rpm|parity OK|firmware-ci: (OK|build-time|demonstration image panic)|flash +=|static RAM =' \
            >>"$CURRENT"
    end
fi
if want firmware board; then
    begin board "The real board's image: \`bash scripts/board-ci.sh\`" \
        "The Nucleo-F446RE image (board_f446) measured without hardware."
    printf '$ bash scripts/board-ci.sh | grep -E ...\n' >>"$CURRENT"
    bash scripts/board-ci.sh 2>&1 | grep -E 'flash +=|static RAM =|board flash_bytes=|board-ci: OK' >>"$CURRENT"
    end
fi

# Merge: the sections run now replace their old text; the others keep theirs.
python3 - "$OUT" "$WORK" "$ORDER" <<'EOF'
import os, re, sys
out, work, order = sys.argv[1], sys.argv[2], sys.argv[3].split()
old = open(out, encoding="utf-8").read() if os.path.exists(out) else ""
sections = {m.group(1): m.group(0) for m in re.finditer(
    r"<!-- figure:([a-z0-9-]+) -->.*?<!-- /figure -->\n", old, re.S)}
for name in order:
    path = os.path.join(work, name + ".md")
    if os.path.exists(path):
        sections[name] = open(path, encoding="utf-8").read()
head = """# Figures

Every measured figure the docs quote, generated by `bash scripts/figures.sh` (do not edit by
hand): each section gives the command, the commit and the machine's load when it ran, and the
command's output. The other docs link to a section (`FIGURES.md#run`) instead of copying its
numbers. `--long` adds the studies, design searches and the full bench, `--firmware` the
firmware and board images, `--all` both; a section not run keeps its previous text.

"""
toc = "".join(f"- [{name}](#{name})\n" for name in order if name in sections)
body = "\n".join(sections[name] for name in order if name in sections)
tmp = out + ".tmp"
with open(tmp, "w", encoding="utf-8") as f:
    f.write(head + toc + "\n" + body)
os.replace(tmp, out)
EOF
printf 'figures.sh: wrote %s\n' "$OUT" >&2
