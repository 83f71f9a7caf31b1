#!/usr/bin/python3
"""Compares two sweep summary.csv files cell by cell, ignoring wall-clock columns (ref_ms,
sim_ms). Exit 0 when every other value is identical, 1 otherwise (prints the differences)."""
import csv
import sys

TIMING = {"ref_ms", "sim_ms"}


def load(p):
    with open(p, newline="") as f:
        r = csv.DictReader(f)
        return r.fieldnames, list(r)


def main(a, b):
    ca, ra = load(a)
    cb, rb = load(b)
    bad = 0
    if [c for c in ca if c not in TIMING] != [c for c in cb if c not in TIMING]:
        print("columns differ")
        return 1
    if len(ra) != len(rb):
        print(f"row count differs: {len(ra)} vs {len(rb)}")
        return 1
    for i, (x, y) in enumerate(zip(ra, rb)):
        for c in ca:
            if c not in TIMING and x[c] != y[c]:
                bad += 1
                if bad <= 10:
                    print(f"row {i} ({x.get('config_id')}) {c}: {x[c]} != {y[c]}")
    print(f"compared {len(ra)} rows x {len(ca) - len(TIMING & set(ca))} columns: "
          + ("identical" if not bad else f"{bad} differences"))
    return 0 if bad == 0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
