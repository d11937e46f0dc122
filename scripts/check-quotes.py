#!/usr/bin/env python3
"""Checks that every output block the docs quote next to a link to docs/FIGURES.md is still in
docs/FIGURES.md (a stale figure is a defect): each line of such a fenced block (``` or
```text, within three lines of a "FIGURES.md" link), split at "..." elisions, must appear in
FIGURES.md with whitespace normalised. Command lines in the block are skipped.

    python3 scripts/check-quotes.py     # exit 1 and one line per stale block

After `bash scripts/figures.sh` moves a figure, copy the new text into the quoting doc.
"""
import glob
import os
import re
import sys

os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def norm(t):
    return re.sub(r"\s+", " ", t).strip()


figures = norm(open("docs/FIGURES.md", encoding="utf-8").read())
docs = ["README.md"] + sorted(
    f for f in glob.glob("docs/*.md") if not f.endswith(("FIGURES.md", "CLI.md"))
)
command = re.compile(r"^\s*(\$ |camsim |cargo |bash )")
checked = stale = 0
for path in docs:
    text = open(path, encoding="utf-8").read()
    for m in re.finditer(r"^```([a-z]*)\n(.*?)^```", text, re.S | re.M):
        if m.group(1) not in ("", "text"):
            continue
        before = text[: m.start()].rstrip().splitlines()[-3:]
        after = text[m.end() :].lstrip().splitlines()[:3]
        if not any("FIGURES.md" in line for line in before + after):
            continue
        checked += 1
        missing = [
            norm(frag)
            for line in m.group(2).splitlines()
            if not command.match(line)
            for frag in re.split(r"\.\.\.|…", line)
            if len(norm(frag)) >= 4 and norm(frag) not in figures
        ]
        if missing:
            stale += 1
            line_no = text[: m.start()].count("\n") + 1
            print(
                f"{path}:{line_no}: {len(missing)} quoted line(s) not in docs/FIGURES.md, "
                f"first: {missing[0][:120]!r}"
            )
print(f"check-quotes: {checked} quoted output blocks, {stale} stale", file=sys.stderr)
sys.exit(1 if stale else 0)
