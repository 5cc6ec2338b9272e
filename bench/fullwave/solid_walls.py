#!/usr/bin/python3
"""Walls as solid boxes against the same FDTD references as walls as one sheet (issue #33, cases e and f).

  /usr/bin/python3 bench/fullwave/solid_walls.py --rfidray build/rfidray -o bench/results/fullwave

run.py gives rfidray a thick wall as one sheet (its front face) with `--thickness`: a slab for reflection and
transmission, and half-plane edges at the front face. Here the same walls are closed boxes of their real
thickness (`link --solid --thickness T`: a direct path's entry and exit are one slab, RadioMaterial::solid in
core/material.h), so rfidray also has the end faces (a doorway's jambs) and the back edges, as 90° wedges. The FDTD
field of every observer is read from OUT/CASE.csv (run.py --case CASE, cached FDTD; nothing is recomputed), and
the sheet's `full` error from the same file. Writes OUT/solid_walls.md and OUT/solid_walls.csv; exit 2 when a
case's CSV is missing.
"""
from __future__ import annotations

import argparse
import csv
import dataclasses
import os
import sys
import tempfile

import numpy as np

import case_table
import cases
import rfidray_link
from geometry import Box

CASES = ("concrete_wall", "doorway")
LEVELS = ("los+blocked", "full")


def solid_case(case):
    """The case with every wall sheet (Box.slab_m > 0) as the closed box FDTD has (slab_m behind the sheet)."""
    boxes = []
    for b in case.boxes:
        if b.slab_m > 0.0:
            t = b.thin_axis
            hi = list(b.hi)
            hi[t] = b.lo[t] + b.slab_m
            boxes.append(Box(b.lo, tuple(hi), b.material, eps_r=b.eps_r, sigma_s_m=b.sigma_s_m))
        else:
            boxes.append(b)
    return dataclasses.replace(case, boxes=tuple(boxes))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rfidray", required=True)
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    rows_out = []
    md = ["# Walls as solid boxes against FDTD", "",
          "`python3 bench/fullwave/solid_walls.py --rfidray build/rfidray -o bench/results/fullwave`: the concrete",
          "wall (e) and the doorway (f) of [other_geometries.md](other_geometries.md) with rfidray's wall as a closed",
          "box 0.2 m thick (`link --solid --thickness 0.2`) instead of one sheet with `--thickness 0.2`; FDTD fields",
          "from the cases' CSVs (the finest resolution's Richardson value; `spread` is the 30/60 px/m difference).",
          "Errors |h/h₀ − E/E₀| as a fraction of the free-space field.", ""]
    for name in CASES:
        case = getattr(cases, name)()
        ref = case_table.rows_by_observer(a.out, name, "solid_walls", [o.label for o in case.observers])
        thickness = rfidray_link.case_thickness(case)
        with tempfile.TemporaryDirectory() as scratch:
            res = rfidray_link.all_levels(a.rfidray, solid_case(case), scratch, levels=LEVELS, thickness_m=thickness,
                                          jobs=a.jobs, extra_args=("--solid",))
        md += [f"## {name}", "",
               "| observer | region | FDTD | spread | sheet `full` error | solid `los+blocked` | error | solid `full` | error |",
               "|---|---|---|---|---|---|---|---|---|"]
        per = []
        for i, o in enumerate(case.observers):
            r = ref[o.label]
            e = float(r["fdtd_abs"]) * np.exp(1j * float(r["fdtd_arg_rad"]))
            sheet = float(r["full_error"])
            lb, full = res["los+blocked"][i], res["full"][i]
            row = {"case": name, "observer": o.label, "region": o.region, "fdtd_abs": abs(e),
                   "fdtd_arg_rad": np.angle(e), "reference_spread": float(r["reference_spread"]),
                   "sheet_full_error": sheet, "solid_los_blocked_abs": abs(lb),
                   "solid_los_blocked_arg_rad": np.angle(lb), "solid_los_blocked_error": abs(lb - e),
                   "solid_full_abs": abs(full), "solid_full_arg_rad": np.angle(full), "solid_full_error": abs(full - e)}
            rows_out.append(row)
            per.append(row)
            md.append(f"| {o.label} | {o.region} | {abs(e):.3f}∠{np.angle(e):+.2f} | {row['reference_spread']:.3f} | "
                      f"{sheet:.3f} | {abs(lb):.3f}∠{np.angle(lb):+.2f} | {row['solid_los_blocked_error']:.3f} | "
                      f"{abs(full):.3f}∠{np.angle(full):+.2f} | {row['solid_full_error']:.3f} |")
        md += ["", "| region | observers | sheet `full` median / max | solid `los+blocked` | solid `full` median / max |",
               "|---|---|---|---|---|"]
        for region in dict.fromkeys(r["region"] for r in per):
            sel = [r for r in per if r["region"] == region]
            f = lambda k: f"{np.median([r[k] for r in sel]):.2f} / {max(r[k] for r in sel):.2f}"
            md.append(f"| {region} | {len(sel)} | {f('sheet_full_error')} | {f('solid_los_blocked_error')} | "
                      f"{f('solid_full_error')} |")
        f = lambda k: f"{np.median([r[k] for r in per]):.3f} / {max(r[k] for r in per):.3f}"
        md.append(f"| all | {len(per)} | {f('sheet_full_error')} | {f('solid_los_blocked_error')} | "
                  f"{f('solid_full_error')} |")
        md.append("")
    with open(os.path.join(a.out, "solid_walls.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows_out[0].keys()))
        w.writeheader()
        for r in rows_out:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    with open(os.path.join(a.out, "solid_walls.md"), "w") as fh:
        fh.write("\n".join(md) + "\n")
    print("\n".join(md))
    return 0


if __name__ == "__main__":
    sys.exit(main())
