#!/usr/bin/python3
"""A prototype for the plate corner (issue #33, case g): first-order edge diffraction with each edge's term weighted
by the share of its Fresnel zone that lies on the edge, against the same cached FDTD.

  /usr/bin/python3 bench/fullwave/corner_truncation.py --rfidray build/rfidray -o bench/results/fullwave

rfidray's first-order diffraction takes each edge as infinite and drops its term when the Keller point falls past an
end (docs/fullwave.md, "Where `full` is discontinuous"). Here, for the two edges that meet at case (g)'s corner
(y = 0 and x = 0, each 0.6 m), the infinite edge's term is read from rfidray itself (`link --json`, level full,
`--double-diffraction-max 0`, on a 10 m half-plane carrying that edge's line) and weighted by the uniform endpoint
truncation of the edge integral, T = [Φ(u₁) − Φ(u₀)] / (1 − j), Φ(u) = C(u) − j S(u) (Fresnel integrals,
scipy.special.fresnel), u_end = sign(z_end − z_Q)·√((2k/π)(L(z_end) − L(z_Q))) with L(z) the path length A → edge
point → T (the exact phase detour, not its quadratic): T → 1 with Q deep inside, ½ with Q at an end, → 0 far past it.
Everything else (direct, reflection, the plate's other two edges, the edge near field) is rfidray's first-order
`full` on the 0.6 m plate. The same assembly with T a step (1 on the edge, 0 off it) reproduces rfidray's own
first-order `full`, which checks it. No corner term: this keeps the jump across the shadow boundaries near the
corner that truncation moves there. FDTD from OUT/plate_corner.csv (run.py --case plate_corner; nothing recomputed).
Writes OUT/corner_truncation.md; exit 2 when the CSV or the binary is missing.
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import os
import sys
import tempfile

import numpy as np
from scipy.special import fresnel

import case_table
import cases
from geometry import K_RAD_M, Box
import rfidray_link
from rfidray_link import link_json, write_obj

FIRST_ORDER = ["--double-diffraction-max", "0"]


def fail(msg):
    print("corner_truncation: error: " + msg, file=sys.stderr)
    sys.exit(2)


def weighted_paths(j, case, tag):
    """rfidray_link's weighted paths and the ideal channel's h."""
    return rfidray_link.weighted_paths(j, case, tag), complex(j["ideal"]["h"]["re"], j["ideal"]["h"]["im"])


def fresnel_phi(u):
    s, c = fresnel(u)
    return c - 1j * s


def truncation(a, t, start, d, length, k):
    """(T, z_Q): the share of the edge integral's stationary-phase value carried by [0, length] along start + z·d."""
    ra, rt = a - start, t - start
    za, zt = ra @ d, rt @ d
    rho_a, rho_t = np.linalg.norm(ra - za * d), np.linalg.norm(rt - zt * d)
    zq = za + (zt - za) * rho_a / (rho_a + rho_t)
    path = lambda z: np.linalg.norm(a - (start + z * d)) + np.linalg.norm(t - (start + z * d))
    lq = path(zq)
    u = lambda z: math.copysign(math.sqrt(max(0.0, 2.0 * k / math.pi * (path(z) - lq))), z - zq)
    return (fresnel_phi(u(length)) - fresnel_phi(u(0.0))) / (1 - 1j), zq


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rfidray", default="build/rfidray")
    ap.add_argument("-o", "--out", default="bench/results/fullwave")
    a = ap.parse_args()
    if not os.path.isfile(a.rfidray):
        fail(a.rfidray + ": no rfidray binary")
    case = cases.plate_corner()
    fdtd = {label: case_table.ratio(r, "fdtd") for label, r in
            case_table.rows_by_observer(a.out, "plate_corner", "corner_truncation",
                                        [o.label for o in case.observers]).items()}
    scratch = tempfile.mkdtemp(prefix="corner-truncation-")
    plate = write_obj(case, os.path.join(scratch, "plate.obj"))
    # Each corner edge alone, as the edge of a 10 m half-plane on the same line (its term as if infinite).
    half_planes = {
        "y = 0": dataclasses.replace(case, name="y0", boxes=(Box((-5.0, 0.0, 0.0), (5.0, 5.0, 0.0), "metal"),)),
        "x = 0": dataclasses.replace(case, name="x0", boxes=(Box((0.0, -5.0, 0.0), (5.0, 5.0, 0.0), "metal"),)),
    }
    edges = {  # start, direction, length, on the line
        "y = 0": (np.zeros(3), np.array([1.0, 0.0, 0.0]), 0.6, lambda q: abs(q[1]) < 1e-6 and abs(q[2]) < 1e-6),
        "x = 0": (np.zeros(3), np.array([0.0, 1.0, 0.0]), 0.6, lambda q: abs(q[0]) < 1e-6 and abs(q[2]) < 1e-6),
    }
    scenes = {name: write_obj(c, os.path.join(scratch, c.name + ".obj")) for name, c in half_planes.items()}
    src = np.array(case.source)
    rows = []
    for o in case.observers:
        tag = np.array(o.position, float)
        paths, h0 = weighted_paths(link_json(a.rfidray, plate, case, tag, "full", extra_args=FIRST_ORDER), case, tag)
        first = sum(c for _, _, c in paths) / h0
        on_corner_edges = lambda kind, pts: kind == "diffraction" and any(e[3](pts[0]) for e in edges.values())
        rest = sum(c for kind, pts, c in paths if not on_corner_edges(kind, pts))
        step, trunc, shares = rest, rest, []
        for name, (start, d, length, on_line) in edges.items():
            alone, _ = weighted_paths(link_json(a.rfidray, scenes[name], case, tag, "full", extra_args=FIRST_ORDER),
                                      case, tag)
            term = [c for kind, pts, c in alone if kind == "diffraction" and on_line(pts[0])]
            if not term:
                continue
            t, zq = truncation(src, tag, start, d, length, K_RAD_M)
            step += term[0] * (1.0 if 0.0 <= zq <= length else 0.0)
            trunc += term[0] * t
            shares.append(f"{name}: z_Q {zq:+.3f} m, \\|T\\| {abs(t):.2f}")
        step, trunc = step / h0, trunc / h0
        rows.append((o.label, fdtd[o.label], first, step, trunc, "; ".join(shares)))
    for label, _, first, step, _, _ in rows:
        if abs(first - step) > 1e-9:
            fail(f"{label}: the step assembly ({step}) does not reproduce rfidray's first order ({first})")
    err = lambda i: [abs(r[i] - r[1]) for r in rows]
    lines = ["# Plate corner: first-order diffraction with Fresnel truncation at the edges' ends (prototype)", "",
             "`/usr/bin/python3 bench/fullwave/corner_truncation.py --rfidray build/rfidray -o bench/results/fullwave`"
             " (see the script's header). Errors |h/h₀ − E/E₀| against case (g)'s FDTD; `first order` is rfidray's "
             "`full` with `double_diffraction_max_m = 0` (the step assembly reproduces it to 1e-9); `truncated` "
             "weights the two corner edges' terms by T. No corner term.", "",
             "| observer | FDTD \\|E/E₀\\| | first order \\|h/h₀\\| (error) | truncated (error) | corner edges |",
             "|---|---|---|---|---|"]
    for label, f, first, _, trunc, shares in rows:
        lines.append(f"| {label} | {abs(f):.3f} | {abs(first):.3f} ({abs(first - f):.3f}) | "
                     f"{abs(trunc):.3f} ({abs(trunc - f):.3f}) | {shares} |")
    lines += ["", f"Median / max error: first order {np.median(err(2)):.3f} / {max(err(2)):.3f}; truncated "
                  f"{np.median(err(4)):.3f} / {max(err(4)):.3f} ({len(rows)} observers)."]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "corner_truncation.md"), "w") as fh:
        fh.write(text)
    print(text)


if __name__ == "__main__":
    main()
