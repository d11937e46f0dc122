#!/usr/bin/env bash
# Lists the longest Rust functions (tests included) under the given directories (default
# core/src), longest first: lines from the `fn` line to its closing brace, both counted.
# The body is found by brace matching that skips comments, strings and char literals.
# Usage: scripts/longest-fns.sh [--top N] [DIR...]
set -euo pipefail
cd "$(dirname "$0")/.."
top=10
if [[ "${1:-}" == --top ]]; then
    top=$2
    shift 2
fi
[[ $# -gt 0 ]] || set -- core/src
python3 - "$top" "$@" <<'PY'
import os, re, sys

top, dirs = int(sys.argv[1]), sys.argv[2:]
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


rows = []
for d in dirs:
    for root, _, files in os.walk(d):
        for f in files:
            if not f.endswith('.rs'):
                continue
            path = os.path.join(root, f)
            code = code_only(open(path, encoding='utf-8').read())
            for m in FN.finditer(code):
                # The body: the first `{` before any `;` (a declaration has none).
                j = m.end()
                while j < len(code) and code[j] not in '{;':
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
                rows.append((last - first + 1, path, first, m.group(1)))
rows.sort(key=lambda r: (-r[0], r[1], r[2]))
for lines, path, first, name in rows[:top]:
    print(f'{lines:5d}  {path}:{first}  {name}')
PY
