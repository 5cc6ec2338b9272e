"""A second FDTD side on openEMS (Debian `python3-openems`), for what meep's uniform grid cannot reach: a tag a few
millimetres from a metal plate (issue #33 asks for d = λ/100 = 3.5 mm; at 60 px/m that is a fifth of a cell).
openEMS grids are rectilinear but graded: cells of `fine` across the gap, growing geometrically (ratio ≤ 1.3) to
`coarse` away from it.

Only the plate-front geometry is built here (plate_front_near in cases.py): a zero-thickness PEC sheet in y = 0,
a z dipole in front, observers in front of it. The half z ≥ 0 is simulated: z = 0 is an electric wall (E_x, E_y
are odd in z for a z dipole centred on z = 0), exact for this source and plate. (x = 0 would be a magnetic wall,
but openEMS 0.0.35 holds a source on a PMC boundary at zero: tried, no field anywhere.) The other five faces are
8-cell PMLs (openEMS `PML_8`).

The source is a soft E-field excitation on the one mesh edge along z from (0, y_s, 0) (with its image in the
electric wall: a short dipole two cells long), a Gaussian pulse about 866 MHz; each observer is an E-field probe
on a mesh node. The field at 866 MHz is the discrete Fourier transform of the probe's E_z over the whole run; the
run with the plate divided by the same run without it (same mesh, same source) is E/E_free, in which the pulse's
spectrum and the source's discretization cancel. The transform's kernel is e^{−jωt}, so the ratio is a phasor in
rfidray's e^{+jωt} convention (no conjugation, unlike meep's fields).
"""
from __future__ import annotations

import math
import os
import shutil
import time

import numpy as np

from geometry import FREQUENCY_HZ, Case


def _size_at(x: float, zones, fine_m: float, coarse_m: float, ratio: float) -> float:
    """Largest cell allowed at x: `fine_m` inside a zone, growing by `ratio` per cell away from it (linear growth in
    distance, the continuous form of a geometric grading), at most `coarse_m`."""
    h = coarse_m
    for lo, hi in zones:
        dist = max(lo - x, 0.0, x - hi)
        h = min(h, fine_m + (ratio - 1.0) * dist)
    return h


def graded_lines(fixed, zones, fine_m: float, coarse_m: float, ratio: float = 1.3) -> np.ndarray:
    """Mesh lines through every fixed coordinate; between two fixed ones as few lines as keep every cell within
    _size_at, spaced evenly in ∫dx/h (so the cells follow h smoothly)."""
    fixed = sorted(set(round(v, 12) for v in fixed))
    lines = [fixed[0]]
    for a, b in zip(fixed[:-1], fixed[1:]):
        xs = np.linspace(a, b, 2001)
        w = 1.0 / np.array([_size_at(x, zones, fine_m, coarse_m, ratio) for x in xs])
        cum = np.concatenate(([0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(xs))))
        n = max(1, math.ceil(cum[-1] - 1e-9))
        for k in range(1, n):
            lines.append(float(np.interp(k * cum[-1] / n, cum, xs)))
        lines.append(b)
    return np.array(lines)


def pml_extend(lines: np.ndarray, low: bool = True, cells: int = 8) -> np.ndarray:
    """`cells` more cells of the end cell's size beyond the high end and, if `low`, the low end (openEMS puts its
    PML inside the mesh)."""
    hi = lines[-1] + (lines[-1] - lines[-2]) * np.arange(1, cells + 1)
    lo = lines[0] - (lines[1] - lines[0]) * np.arange(cells, 0, -1) if low else lines[:0]
    return np.concatenate((lo, lines, hi))


def half_mesh(case: Case, scale: float, gap_m: float):
    """Mesh lines (x, y, z ≥ 0) for a plate-front case at `scale` (1: cells of 0.5 mm across the gap, 2 mm round
    the plate's edges, 8 mm elsewhere; 2: twice those)."""
    fine, edge, coarse = 0.5e-3 * scale, 2e-3 * scale, 8e-3 * scale
    plate = case.boxes[0]
    xe, ze = plate.hi[0], plate.hi[2]
    obs = [o.position for o in case.observers]
    fx = [case.domain_lo[0], -xe, 0.0, xe, case.domain_hi[0]] + [p[0] for p in obs]
    fz = [0.0, ze, case.domain_hi[2]] + [p[2] for p in obs]
    fy = [case.domain_lo[1], case.source[1], 0.0, case.domain_hi[1]] + [p[1] for p in obs]
    # Round the edges (x = xe, z = ze): `edge` from 4 cm inside to 1 cm outside (the observers 3 cm inside).
    x = graded_lines(fx, [(-xe - 0.01, -xe + 0.04), (xe - 0.04, xe + 0.01)], edge, coarse)
    z = graded_lines(fz, [(ze - 0.04, ze + 0.01)], edge, coarse)
    # Across the gap: `fine` from the plate to past the nearest observers (and as far behind the sheet).
    y = graded_lines(fy, [(-max(2.0 * gap_m, 8 * fine), 4 * fine)], fine, coarse)
    return pml_extend(x), pml_extend(y), pml_extend(z, low=False)  # z = 0: the electric wall


# The record's length: the pulse (9.45 ns) has passed every observer 1.3 m from the source by ~14 ns; the field
# is transformed over records cut at these times, and their spread is stated as the record's own error. (An energy
# criterion stopped the free runs before the pulse had passed the observers. From ~15 ns on, openEMS's PMLs let
# the energy grow again, by ~1 dB per 1 000 steps from −48 dB with the plate at scale 2: the spread says whether it
# reaches the ratio by 22 ns.)
RECORD_CUTS_S = (16e-9, 19e-9, 22e-9)


