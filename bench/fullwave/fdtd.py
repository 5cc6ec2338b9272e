"""The FDTD side: a case (geometry.Case) in meep, one CW point dipole, the complex field at every observer.

Units: meep's length unit is 1 m, so its frequency is f/c in 1/m and its time is metres of light travel.
Fields in meep go as e^{-iωt}; rfidray's h as e^{+jωt} (e^{-jkL}, core/path.h): ratios are conjugated before they
are compared (compare.py). The complex amplitude comes from a least-squares fit of a·cos ωt + b·sin ωt to the
real field over the last two periods (A = a + ib); the change between the fits of the last two single periods is
reported as the run's distance from steady state.

Sheets (a Box with one zero extent) are one grid plane of tangential E forced to zero: a metal block thinner than
half a cell centred on that plane, with eps_averaging off (meep then reads the material at the field points, and
the plane carries E_x and E_z, say, for a sheet in y = const). The sheet's plane must be on the grid: the domain is
snapped to whole cells. `sheet_thickness_m > 0` instead gives sheets that thickness (a solid block).
A sheet with `slab_m > 0` (a wall) is a solid block of that thickness behind its plane. Dielectrics: meep's
ε(ω) = ε'(1 + iσ_D/ω) with ω = 2πf/c in 1/m (time in metres of light travel), and the physical
ε_c = ε' + iσ/(ω_phys ε0) in e^{-iωt} with ω_phys = ω·c, so σ_D = σ/(ε0 ε' c) in 1/m (concrete at 866 MHz:
σ = 0.0413 S/m, ε' = 5.24 → σ_D = 2.97 /m, σ_D/ω = tan δ = 0.164). `case.symmetries` are meep mirror planes (exact, a speed-up only).
"""
from __future__ import annotations

import math
import time

import numpy as np

from geometry import C0_M_S, FREQUENCY_HZ, Case

EPS0 = 8.8541878128e-12


def _meep():
    import meep as mp  # imported late: the rest of the harness works (and --help prints) without meep
    mp.verbosity(0)
    return mp


def _snap(v: float, d: float, up: bool) -> float:
    n = v / d
    return (math.ceil(n - 1e-9) if up else math.floor(n + 1e-9)) * d


