#!/usr/bin/python3
"""Per-region error summary of the cases other than the sheet edge (issue #33 cases b–f), from their CSVs.

  /usr/bin/python3 bench/fullwave/cases_summary.py -o bench/results/fullwave

Reads OUT/CASE.csv (written by run.py --case CASE) for every case present and writes OUT/other_geometries.md: per
case and region the number of observers, how many have a converged reference (spread ≤ 0.05 of the free-space
field), the spread median / max and each level's error median / max over the converged observers (over all when
none is converged, marked). Exit 2 when no CSV is there.
"""
from __future__ import annotations

import argparse
import os
import sys

import numpy as np

from summary import read_rows

CASES = ("concrete_wall", "doorway", "plate_front", "rack_bay", "upright", "upright_hard", "rack_post", "plate_corner")
LEVELS = ("los", "los+blocked", "single-bounce", "double-bounce", "full-selective", "full")
CONVERGED = 0.05


def table(rows):
    out = ["| region | n (converged) | spread median / max | " + " | ".join(f"`{lv}`" for lv in LEVELS) + " |",
           "|---|---|---|" + "---|" * len(LEVELS)]
    for region in dict.fromkeys(r["region"] for r in rows):
        sel = [r for r in rows if r["region"] == region]
        conv = [r for r in sel if r["reference_spread"] <= CONVERGED]
        use, mark = (conv, "") if conv else (sel, " †")
        sp = np.array([r["reference_spread"] for r in sel])
        cells = [f"{np.median([r[lv + '_error'] for r in use]):.2f} / {np.max([r[lv + '_error'] for r in use]):.2f}"
                 for lv in LEVELS]
        out.append(f"| {region}{mark} | {len(sel)} ({len(conv)}) | {np.median(sp):.3f} / {np.max(sp):.3f} | "
                   + " | ".join(cells) + " |")
    return out


def write(out_dir, log=print):
    """OUT/other_geometries.md from the CSVs there; exit 2 when there is none."""
    md = ["# Other geometries: error of each level against the FDTD reference, per region", "",
          "Error = |h/h_ideal − E/E_free| (a fraction of the free-space field), median / max over the region's "
          f"observers where the reference is converged (spread ≤ {CONVERGED}); † = none is, over all. "
          "Per-observer figures: CASE.md / CASE.csv.", ""]
    found = 0
    for c in CASES:
        p = os.path.join(out_dir, c + ".csv")
        if not os.path.exists(p):
            continue
        found += 1
        md += [f"## {c}", ""] + table(read_rows(p)) + [""]
    if not found:
        print(f"cases_summary.py: error: no {', '.join(c + '.csv' for c in CASES)} in {out_dir}", file=sys.stderr)
        sys.exit(2)
    path = os.path.join(out_dir, "other_geometries.md")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(path + ".tmp", path)
    log(f"wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", required=True, help="directory with the cases' CSVs (run.py -o)")
    write(ap.parse_args().out)


if __name__ == "__main__":
    main()
