#!/usr/bin/env bash
# Lists the panic call sites of a firmware ELF (shared by scripts/firmware-ci.sh and
# scripts/board-ci.sh; source it, or run `bash scripts/panic-sites.sh ELF [ALLOWED_RE]`).
#
# A call site is a branch to a panic entry point (core::panicking::*, any panic_* item,
# Option/Result unwrap and expect failures, slice and str index failures, the panic
# handler) from code that is not itself one. Each is printed with the code responsible
# for it: the innermost inlined frame outside Rust's own library (llvm-addr2line -i),
# named by its origin: "camsim" (this repository), a crate from the cargo registry
# (name-version), "core library", or "unknown".
#
# panic_sites ELF [ALLOWED_RE] prints the sites and a count per origin, and sets
#   PANIC_TOTAL    all call sites,
#   PANIC_OWN      those whose responsible code is camsim's own,
#   PANIC_OUTSIDE  those whose origin does not match the extended regex ALLOWED_RE
#                  (default: matches nothing, so PANIC_OUTSIDE = PANIC_TOTAL).
# Needs llvm-objdump and llvm-addr2line (plain or apt's -14); run from the repository root.

if command -v llvm-objdump >/dev/null 2>&1; then PANIC_OBJDUMP=llvm-objdump
else PANIC_OBJDUMP=llvm-objdump-14; fi
if command -v llvm-addr2line >/dev/null 2>&1; then PANIC_ADDR2LINE=llvm-addr2line
else PANIC_ADDR2LINE=llvm-addr2line-14; fi

# Panic entry points (demangled, without hash).
PANIC_RE='^(core::panicking::|core::option::(unwrap|expect)_failed|core::result::unwrap_failed|core::slice::index::[a-z_]*_fail|core::str::slice_error_fail|core::cell::panic_|(__rustc::)?rust_begin_unwind$)|(^|::)panic_[a-z_]*$'

panic_sites() {
    local elf=$1 allowed=${2:-'^$'} root sites frames out
    root=$(pwd)
    for t in "$PANIC_OBJDUMP" "$PANIC_ADDR2LINE"; do
        command -v "$t" >/dev/null 2>&1 || { echo "panic_sites: $t not found (apt-get install llvm-14)" >&2; return 1; }
    done
    [ -f "$elf" ] || { echo "panic_sites: no ELF at $elf" >&2; return 1; }
    # "address<TAB>callee<TAB>caller" for each branch to a panic entry point from code that
    # is not itself one (branches inside a function, <f+0x..>, are not calls).
    sites=$("$PANIC_OBJDUMP" -d --no-show-raw-insn -C "$elf" | awk -v re="$PANIC_RE" '
        # A label starts a function, except the ARM mapping symbols ($t, $d: Thumb code, data).
        /^[0-9a-f]+ <.*>:$/ { l = $0; sub(/^[0-9a-f]+ </, "", l); sub(/>:$/, "", l); if (l !~ /^\$/) fn = l; next }
        $2 ~ /^b/ && match($0, /<[^>]*>/) {
            callee = substr($0, RSTART + 1, RLENGTH - 2)
            if (callee ~ /\+0x[0-9a-f]+$/) next
            if (callee ~ re && fn !~ re) { a = $1; sub(/:$/, "", a); printf "%s\t%s\t%s\n", a, callee, fn }
        }')
    PANIC_TOTAL=0 PANIC_OWN=0 PANIC_OUTSIDE=0
    if [ -z "$sites" ]; then
        echo "  0 panic call sites"
        return 0
    fi
    # The responsible frame of each site: the innermost inlined frame whose file is not
    # Rust's own library (/rustc/...), else the innermost frame.
    frames=$(cut -f1 <<<"$sites" | sed 's/^/0x/' | "$PANIC_ADDR2LINE" -a -f -i -e "$elf" | awk '
        function flush() { if (a != "") print a "\t" (pick != "" ? pick : first) }
        /^0x[0-9a-f]+$/ { flush(); a = $0; first = ""; pick = ""; n = 0; next }
        { n++; if (n % 2 == 1) { f = $0; next }
          fr = $0 "\t" f
          if (first == "") first = fr
          if (pick == "" && $0 !~ /^\/rustc\// && $0 !~ /^\?\?/) pick = fr }
        END { flush() }')
    out=$(paste <(cut -f2,3 <<<"$sites") <(cut -f2,3 <<<"$frames") | awk -F '\t' -v root="$root/" -v allowed="$allowed" '
        {
            callee = $1; caller = $2; file = $3
            if (index(file, root) == 1) { origin = "camsim"; file = substr(file, length(root) + 1); own++ }
            else if (file ~ /\/\.cargo\/registry\/src\/[^\/]*\//) {
                origin = file; sub(/.*\/\.cargo\/registry\/src\/[^\/]*\//, "", origin); sub(/\/.*/, "", origin)
                sub(/.*\/\.cargo\/registry\/src\/[^\/]*\/[^\/]*\//, "", file)
            } else if (file ~ /^\/rustc\//) { origin = "core library"; sub(/^\/rustc\/[^\/]*\/library\//, "", file) }
            else origin = "unknown"
            if (origin !~ allowed) outside++
            count[origin]++; total++
            printf "    %-14s %-42s <- %s (in %s)\n", origin, callee, file, caller
        }
        END {
            line = ""
            for (o in count) line = line sprintf("%s%s %d", (line == "" ? "" : ", "), o, count[o])
            printf "  %d panic call sites (%s)\n", total, line
            printf "#counts %d %d %d\n", total, own + 0, outside + 0
        }')
    grep -v '^#counts ' <<<"$out"
    read -r _ PANIC_TOTAL PANIC_OWN PANIC_OUTSIDE < <(grep '^#counts ' <<<"$out")
    return 0
}

# Run as a script: list one ELF.
if [ "${BASH_SOURCE[0]}" = "$0" ]; then
    set -euo pipefail
    [ $# -ge 1 ] || { echo "usage: bash scripts/panic-sites.sh ELF [ALLOWED_ORIGIN_RE]" >&2; exit 2; }
    elf=$(realpath "$1")
    cd "$(dirname "$0")/.."
    panic_sites "$elf" "${2:-^$}"
    echo "total=$PANIC_TOTAL camsim=$PANIC_OWN outside_allowed=$PANIC_OUTSIDE"
fi
