#!/usr/bin/python3
"""What the plate changes across a sheet's edge is one number: the amplitude of the edge's singular mode.

Across an edge (hard polarization, the x dipoles of the sheet cases) the edge's singular near field is
E ∝ (kρ)^{−1/2}·ê_s, ê_s = sin(φ/2) ρ̂ + cos(φ/2) φ̂ (Meixner's edge condition), and an x dipole reads
x̂·ê_s = −sin(φ/2) of it. If a difference D between two fields near the edge is that mode alone, then
C = D·e^{jkρ cos(φ − φ')} / ((kρ)^{−1/2} sin(φ/2)) is the same complex number at every angle φ round the edge (the
exponential takes back the free-space field's own phase, by which each case's CSV divides; the source is 1 m away
at φ' = 60°). Printed per distance: |C| (median, range) and arg C ± half its spread over the angles where
|sin(φ/2)| > 0.3 (the mode's nodes on the faces are left out), for
  - FDTD, 1.6 m sheet − 0.8 m sheet (cases sheet_edge_hard_tall, sheet_edge_hard): what the plate's size changes;
  - FDTD − `full` on each sheet: what `full` misses;
  - physical optics, 1.6 m − 0.8 m (physical_optics.po_ratio, 2 mm cells): whether the plate's PO current carries it.
Reads the stored CSVs (nothing run but PO, ~20 s); writes OUT/edge_mode.md. Issue #33.

  /usr/bin/python3 bench/fullwave/edge_mode.py -o bench/results/fullwave
"""
from __future__ import annotations

import argparse
import math
import os

import numpy as np

import case_table
import cases
import physical_optics
from cases import SOURCE_PHI_DEG
from geometry import K_RAD_M

RHOS_CM = (4, 8, 16)


def mode_constants(rows, differences):
    """C at each observer of `rows` (one distance) for each difference(row) → complex, where |sin(φ/2)| > 0.3."""
    out = {name: [] for name in differences}
    for r in rows:
        phi = math.radians(float(r["phi_deg"]))
        shape = math.sin(phi / 2.0)
        if abs(shape) <= 0.3:
            continue
        back = np.exp(1j * K_RAD_M * float(r["rho_m"]) * math.cos(phi - math.radians(SOURCE_PHI_DEG)))
        for name, diff in differences.items():
            out[name].append(diff(r) * back / (float(r["krho"]) ** -0.5 * shape))
    return out


def summary(values):
    v = np.array(values)
    spread = np.degrees(np.ptp(np.unwrap(np.angle(v))))
    mid = np.median(v.real) + 1j * np.median(v.imag)
    return (f"{np.median(np.abs(v)):.3f} ({np.min(np.abs(v)):.3f}–{np.max(np.abs(v)):.3f}), "
            f"arg {np.degrees(np.angle(mid)):+.0f}° ± {spread / 2:.0f}°")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--out", default="bench/results/fullwave")
    args = ap.parse_args()
    short_case, tall_case = cases.CASES["sheet_edge_hard"](), cases.CASES["sheet_edge_hard_tall"]()
    labels = [ob.label for ob in short_case.observers]
    short = case_table.rows_by_observer(args.out, short_case.name, "edge_mode", labels)
    tall = case_table.rows_by_observer(args.out, tall_case.name, "edge_mode", labels)
    po = {}
    for ob in short_case.observers:
        if round(ob.rho_m * 100) in RHOS_CM:
            t = np.array(ob.position, float)
            po[ob.label] = (physical_optics.po_ratio(tall_case, t, None, cell_m=0.002) -
                            physical_optics.po_ratio(short_case, t, None, cell_m=0.002))
    lines = ["# Across a sheet's edge: one mode, one number",
             "",
             "Written by `bench/fullwave/edge_mode.py` from the stored `sheet_edge_hard.csv` and `sheet_edge_hard_tall.csv`",
             "(FDTD: Richardson of 90/120 and 60/90 px/m) and physical optics of both sheets. Per distance: |C| median "
             "(range), and arg C (of the median re, im) ± half its spread over the 9 angles with |sin(φ/2)| > 0.3, where C "
             "is the difference divided by the edge's singular mode (kρ)^{−1/2}·sin(φ/2) as an x dipole reads it (the "
             "free-space field's phase taken back). One mode = one C at every angle.",
             "",
             "| ρ (kρ) | FDTD, 1.6 m − 0.8 m sheet | FDTD − `full`, 0.8 m | FDTD − `full`, 1.6 m | PO, 1.6 m − 0.8 m |",
             "|---|---|---|---|---|"]
    for rho in RHOS_CM:
        rows = [r for k, r in short.items() if k.startswith(f"rho{rho}cm_")]
        c = mode_constants(rows, {
            "plate": lambda r: case_table.ratio(tall[r["observer"]], "fdtd") - case_table.ratio(r, "fdtd"),
            "short": lambda r: case_table.ratio(r, "fdtd") - case_table.ratio(r, "full"),
            "tall": lambda r: case_table.ratio(tall[r["observer"]], "fdtd") - case_table.ratio(tall[r["observer"]], "full"),
            "po": lambda r: po[r["observer"]],
        })
        krho = float(rows[0]["krho"])
        lines.append(f"| {rho} cm ({krho:.2f}) | {summary(c['plate'])} | {summary(c['short'])} | {summary(c['tall'])} | "
                     f"{summary(c['po'])} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "edge_mode.md"), "w") as f:
        f.write(text)
    print(text, end="")


if __name__ == "__main__":
    main()