def run(case: Case, scale: float, gap_m: float, with_boxes: bool, work_dir: str, keep: bool = False,
        time_step_factor: float = 0.9, log=print) -> dict:
    """One openEMS run; returns {'fields': complex E_z at 866 MHz per observer (arbitrary common scale), 'fields_by_cut'
    (observer × RECORD_CUTS_S), 'cells', 'steps' (probe samples), 'seconds', 'tail': the last 5 % of the probe signals
    over their peak (how far the run had decayed)}. `keep` leaves openEMS's files in `work_dir`."""
    from CSXCAD import ContinuousStructure
    from openEMS import openEMS

    if case.axis != "z":
        raise ValueError("fdtd_openems: only a z dipole (the electric wall z = 0 assumes it)")
    x, y, z = half_mesh(case, scale, gap_m)
    fdtd = openEMS(NrTS=10_000_000, EndCriteria=1e-12)
    fdtd.SetMaxTime(RECORD_CUTS_S[-1])
    fdtd.SetGaussExcite(FREQUENCY_HZ, 0.35 * FREQUENCY_HZ)
    fdtd.SetTimeStepFactor(time_step_factor)
    fdtd.SetBoundaryCond(["PML_8", "PML_8", "PML_8", "PML_8", "PEC", "PML_8"])  # xmin xmax ymin ymax zmin zmax
    csx = ContinuousStructure()
    fdtd.SetCSX(csx)
    mesh = csx.GetGrid()
    mesh.SetDeltaUnit(1.0)
    mesh.SetLines("x", x)
    mesh.SetLines("y", y)
    mesh.SetLines("z", z)
    if with_boxes:
        for i, b in enumerate(case.boxes):
            if b.material != "metal" or b.thin_axis != 1:
                raise ValueError("fdtd_openems: only metal sheets in a plane y = const")
            metal = csx.AddMetal(f"plate{i}")
            metal.AddBox([b.lo[0], b.lo[1], max(b.lo[2], 0.0)], [b.hi[0], b.hi[1], b.hi[2]])
    sx, sy, sz = case.source
    if abs(sx) > 1e-12 or abs(sz) > 1e-12:
        raise ValueError("fdtd_openems: the source must lie on x = 0, z = 0 (on the electric wall z = 0)")
    exc = csx.AddExcitation("source", exc_type=0, exc_val=[0, 0, 1])
    exc.AddBox([0.0, sy, 0.0], [0.0, sy, z[1]])
    for i, o in enumerate(case.observers):
        p = csx.AddProbe(f"obs{i}", p_type=2)
        p.AddBox(list(o.position), list(o.position))
    path = os.path.join(os.path.abspath(work_dir), f"{case.name}_s{scale:g}_{'plate' if with_boxes else 'free'}")
    fdtd.SetOverSampling(4)  # probe samples: 4× the pulse's Nyquist rate
    t0 = time.time()
    cwd = os.getcwd()
    try:
        fdtd.Run(path, cleanup=True, verbose=0)  # it changes into `path`
    finally:
        os.chdir(cwd)
    seconds = time.time() - t0
    fields, tails, steps = [], [], 0
    for i, o in enumerate(case.observers):
        data = np.loadtxt(os.path.join(path, f"obs{i}"), comments="%")
        t, ez = data[:, 0], data[:, 3]
        steps = len(t)
        dt = np.diff(t)
        w = np.exp(-2j * math.pi * FREQUENCY_HZ * t)
        # Trapezoid rule over the (uniform) time steps.
        terms = 0.5 * (ez[1:] * w[1:] + ez[:-1] * w[:-1]) * dt
        fields.append([np.sum(terms[t[1:] <= cut * (1 + 1e-9)]) for cut in RECORD_CUTS_S])
        tail = np.max(np.abs(ez[int(0.95 * len(ez)):])) / max(np.max(np.abs(ez)), 1e-300)
        tails.append(tail)
    cells = (len(x) - 1) * (len(y) - 1) * (len(z) - 1)
    log(f"  openEMS {case.name} scale {scale:g} {'plate' if with_boxes else 'free'}: {cells / 1e6:.2f} M cells, "
        f"{steps} samples to {t[-1] * 1e9:.1f} ns, {seconds:.0f} s, last 5 % of the record ≤ {max(tails):.1e} of its peak")
    if not keep:
        shutil.rmtree(path, ignore_errors=True)
    fields = np.array(fields)  # observer × cut
    return {"fields": fields[:, -1], "fields_by_cut": fields, "cells": cells, "steps": steps, "seconds": seconds,
            "tail": max(tails)}


def ratio(case: Case, scale: float, gap_m: float, work_dir: str, log=print) -> dict:
    """E/E_free at every observer (plate run over free run on the same mesh), with both runs' facts."""
    plate = run(case, scale, gap_m, True, work_dir, log=log)
    free = run(case, scale, gap_m, False, work_dir, log=log)
    by_cut = plate["fields_by_cut"] / free["fields_by_cut"]  # observer × cut
    r = by_cut[:, -1]
    # How far the ratio moves between the records cut at RECORD_CUTS_S: the record's own error.
    truncation = np.max(np.abs(by_cut - r[:, None]), axis=1)
    return {"ratio": r, "truncation": truncation, "plate": plate, "free": free}
