#!/usr/bin/env python3
"""Where `full` goes wrong in the rack bay (case rack_bay): its field at each observer split by the edges it comes
from (and its second-order diffraction, kind diffraction2), against the FDTD table, and what the missing
diffraction-then-reflection paths would add.

`full` diffracts once at every edge and twice between two edges (raytrace/double_diffraction.cpp); it has no path
that diffracts and then reflects. Those paths are computed
here by images: with the plates perfect conductors and the dipoles along z (normal to the plates), a path that
diffracts at an edge of one plate and then reflects in the other plate's plane is the diffracted path of that
edge alone to the tag's image in the other plate's plane, with the same sign (the normal field keeps its sign
in a perfect conductor). The reflection point lies on the plate for every observer of the case (checked).

    python3 bench/fullwave/bay_paths.py --rfidray build/rfidray -o bench/results/fullwave

Reads bench/results/fullwave/rack_bay.csv (the FDTD reference of run.py); writes rack_bay_paths.md.
"""
from __future__ import annotations

import argparse
import cmath
import csv
import os
import tempfile

import numpy as np

from cases import CASES
from geometry import Case
import rfidray_link as rl


def weighted_paths(binary, scene, case, position, reference=None):
    """[(kind, first interaction point or None, contribution with the short-dipole weights / h_ideal)], h_ideal and
    the direct line's weight taken at `reference` (default: `position`; an image's paths are referred to the tag)."""
    j = rl.link_json(binary, scene, case, position, "full")
    src, tag = np.array(case.source, float), np.array(position, float)
    axis = np.array(rl.axis_vector(case.axis), float)
    ref = position if reference is None else reference
    h0 = complex(j["ideal"]["h"]["re"], j["ideal"]["h"]["im"])
    if reference is not None:
        ideal = rl.link_json(binary, scene, case, ref, "los")["ideal"]["h"]
        h0 = complex(ideal["re"], ideal["im"])
    los = np.array(ref, float) - src
    w_los = rl._hertz_weight(axis, los) * rl._hertz_weight(axis, -los)
    out = []
    for p in j["raytraced"]["paths"]:
        pts = [np.array(q) for q in p["points"]] if p["kind"] not in ("los", "blocked") else []
        first = (pts[0] if pts else tag) - src
        last = tag - (pts[-1] if pts else src)
        probe = 1.0 if p["kind"] == "edge-near-field" else rl._hertz_weight(axis, last)
        w = rl._hertz_weight(axis, first) * probe / w_los
        c = complex(p["contribution"]["re"], p["contribution"]["im"]) * w / h0
        out.append((p["kind"], pts[0] if pts else None, c))
    return out, h0


def edge_group(point):
    """Which edges of the bay a diffraction point is on (case rack_bay: plates y ∈ [0, 0.5], x ∈ ±0.45)."""
    x, y, _ = point
    if abs(y) < 1e-6:
        return "front"
    if abs(y - 0.5) < 1e-6:
        return "back"
    return "sides"


def fmt(c):
    return f"{abs(c):.3f}∠{cmath.phase(c):+.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rfidray", required=True)
    ap.add_argument("-o", "--out", default="bench/results/fullwave")
    args = ap.parse_args()
    case = CASES["rack_bay"]()
    top, bottom = case.boxes
    ref = {}
    with open(os.path.join(args.out, "rack_bay.csv")) as f:
        for r in csv.DictReader(f):
            ref[r["observer"]] = cmath.rect(float(r["fdtd_abs"]), float(r["fdtd_arg_rad"]))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        def scene(boxes, name):
            c = Case(name=name, description=name, boxes=boxes, source=case.source, axis=case.axis, observers=(),
                     domain_lo=case.domain_lo, domain_hi=case.domain_hi, polarization_name="", symmetries=())
            return rl.write_obj(c, os.path.join(tmp, name + ".obj"))
        both, only_top, only_bottom = scene((top, bottom), "bay"), scene((top,), "top"), scene((bottom,), "bottom")
        zt, zb = top.lo[2], bottom.lo[2]
        for o in case.observers:
            x, y, z = o.position
            paths, _ = weighted_paths(args.rfidray, both, case, o.position)
            groups = {"los": 0j, "front": 0j, "back": 0j, "sides": 0j, "near": 0j, "diffraction2": 0j}
            for kind, point, c in paths:
                if kind == "los":
                    groups["los"] += c
                elif kind == "edge-near-field":
                    groups["near"] += c
                elif kind == "diffraction":
                    groups[edge_group(point)] += c
                else:
                    groups.setdefault(kind, 0j)
                    groups[kind] += c
            full = sum(c for _, _, c in paths)
            dr = 0j
            # Diffracted by the top plate, reflected in the bottom plate's plane (tag image 2·zb − z), and the
            # converse; the reflection point must lie on the plate (y within it) for the image to stand for it.
            for plate_scene, mirror_z in ((only_top, zb), (only_bottom, zt)):
                image = (x, y, 2.0 * mirror_z - z)
                for kind, point, c in weighted_paths(args.rfidray, plate_scene, case, image, o.position)[0]:
                    if kind != "diffraction":
                        continue
                    q = np.array(point)
                    t = (mirror_z - q[2]) / (image[2] - q[2])
                    hit = q + t * (np.array(image) - q)
                    if 0.0 <= t <= 1.0 and 0.0 <= hit[1] <= 0.5 and abs(hit[0]) <= 0.45:
                        dr += c
            e = ref[o.label]
            rows.append((o, e, groups, full, dr))
    lines = [
        "# rack_bay: where `full` goes wrong",
        "",
        "Produced by `python3 bench/fullwave/bay_paths.py --rfidray build/rfidray -o bench/results/fullwave` "
        "(the FDTD column is rack_bay.csv's reference). Fields are fractions of the free-space field, short-dipole "
        "weighted as in the FDTD tables; `full` split by the edges its first-order diffracted paths come from and its "
        "second-order diffraction (`diffraction2`, both edges; first order = `full` without it); D-R is the sum of "
        "the paths that diffract at one plate and reflect in the other (not in `full`; computed by images).",
        "",
        "| observer | FDTD | `los` error | `full` | front edges | back edges | side edges | near field | second order | `full` error | first-order `full` error | first order without the back edges: error | D-R | `full` + D-R error |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for o, e, g, full, dr in rows:
        first = full - g["diffraction2"]
        lines.append(f"| {o.label} | {fmt(e)} | {abs(1 - e):.3f} | {fmt(full)} | {fmt(g['front'])} | {fmt(g['back'])} | "
                     f"{fmt(g['sides'])} | {fmt(g['near'])} | {fmt(g['diffraction2'])} | {abs(full - e):.3f} | "
                     f"{abs(first - e):.3f} | {abs(first - g['back'] - e):.3f} | {fmt(dr)} | {abs(full + dr - e):.3f} |")
    med = lambda v: float(np.median(v))
    lines += ["", "Median error over the 11 observers: `los` {:.3f}, `full` {:.3f}, first-order `full` {:.3f}, "
              "first order without the back edges {:.3f}, `full` + D-R {:.3f}.".format(
                  med([abs(1 - e) for _, e, _, _, _ in rows]),
                  med([abs(f - e) for _, e, _, f, _ in rows]),
                  med([abs(f - g['diffraction2'] - e) for _, e, g, f, _ in rows]),
                  med([abs(f - g['diffraction2'] - g['back'] - e) for _, e, g, f, _ in rows]),
                  med([abs(f + d - e) for _, e, _, f, d in rows]))]
    path = os.path.join(args.out, "rack_bay_paths.md")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
