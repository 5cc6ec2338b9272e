#!/usr/bin/python3
"""Physical optics (PO) of a plate, integrated numerically, against the cached FDTD of the plate cases: how much of
`full`'s error near a plate's corner is what PO already gets right (issue #33; a reference for a corner model, not
part of rfidray).

  /usr/bin/python3 bench/fullwave/physical_optics.py --rfidray build/rfidray -o bench/results/fullwave

For a perfectly conducting plate (one horizontal box of a case, zero thickness or not: its top or bottom face, the
one the source sees) PO puts the current J = 2 n̂ × H_src on the lit face and nothing elsewhere. By reciprocity the
scattered field read by the tag dipole is E_s(T)·p̂_t = ∫∫ E_t(P)·J(P) dS / (jω|p_t|), E_t the field the tag dipole
would radiate; both dipoles' fields are the exact short-dipole fields (near-field terms included: the tags are
1.9–3.5 wavelengths/2π from the edges). The result is (E_src + E_s)·p̂_t / E_src·p̂_t, the same ratio the FDTD
gives. Quadrature: the midpoint rule on an N × N grid over the face (N = 300: 2 mm cells for a 0.6 m plate; the
table also gives N = 150 as a check of the quadrature). PO has no edge fringe (the current a true edge carries
beyond 2 n̂ × H) and no shadow-side current: where it is wrong by that much is what a fringe (PTD) term must add.
A last column adds each edge's fringe (fringe_model: rfidray's first-order `full` minus PO on a rectangle behind the
edge, weighted by the edge's truncation W of corner_term.py), for horizontal sheets. Reads OUT/<case>.csv (the FDTD
reference and rfidray's levels); writes OUT/physical_optics.md; exit 2 when a CSV or the binary is missing.
"""
from __future__ import annotations

import argparse
import cmath
import dataclasses
import math
import os
import sys
import tempfile

import numpy as np

import case_table
import cases
from geometry import FREQUENCY_HZ, K_RAD_M, Box, axis_vector

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


def po_ratio(case, tag, n_grid, box=None, cell_m=None):
    """(E_src + E_PO)·p̂ / E_src·p̂ at the tag, for `box` (default: the case's first); an n_grid × n_grid midpoint
    rule, or cells of about cell_m."""
    k = K_RAD_M
    omega = k * C0
    box = box or case.boxes[0]
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
    n_u = n_v = n_grid
    if cell_m:
        n_u, n_v = (max(2, int(math.ceil((hi[i] - lo[i]) / cell_m))) for i in (u, v))
    us = lo[u] + (np.arange(n_u) + 0.5) * (hi[u] - lo[u]) / n_u
    vs = lo[v] + (np.arange(n_v) + 0.5) * (hi[v] - lo[v]) / n_v
    gu, gv = np.meshgrid(us, vs, indexing="ij")
    pts = np.zeros((gu.size, 3))
    pts[:, u], pts[:, v], pts[:, t] = gu.ravel(), gv.ravel(), face
    da = (hi[u] - lo[u]) * (hi[v] - lo[v]) / (n_u * n_v)
    _, h_src = dipole_fields(a, src, pts, k)
    current = 2.0 * np.cross(normal, h_src)  # J = 2 n̂ × H (A/m)
    e_tag, _ = dipole_fields(a, tag, pts, k)
    scattered = np.sum(np.einsum("ij,ij->i", e_tag, current)) * da / (1j * omega)
    e_direct, _ = dipole_fields(a, src, tag[None, :], k)
    direct = e_direct[0] @ a
    return (direct + scattered) / direct


