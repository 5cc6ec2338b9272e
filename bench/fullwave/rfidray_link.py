"""The rfidray side: the case's boxes as an OBJ scene, `rfidray link --json` per level and observer, and h/h_ideal
for the same source and probe as the FDTD.

What h is (cli/cmd_link.cpp, core/path.h, core/polarization.cpp): the one-way channel
h = Σ_paths (λ/4πL)·√(G_R G_T)·(polarization match)·Γ·e^{-jkL}, with e^{+jωt}. With isotropic patterns and linear
polarization along the source axis a (antenna) and the probe axis a (tag), each path's polarization factor is the
unit field the antenna radiates along the path's first leg (a projected transverse to it, normalised), carried
through reflections and diffraction, dotted into the tag's unit transverse axis: the field of an antenna that
radiates the same amplitude in every direction, read by a tag of the same kind. The FDTD source is a short
(Hertzian) dipole, whose amplitude is |a × d| in direction d, and the FDTD probe reads E·a = |a × d|·(E·â_⊥): so
each path's contribution is weighted by |a × d_first leg|·|a × d_last leg| / (the same on the direct line), which
is exactly rfidray's per-path sum with a short-dipole pattern (rfidray's `dipole` is a half-wave dipole). In the
sheet's plane of symmetry and for a z dipole every in-plane path has weight 1; the weight matters for paths off
that plane (the sheet's top and bottom edges) and for the hard (x) dipole. The ideal channel is λ/4πD·e^{-jkD}
(polarization taken as matched), so h/h_ideal is the field over the free-space field of the same two short dipoles.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from geometry import FREQUENCY_HZ, Case, axis_vector

LEVELS = ("los", "los+blocked", "single-bounce", "double-bounce", "full-selective", "full")


def _box_faces(b):
    """Quads (4 corners each, counter-clockwise seen from outside) of a box, or the one quad of a sheet."""
    lo, hi = b.lo, b.hi
    t = b.thin_axis
    if t is not None:
        u, v = [i for i in range(3) if i != t]
        corners = []
        for cu, cv in ((lo[u], lo[v]), (hi[u], lo[v]), (hi[u], hi[v]), (lo[u], hi[v])):
            p = [0.0, 0.0, 0.0]
            p[t], p[u], p[v] = lo[t], cu, cv
            corners.append(tuple(p))
        return [corners]
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    return [
        [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],  # z = z0 (normal −z)
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # z = z1
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],  # y = y0
        [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],  # y = y1
        [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],  # x = x0
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],  # x = x1
    ]


def write_obj(case: Case, path: str) -> str:
    lines = [f"# {case.name}: {case.description}"]
    n = 0
    for i, b in enumerate(case.boxes):
        lines.append(f"o box{i}")
        lines.append(f"usemtl {b.material}")
        for quad in _box_faces(b):
            for p in quad:
                lines.append("v {:.9g} {:.9g} {:.9g}".format(*p))
            lines.append("f {} {} {} {}".format(n + 1, n + 2, n + 3, n + 4))
            n += 4
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def _hertz_weight(axis, d):
    n = np.linalg.norm(d)
    return np.linalg.norm(np.cross(axis, d / n)) if n > 0 else 0.0


def link_json(binary: str, scene: str, case: Case, position, level: str, thickness_m: float | None = None,
              extra_args=()) -> dict:
    """`rfidray link --json` for the case's source and a tag at `position` (same polarization), parsed."""
    a = axis_vector(case.axis)
    pol = "linear:{},{},{}".format(*a)
    cmd = [binary, "link", "--scene", scene, "--antenna", "{},{},{}".format(*case.source),
           "--tag", "{},{},{}".format(*position), "--level", level, "--json", "--frequency", str(FREQUENCY_HZ),
           "--antenna-pol", pol, "--tag-pol", pol, "--pattern", "isotropic", "--tag-pattern", "isotropic",
           "--candidates", "exhaustive", "--drop-db", "400"]
    if thickness_m is not None:
        cmd += ["--thickness", str(thickness_m)]
    cmd += list(extra_args)
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({r.returncode}): {r.stderr.strip()}")
    return json.loads(r.stdout)


def weighted_paths(j: dict, case: Case, position) -> list:
    """[(kind, points, contribution)] of a `link --json` result, each contribution weighted by the short dipoles'
    amplitudes (the module's header) relative to the direct line's."""
    src, tag = np.array(case.source), np.array(position, dtype=float)
    axis = np.array(axis_vector(case.axis))
    los = tag - src
    w_los = _hertz_weight(axis, los) * _hertz_weight(axis, -los)
    out = []
    for p in j["raytraced"]["paths"]:
        pts = [np.array(q) for q in p["points"]] if p["kind"] not in ("los", "blocked") else []
        first = (pts[0] if pts else tag) - src
        last = tag - (pts[-1] if pts else src)
        # The edge's near field (level full, kind edge-near-field) is read by the tag as p·E already (its radial
        # part is not transverse to any ray): only the source's Hertzian amplitude applies.
        probe = 1.0 if p["kind"] == "edge-near-field" else _hertz_weight(axis, last)
        w = _hertz_weight(axis, first) * probe / w_los
        out.append((p["kind"], pts, complex(p["contribution"]["re"], p["contribution"]["im"]) * w))
    return out


def link(binary: str, scene: str, case: Case, position, level: str, thickness_m: float | None = None,
         extra_args=()) -> dict:
    j = link_json(binary, scene, case, position, level, thickness_m, extra_args)
    h_raw = complex(j["raytraced"]["h"]["re"], j["raytraced"]["h"]["im"])
    h0 = complex(j["ideal"]["h"]["re"], j["ideal"]["h"]["im"])
    h = 0j
    for _, _, c in weighted_paths(j, case, position):
        h += c
    return {"ratio": h / h0, "ratio_isotropic": h_raw / h0, "paths": [p["kind"] for p in j["raytraced"]["paths"]]}


def case_thickness(case: Case, thickness_m: float | None = None) -> float | None:
    """The `--thickness` of a case with walls (Box.slab_m > 0; one per case), else `thickness_m`."""
    slabs = {b.slab_m for b in case.boxes if b.slab_m > 0.0}
    if len(slabs) > 1:
        raise ValueError(f"case {case.name}: walls of different thickness {sorted(slabs)} (rfidray link takes one)")
    if slabs and thickness_m is None:
        thickness_m = slabs.pop()
    return thickness_m


def all_levels(binary: str, case: Case, scratch: str, levels=LEVELS, thickness_m=None, jobs: int = 2,
               extra_args=()) -> dict:
    """{level: complex array of h/h_ideal per observer (short-dipole weighted)}, plus '<level>:isotropic'.
    A case with walls (Box.slab_m > 0) passes their thickness as `--thickness` (one per case)."""
    thickness_m = case_thickness(case, thickness_m)
    scene = write_obj(case, os.path.join(scratch, case.name + ".obj"))
    tasks = [(lv, i, o.position) for lv in levels for i, o in enumerate(case.observers)]
    with ThreadPoolExecutor(max_workers=jobs) as ex:
        res = list(ex.map(lambda t: link(binary, scene, case, t[2], t[0], thickness_m, extra_args), tasks))
    out = {lv: np.zeros(len(case.observers), complex) for lv in levels}
    raw = {lv: np.zeros(len(case.observers), complex) for lv in levels}
    for (lv, i, _), r in zip(tasks, res):
        out[lv][i] = r["ratio"]
        raw[lv][i] = r["ratio_isotropic"]
    out.update({lv + ":isotropic": raw[lv] for lv in levels})
    return out
