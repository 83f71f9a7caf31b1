#!/usr/bin/env python3
"""Fails when a `catch` block under sim/ is empty -- only whitespace, comments, empty statements
or `(void)e;` -- in any C++ source (.cpp, .h, .inc): an error that is swallowed must at least do
something visible (return, assign a fallback that says so, or rethrow). Run by ctest as
NoEmptyCatch."""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "sim")
pat = re.compile(r"catch\s*\([^)]*\)\s*\{((?:\s|//[^\n]*\n|/\*.*?\*/|;|\(void\)\s*\w+\s*;)*)\}",
                 re.S)
bad = []
for f in sorted(root.rglob("*")):
    if f.suffix not in (".cpp", ".h", ".inc"):
        continue
    text = f.read_text(encoding="utf-8")
    for m in pat.finditer(text):
        bad.append(f"{f}:{text.count(chr(10), 0, m.start()) + 1}: empty catch block")
print("\n".join(bad) if bad else f"no empty catch blocks under {root}")
sys.exit(1 if bad else 0)