def fringe_model(binary, case, scratch):
    """PO of the plate plus each edge's fringe, truncated at the edge's ends (physical theory of diffraction): a
    function tag → h/h₀. The fringe of edge i is rfidray's first-order `full` minus PO, both on the same 3 m
    half-plane-like rectangle behind that edge's line (1.5 m past its ends): UTD has the edge's exact field, PO its
    PO part; the far sides' own fringes are left in, 1.5 m away. Horizontal sheets only."""
    from corner_term import FIRST_ORDER, end_share
    from rfidray_link import link_json, weighted_paths, write_obj
    box = case.boxes[0]
    lo, hi = np.array(box.lo, float), np.array(box.hi, float)
    z = lo[2]
    corners = [np.array([lo[0], lo[1], z]), np.array([hi[0], lo[1], z]), np.array([hi[0], hi[1], z]),
               np.array([lo[0], hi[1], z])]
    edges = []
    for i in range(4):
        p, q = corners[i], corners[(i + 1) % 4]
        d = (q - p) / np.linalg.norm(q - p)
        inward = np.cross([0.0, 0.0, 1.0], d)
        axis = 1 if abs(d[0]) > 0.5 else 0
        along = 1 - axis
        lo_b, hi_b = [0.0, 0.0, z], [0.0, 0.0, z]
        lo_b[along], hi_b[along] = min(p[along], q[along]) - 1.5, max(p[along], q[along]) + 1.5
        lo_b[axis], hi_b[axis] = (p[axis], p[axis] + 3.0) if inward[axis] > 0 else (p[axis] - 3.0, p[axis])
        rect = Box(tuple(lo_b), tuple(hi_b), "metal")
        hp = dataclasses.replace(case, name=f"{case.name}_fringe{i}", boxes=(rect,))
        edges.append((p, q, d, rect, write_obj(hp, os.path.join(scratch, hp.name + ".obj"))))
    src = np.array(case.source, float)

    def ratio(tag):
        total = po_ratio(case, tag, 300)
        for p, q, d, rect, scene in edges:
            j = link_json(binary, scene, case, tag, "full", extra_args=FIRST_ORDER)
            h0 = complex(j["ideal"]["h"]["re"], j["ideal"]["h"]["im"])
            utd = sum(c for _, _, c in weighted_paths(j, case, tag)) / h0
            po = po_ratio(case, tag, 0, box=rect, cell_m=0.004)
            w = end_share(src, tag, p, -d, K_RAD_M)[0] + end_share(src, tag, q, d, K_RAD_M)[0] - 1.0
            total += w * (utd - po)
        return total
    return ratio


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--out", default="bench/results/fullwave")
    ap.add_argument("--grid", type=int, default=300)
    ap.add_argument("--rfidray", default="build/rfidray", help="for the fringe column (horizontal sheets only)")
    a = ap.parse_args()
    if abs(FREQUENCY_HZ - K_RAD_M * C0 / (2 * math.pi)) > 1.0:
        fail("geometry's frequency and wavenumber disagree")
    lines = ["# Physical optics of the plate against FDTD (prototype reference)", "",
             "`/usr/bin/python3 bench/fullwave/physical_optics.py --rfidray build/rfidray -o bench/results/fullwave` (the script's header says "
             "what is integrated). Errors |h/h₀ − E/E₀|, a fraction of the free-space field; `PO (N = 150)` is the "
             "quadrature check.", "",
             "| case | observer | kρ | FDTD E/E₀ | `full` (error) | PO (error) | PO, N = 150 (error) | PO + fringe (error) |",
             "|---|---|---|---|---|---|---|---|"]
    if not os.path.isfile(a.rfidray):
        fail(a.rfidray + ": no rfidray binary (the fringe column needs it)")
    scratch = tempfile.mkdtemp(prefix="physical-optics-")
    summary = []
    for name in CASES:
        case = cases.CASES[name]()
        rows = case_table.rows_by_observer(a.out, name, "physical_optics", [o.label for o in case.observers])
        errs_full, errs_po, errs_ptd = [], [], []
        sheet = case.boxes[0].thin_axis == 2 and len(case.boxes) == 1
        ptd = fringe_model(a.rfidray, case, scratch) if sheet else None
        for o in case.observers:
            r = rows[o.label]
            f, full = case_table.ratio(r, "fdtd"), case_table.ratio(r, "full")
            tag = np.array(o.position, float)
            po = po_ratio(case, tag, a.grid)
            po_coarse = po_ratio(case, tag, a.grid // 2)
            errs_full.append(abs(full - f))
            errs_po.append(abs(po - f))
            cell = "—"
            if ptd:
                h = ptd(tag)
                errs_ptd.append(abs(h - f))
                cell = f"{abs(h):.3f} ({abs(h - f):.3f})"
            lines.append(f"| {name} | {o.label} | {o.krho:.2f} | {abs(f):.3f}∠{cmath.phase(f):+.2f} | "
                         f"{abs(full):.3f} ({abs(full - f):.3f}) | {abs(po):.3f} ({abs(po - f):.3f}) | "
                         f"{abs(po_coarse):.3f} ({abs(po_coarse - f):.3f}) | {cell} |")
        summary.append(f"- {name} ({len(errs_po)} observers), median / max error: `full` {np.median(errs_full):.3f} / "
                       f"{max(errs_full):.3f}; PO {np.median(errs_po):.3f} / {max(errs_po):.3f}" +
                       (f"; PO + fringe {np.median(errs_ptd):.3f} / {max(errs_ptd):.3f}" if errs_ptd else ""))
        print(summary[-1], flush=True)
    text = "\n".join(lines + [""] + summary) + "\n"
    with open(os.path.join(a.out, "physical_optics.md"), "w") as fh:
        fh.write(text)


if __name__ == "__main__":
    main()
