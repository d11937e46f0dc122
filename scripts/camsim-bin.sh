#!/usr/bin/env bash
# Prints the path of the release `camsim` binary where cargo puts it (CARGO_TARGET_DIR or a
# config may move the target directory); the scripts build it and run it from there.
set -euo pipefail
cd "$(dirname "$0")/.."
printf '%s/release/camsim\n' "$(cargo metadata --format-version 1 --no-deps |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
