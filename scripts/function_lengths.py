#!/usr/bin/env python3
"""The longest C++ function bodies under a folder (docs/architecture.md "Long functions and how to split them").

    python3 scripts/function_lengths.py sim [--top 15] [--over 120]
    python3 scripts/function_lengths.py sim --over 120 --require-reason [--pending FILE]

--require-reason (ctest LongFunctions): every function over --over lines must have a comment
directly above its header (the `//` lines right before it) containing "Long because:", saying
why it is not split; the functions without one are listed and the exit status is 1. --pending
names a file of paths (one a line, `#` comments) whose functions are not checked yet.

A function is a brace block at namespace or class level whose header ends with `)` (plus
qualifiers, a trailing return type or a constructor's initialiser list); its length is the
number of lines from the first line of its header to its closing brace. Comments and string
literals are blanked first. Lambdas and local classes count towards the function that holds
them. A heuristic, not a parser: good for finding the long ones, not for exact counts.
"""
import argparse
import os
import re
import sys

NOT_FUNCTION = re.compile(r"^\s*(?:template\s*<.*>\s*)?(namespace|class|struct|enum|union|extern)\b",
                          re.S)
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|return)\b")


def blank(src):
    """Comments and string/char literals replaced by spaces (newlines kept)."""
    out, i, n = [], 0, len(src)
    while i < n:
        c = src[i]
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif src.startswith('R"', i) and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', src[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = src.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and src[i - 1].isalnum() and i + 1 < n and src[i + 1].isalnum():
                out.append(c)  # digit separator 1'000
                i += 1
                continue
            j = i + 1
            while j < n and src[j] != c:
                j += 2 if src[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(c + re.sub(r"[^\n]", " ", src[i + 1:j - 1]) + c)
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        src = blank(f.read())
    # Preprocessor lines out (macros with braces would confuse the header test).
    src = "\n".join("" if l.lstrip().startswith("#") else l for l in src.split("\n"))
    res = []
    i, n = 0, len(src)
    header_start = 0

    def skip_block(k):  # k at '{': index after its matching '}'
        depth = 0
        while k < n:
            if src[k] == "{":
                depth += 1
            elif src[k] == "}":
                depth -= 1
                if depth == 0:
                    return k + 1
            k += 1
        return n

    while i < n:
        c = src[i]
        if c in ";}":
            header_start = i + 1
        elif c == "{":
            header = src[header_start:i]
            h = header.strip()
            is_fn = (h.endswith(")") or re.search(r"\)\s*(const|noexcept|override|final|mutable|\s)*"
                                                  r"(->\s*[\w:<>,\s*&]+)?\s*$", h) or
                     re.search(r"\)\s*:\s*[\w:]+\s*[({]", h)) and "(" in h
            is_fn = is_fn and not NOT_FUNCTION.match(h) and not CONTROL.match(h) and "=" not in h.split("(")[0]
            if is_fn:
                end = skip_block(i)
                first = header_start + (len(header) - len(header.lstrip()))
                l0 = src.count("\n", 0, first) + 1
                l1 = src.count("\n", 0, end - 1) + 1
                name = re.findall(r"([~\w:]+(?:operator\S*)?)\s*\(", h.split(")")[0] + ")")
                res.append((l1 - l0 + 1, name[0] if name else "?", l0))
                i = end
                header_start = i
                continue
            header_start = i + 1
        i += 1
    return res


REASON = "Long because:"


def has_reason(path, l0):
    """True when the `//` comment lines directly above line l0 (1-based) contain REASON."""
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().split("\n")
    k = l0 - 2
    while k >= 0 and lines[k].lstrip().startswith("template"):
        k -= 1
    found = False
    while k >= 0 and lines[k].lstrip().startswith("//"):
        found = found or REASON in lines[k]
        k -= 1
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("root", nargs="?", default="sim")
    ap.add_argument("--top", type=int, default=15)
    ap.add_argument("--over", type=int, default=0, help="list every function longer than this")
    ap.add_argument("--require-reason", action="store_true",
                    help='fail when a function over --over has no "%s" comment above it' % REASON)
    ap.add_argument("--pending", help="file of paths not checked by --require-reason (yet)")
    a = ap.parse_args()
    rows = []
    for d, _, fs in os.walk(a.root):
        for f in fs:
            if f.endswith((".cpp", ".h", ".inc")):
                p = os.path.join(d, f)
                rows += [(ln, name, "%s:%d" % (p, l0)) for ln, name, l0 in functions(p)]
    rows.sort(key=lambda r: (-r[0], r[2]))
    if a.require_reason:
        over = a.over or 120
        pending = set()
        if a.pending:
            with open(a.pending, encoding="utf-8") as f:
                pending = {l.split("#")[0].strip() for l in f} - {""}
        bad = []
        for ln, name, where in rows:
            path, l0 = where.rsplit(":", 1)
            if ln > over and os.path.normpath(path) not in pending and not has_reason(path, int(l0)):
                bad.append((ln, name, where))
        for ln, name, where in bad:
            print("%5d  %-40s %s: over %d lines without a '// %s' comment above it (split it, or "
                  "say why it is long; docs/architecture.md 'Long functions and how to split them')" % (ln, name, where, over, REASON))
        return 1 if bad else 0
    shown = [r for r in rows if r[0] > a.over] if a.over else rows[:a.top]
    for ln, name, where in shown:
        print("%5d  %-40s %s" % (ln, name, where))
    return 0


if __name__ == "__main__":
    sys.exit(main())
