#!/usr/bin/env bash
# Lists the longest Rust functions (tests included) under the given directories (default
# core/src), longest first: lines from the `fn` line to its closing brace, both counted.
# The body is found by brace matching that skips comments, strings and char literals.
# Usage: scripts/longest-fns.sh [--top N] [DIR...]
#        scripts/longest-fns.sh --check
# --check (CI): every function of core/src and chip/src is at most 100 lines and every one
# of host-sim/src and scene-file/src at most 80, firmware's at most 100, except a data
# table (a function with `// longest-fns: data table` in the comments or attributes just
# above its `fn`). The host's, scene-file's and firmware's functions already over their
# limit are listed in scripts/longest-fns.allowed (`lines path name`): a ratchet, so such
# a function may shrink (then lower its line there) but not grow, and no new one may
# exceed the limit. Exits 1 naming each function that breaks a rule.
set -euo pipefail
cd "$(dirname "$0")/.."
top=10
mode=list
if [[ "${1:-}" == --check ]]; then
    mode=check
    shift
elif [[ "${1:-}" == --top ]]; then
    top=$2
    shift 2
fi
[[ $# -gt 0 ]] || set -- core/src
python3 - "$mode" "$top" "$@" <<'PY'
import os, re, sys

mode, top, dirs = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
MARK = 'longest-fns: data table'
# The hard limits (no function over them) and the ratcheted ones (today's list may shrink).
HARD = {'core/src': 100, 'chip/src': 100}
RATCHET = {'host-sim/src': 80, 'scene-file/src': 80, 'firmware': 100}
ALLOWED = 'scripts/longest-fns.allowed'
FN = re.compile(r'\bfn\s+([A-Za-z_][A-Za-z0-9_]*)')


def code_only(text):
    """The text with comments, strings and char literals blanked (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
            out.append(' ' * (j - i)); i = j
        elif text.startswith('/*', i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith('/*', j): depth += 1; j += 2
                elif text.startswith('*/', j): depth -= 1; j += 2
                else: j += 1
            out.append(re.sub(r'[^\n]', ' ', text[i:j])); i = j
        elif (m := re.match(r'b?r(#*)"', text[i:])):
            end = '"' + m.group(1)
            j = text.find(end, i + m.end()); j = n if j < 0 else j + len(end)
            out.append(re.sub(r'[^\n]', ' ', text[i:j])); i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == '\\' else 1
            out.append(re.sub(r'[^\n]', ' ', text[i:j + 1])); i = j + 1
        elif c == "'" and (m := re.match(r"'(\\.[^']*|[^\\'])'", text[i:])):
            out.append(' ' * m.end()); i += m.end()
        else:
            out.append(c); i += 1
    return ''.join(out)


def is_table(lines, first):
    """A `// longest-fns: data table` mark among the comments and attributes above line `first`."""
    i = first - 2
    while i >= 0 and lines[i].strip().startswith(('//', '#[', '#![')):
        if MARK in lines[i]:
            return True
        i -= 1
    return False


def functions(d):
    """(lines, path, first line, name, data table?) of every function under `d`."""
    rows = []
    for root, _, files in os.walk(d):
        for f in sorted(files):
            if not f.endswith('.rs'):
                continue
            path = os.path.join(root, f)
            text = open(path, encoding='utf-8').read()
            code, lines = code_only(text), text.split('\n')
            for m in FN.finditer(code):
                # The body: the first `{` outside brackets and parentheses, unless a `;`
                # outside them comes first (a declaration has no body). The `;` of an
                # array type (`&[T; N]`) and the braces of a const generic argument
                # (`Foo<{ N }>`) lie inside brackets.
                j, depth = m.end(), 0
                while j < len(code):
                    c = code[j]
                    if c in '([<' and not (c == '<' and code[j - 1] == '-'):
                        depth += 1
                    elif c in ')]>' and not (c == '>' and code[j - 1] == '-'):
                        depth -= 1
                    elif c in '{;' and depth <= 0:
                        break
                    j += 1
                if j >= len(code) or code[j] == ';':
                    continue
                depth, k = 0, j
                while k < len(code):
                    if code[k] == '{': depth += 1
                    elif code[k] == '}':
                        depth -= 1
                        if depth == 0: break
                    k += 1
                first = code.count('\n', 0, m.start()) + 1
                last = code.count('\n', 0, k) + 1
                rows.append((last - first + 1, path, first, m.group(1), is_table(lines, first)))
    return rows


def check():
    allowed = {}
    for line in open(ALLOWED, encoding='utf-8'):
        if line.strip() and not line.startswith('#'):
            n, path, name = line.split()
            allowed.setdefault((path, name), []).append(int(n))
    bad, seen = [], {}
    for d, limit in list(HARD.items()) + list(RATCHET.items()):
        for n, path, first, name, table in functions(d):
            if n <= limit or table:
                continue
            if d in RATCHET:
                seen.setdefault((path, name), []).append((n, first))
                continue
            bad.append(f'{path}:{first} {name} is {n} lines; the limit under {d} is {limit}')
    for key, found in sorted(seen.items()):
        room = sorted(allowed.get(key, []), reverse=True)
        for (n, first), cap in zip(sorted(found, reverse=True), room + [0] * len(found)):
            if n > cap:
                was = f'listed at {cap} lines in {ALLOWED}' if cap else f'not listed in {ALLOWED}'
                bad.append(f'{key[0]}:{first} {key[1]} is {n} lines, {was}; '
                           'split it (the list may only shrink)')
    for msg in bad:
        print(f'longest-fns: {msg}', file=sys.stderr)
    if bad:
        sys.exit(1)
    total = sum(len(v) for v in seen.values())
    print(f'longest-fns: ok (core and chip within 100 lines; {total} ratcheted host, '
          f'scene-file and firmware functions within their listed lengths)')


if mode == 'check':
    check()
    sys.exit(0)
rows = [r for d in dirs for r in functions(d)]
rows.sort(key=lambda r: (-r[0], r[1], r[2]))
for lines, path, first, name, table in rows[:top]:
    mark = '  (data table)' if table else ''
    print(f'{lines:5d}  {path}:{first}  {name}{mark}')
PY