def run(case: Case, resolution: float, dpml_m: float = 0.2, with_boxes: bool = True,
        sheet_thickness_m: float = 0.0, settle_periods: float = 20.0, log=print) -> dict:
    """Runs one FDTD simulation; returns {'fields': complex array (observers,), 'steady': array, 'seconds': ...}."""
    mp = _meep()
    d = 1.0 / resolution
    f_meep = FREQUENCY_HZ / C0_M_S  # 1/m
    period = 1.0 / f_meep
    dpml = _snap(dpml_m, d, True)
    lo = [_snap(case.domain_lo[i], d, False) - dpml for i in range(3)]
    hi = [_snap(case.domain_hi[i], d, True) + dpml for i in range(3)]
    # An even number of cells per axis: meep centres its grid on the cell's centre, which must itself be a grid
    # point so that sheet planes (whole multiples of the cell) are too.
    for i in range(3):
        if round((hi[i] - lo[i]) / d) % 2:
            hi[i] += d
    size = [hi[i] - lo[i] for i in range(3)]
    for ax, _ in case.symmetries:  # meep's mirror planes go through the cell's centre: it must be at 0 there
        i = "xyz".index(ax)
        if abs(hi[i] + lo[i]) > 1e-9:
            raise ValueError(f"case {case.name}: mirror {ax} needs a domain symmetric about {ax} = 0 "
                             f"(got {lo[i]:.4f}..{hi[i]:.4f} m with PML)")
    center = mp.Vector3(*[(hi[i] + lo[i]) / 2 for i in range(3)])
    geometry = []
    if with_boxes:
        for b in case.boxes:
            if b.material == "metal":
                medium = mp.metal
            else:
                # ε_c = ε_r − jσ/(ωε0) (e^{jωt}) is ε_r(1 + iσ_D/ω) in meep's e^{-iωt}: σ_D = σ/(ε0 ε_r c) per metre.
                medium = mp.Medium(epsilon=b.eps_r, D_conductivity=b.sigma_s_m / (EPS0 * b.eps_r * C0_M_S))
            lo_b, hi_b = list(b.lo), list(b.hi)
            t = b.thin_axis
            for i in range(3):
                if i == t and b.slab_m > 0.0:  # a wall: the solid block behind the sheet's plane, faces as given
                    lo_b[i], hi_b[i] = b.lo[i], b.lo[i] + b.slab_m
                elif case.eps_averaging and b.material != "metal":  # averaged faces: exactly where they are
                    pass
                elif i == t:
                    n = b.lo[i] / d
                    if sheet_thickness_m <= 0.0 and abs(n - round(n)) > 1e-6:
                        raise ValueError(f"case {case.name}: sheet plane {b.lo[i]} m is not on the {resolution} px/m grid")
                    half = (sheet_thickness_m / 2) if sheet_thickness_m > 0.0 else 0.25 * d
                    lo_b[i], hi_b[i] = b.lo[i] - half, b.hi[i] + half
                else:  # field points exactly on the outline belong to the box
                    lo_b[i], hi_b[i] = b.lo[i] - 0.25 * d, b.hi[i] + 0.25 * d
            geometry.append(mp.Block(center=mp.Vector3(*[(lo_b[i] + hi_b[i]) / 2 for i in range(3)]),
                                     size=mp.Vector3(*[hi_b[i] - lo_b[i] for i in range(3)]), material=medium))
    comp = {"x": mp.Ex, "y": mp.Ey, "z": mp.Ez}[case.axis]
    sources = [mp.Source(mp.ContinuousSource(frequency=f_meep, width=period), component=comp,
                         center=mp.Vector3(*case.source))]
    sim = mp.Simulation(cell_size=mp.Vector3(*size), geometry_center=center, resolution=resolution,
                        geometry=geometry, sources=sources, boundary_layers=[mp.PML(dpml)],
                        eps_averaging=case.eps_averaging,
                        symmetries=[mp.Mirror({"x": mp.X, "y": mp.Y, "z": mp.Z}[ax], phase=ph)
                                    for ax, ph in case.symmetries])
    points = [mp.Vector3(*o.position) for o in case.observers]
    t_stop = (settle_periods + 2.0) * period
    t_sample = settle_periods * period - 1e-9
    times, samples = [], []

    def sample(s):
        if s.meep_time() >= t_sample:
            times.append(s.meep_time())
            samples.append([s.get_field_point(comp, p) for p in points])

    t0 = time.time()
    sim.run(sample, until=t_stop)
    seconds = time.time() - t0
    # Each sheet must be on the grid: its tangential probe component vanishes mid-sheet (meep would otherwise
    # silently drop a sheet thinner than a cell that falls between grid planes).
    if with_boxes and sheet_thickness_m <= 0.0:
        for b in case.boxes:
            if b.thin_axis is not None and "xyz"[b.thin_axis] != case.axis and b.material == "metal" and b.slab_m == 0.0:
                mid = mp.Vector3(*[(b.lo[i] + b.hi[i]) / 2 for i in range(3)])
                ref = max(abs(v) for v in samples[-1]) if samples and samples[-1] else 1.0
                if abs(sim.get_field_point(comp, mid)) > 1e-9 * max(ref, 1e-30):
                    raise RuntimeError(f"case {case.name}: sheet {b} is not on the grid at {resolution} px/m")
    times = np.asarray(times)
    samples = np.real(np.asarray(samples))
    w = 2 * math.pi * f_meep

    def fit(mask):
        m = np.stack([np.cos(w * times[mask]), np.sin(w * times[mask])], axis=1)
        coef, *_ = np.linalg.lstsq(m, samples[mask], rcond=None)
        return coef[0] + 1j * coef[1]

    full = fit(np.ones_like(times, dtype=bool))
    mid = settle_periods * period + period
    first, second = fit(times < mid), fit(times >= mid)
    cells = int(round(np.prod(size) * resolution ** 3))
    log(f"  fdtd {case.name} res {resolution:g} px/m pml {dpml:.3f} m boxes {with_boxes} "
        f"t {sheet_thickness_m:g} m: {cells / 1e6:.2f} M cells, {seconds:.1f} s")
    return {"fields": full, "steady": np.abs(second - first), "seconds": seconds, "cells": cells,
            "resolution": resolution, "dpml_m": dpml}


def ratio(case: Case, resolution: float, dpml_m: float = 0.2, sheet_thickness_m: float = 0.0,
          settle_periods: float = 20.0, log=print, free=None) -> dict:
    """E/E_free at every observer (meep's e^{-iωt} convention) and the steady-state residual relative to |E_free|.
    `free` reuses a free-space run of the same grid."""
    if free is None:
        free = run(case, resolution, dpml_m, False, 0.0, settle_periods, log)
    geo = run(case, resolution, dpml_m, True, sheet_thickness_m, settle_periods, log)
    e0 = free["fields"]
    if np.any(np.abs(e0) == 0.0) or not np.all(np.isfinite(e0)):
        raise RuntimeError(f"case {case.name}: the free-space field is zero or not finite at an observer "
                           f"({resolution:g} px/m): a source off a mirror plane?")
    return {"ratio": geo["fields"] / e0, "steady": (geo["steady"] + free["steady"]) / np.abs(e0),
            "seconds": geo["seconds"] + free["seconds"], "free": free, "cells": geo["cells"]}
