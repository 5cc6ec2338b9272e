#!/usr/bin/python3
"""Physical optics (PO) of a plate, integrated numerically, against the cached FDTD of the plate cases: how much of
`full`'s error near a plate's corner is what PO already gets right (issue #33; a reference for a corner model, not
part of rfidray).

  /usr/bin/python3 bench/fullwave/physical_optics.py -o bench/results/fullwave

For a perfectly conducting plate (one horizontal box of a case, zero thickness or not: its top or bottom face, the
one the source sees) PO puts the current J = 2 n̂ × H_src on the lit face and nothing elsewhere. By reciprocity the
scattered field read by the tag dipole is E_s(T)·p̂_t = ∫∫ E_t(P)·J(P) dS / (jω|p_t|), E_t the field the tag dipole
would radiate; both dipoles' fields are the exact short-dipole fields (near-field terms included: the tags are
1.9–3.5 wavelengths/2π from the edges). The result is (E_src + E_s)·p̂_t / E_src·p̂_t, the same ratio the FDTD
gives. Quadrature: the midpoint rule on an N × N grid over the face (N = 300: 2 mm cells for a 0.6 m plate; the
table also gives N = 150 as a check of the quadrature). PO has no edge fringe (the current a true edge carries
beyond 2 n̂ × H) and no shadow-side current: where it is wrong by that much is what a fringe (PTD) term must add.
Reads OUT/<case>.csv (the FDTD reference and rfidray's levels); writes OUT/physical_optics.md; exit 2 when a CSV is
missing.
"""
from __future__ import annotations

import argparse
import cmath
import csv
import math
import os
import sys

import numpy as np

import cases
from geometry import FREQUENCY_HZ, K_RAD_M, axis_vector

CASES = ("plate_corner_steep", "plate_corner_steep_box", "plate_corner", "plate_corner_line", "plate_grazing",
         "plate_front")
C0 = 299792458.0
EPS0 = 8.8541878128e-12


def fail(msg):
    print("physical_optics: error: " + msg, file=sys.stderr)
    sys.exit(2)


def dipole_fields(p, origin, points, k):
    """E and H (SI, e^{jωt}) of a short dipole of moment p (C·m) at origin, at points (N×3): Jackson (9.18)-(9.19)
    with i → −j."""
    r = points - origin
    dist = np.linalg.norm(r, axis=1)[:, None]
    n = r / dist
    phase = np.exp(-1j * k * dist)
    nxp = np.cross(n, p)
    e = (k * k * np.cross(nxp, n) / dist + (3.0 * n * (n @ p)[:, None] - p) * (1.0 / dist ** 3 + 1j * k / dist ** 2)) \
        * phase / (4.0 * math.pi * EPS0)
    h = (C0 * k * k / (4.0 * math.pi)) * nxp * phase / dist * (1.0 + 1.0 / (1j * k * dist))
    return e, h


def po_ratio(case, tag, n_grid):
    """(E_src + E_PO)·p̂ / E_src·p̂ at the tag, for the case's first box."""
    k = K_RAD_M
    omega = k * C0
    box = case.boxes[0]
    lo, hi = np.array(box.lo, float), np.array(box.hi, float)
    src = np.array(case.source, float)
    a = np.array(axis_vector(case.axis), float)
    # The face the source sees and its outward normal: a sheet's plane, or the face of a closed box towards it.
    t = box.thin_axis
    if t is None:
        t = next(i for i in range(3) if src[i] > hi[i] or src[i] < lo[i])
    u, v = [i for i in range(3) if i != t]
    normal = np.zeros(3)
    normal[t] = 1.0 if src[t] > hi[t] else -1.0
    face = hi[t] if normal[t] > 0 else lo[t]
    us = lo[u] + (np.arange(n_grid) + 0.5) * (hi[u] - lo[u]) / n_grid
    vs = lo[v] + (np.arange(n_grid) + 0.5) * (hi[v] - lo[v]) / n_grid
    gu, gv = np.meshgrid(us, vs, indexing="ij")
    pts = np.zeros((gu.size, 3))
    pts[:, u], pts[:, v], pts[:, t] = gu.ravel(), gv.ravel(), face
    da = (hi[u] - lo[u]) * (hi[v] - lo[v]) / n_grid ** 2
    _, h_src = dipole_fields(a, src, pts, k)
    current = 2.0 * np.cross(normal, h_src)  # J = 2 n̂ × H (A/m)
    e_tag, _ = dipole_fields(a, tag, pts, k)
    scattered = np.sum(np.einsum("ij,ij->i", e_tag, current)) * da / (1j * omega)
    e_direct, _ = dipole_fields(a, src, tag[None, :], k)
    direct = e_direct[0] @ a
    return (direct + scattered) / direct


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--out", default="bench/results/fullwave")
    ap.add_argument("--grid", type=int, default=300)
    a = ap.parse_args()
    if abs(FREQUENCY_HZ - K_RAD_M * C0 / (2 * math.pi)) > 1.0:
        fail("geometry's frequency and wavenumber disagree")
    lines = ["# Physical optics of the plate against FDTD (prototype reference)", "",
             "`/usr/bin/python3 bench/fullwave/physical_optics.py -o bench/results/fullwave` (the script's header says "
             "what is integrated). Errors |h/h₀ − E/E₀|, a fraction of the free-space field; `PO (N = 150)` is the "
             "quadrature check.", "",
             "| case | observer | kρ | FDTD E/E₀ | `full` (error) | PO (error) | PO, N = 150 (error) |",
             "|---|---|---|---|---|---|---|"]
    summary = []
    for name in CASES:
        path = os.path.join(a.out, name + ".csv")
        if not os.path.isfile(path):
            fail(path + ": not found")
        rows = {r["observer"]: r for r in csv.DictReader(open(path))}
        case = cases.CASES[name]()
        errs_full, errs_po = [], []
        for o in case.observers:
            r = rows.get(o.label)
            if r is None:
                fail(f"{path}: no row for observer {o.label}")
            f = cmath.rect(float(r["fdtd_abs"]), float(r["fdtd_arg_rad"]))
            full = cmath.rect(float(r["full_abs"]), float(r["full_arg_rad"]))
            tag = np.array(o.position, float)
            po = po_ratio(case, tag, a.grid)
            po_coarse = po_ratio(case, tag, a.grid // 2)
            errs_full.append(abs(full - f))
            errs_po.append(abs(po - f))
            lines.append(f"| {name} | {o.label} | {o.krho:.2f} | {abs(f):.3f}∠{cmath.phase(f):+.2f} | "
                         f"{abs(full):.3f} ({abs(full - f):.3f}) | {abs(po):.3f} ({abs(po - f):.3f}) | "
                         f"{abs(po_coarse):.3f} ({abs(po_coarse - f):.3f}) |")
        summary.append(f"- {name} ({len(errs_po)} observers), median / max error: `full` {np.median(errs_full):.3f} / "
                       f"{max(errs_full):.3f}; PO {np.median(errs_po):.3f} / {max(errs_po):.3f}")
        print(summary[-1], flush=True)
    text = "\n".join(lines + [""] + summary) + "\n"
    with open(os.path.join(a.out, "physical_optics.md"), "w") as fh:
        fh.write(text)


if __name__ == "__main__":
    main()
