#!/usr/bin/python3
"""A prototype for plate corners (issue #33): first-order diffraction with each edge's term weighted by the Fresnel
truncation of its edge integral at both ends, plus a plate term that keeps every shadow and reflection boundary
continuous, against the cached FDTD of the plate cases.

  /usr/bin/python3 bench/fullwave/corner_term.py --rfidray build/rfidray -o bench/results/fullwave

The model, for a flat metal plate P with edges i:

  h = GO + Σᵢ Wᵢ·cᵢ + c₀·K_through + c_r·K_reflected

- cᵢ: rfidray's first-order term of edge i as if infinite (`link --json`, level full, `--double-diffraction-max 0`,
  on a 10 m half-plane carrying the edge's line), with its Keller point wherever it falls on the line.
- Wᵢ = T(z₀) + T(z₁) − 1: the share of the edge integral's stationary-phase value the segment [z₀, z₁] carries,
  T(z_end) = the Fresnel integral over the exact detour from that end outwards (1 deep inside, ½ at the end, 0 far past).
- K: what paraxial Kirchhoff (physical optics) theory of the same plate gives beyond the same sum of its
  geometrical-optics and weighted infinite-edge terms. With the path's phase expanded to second order about its
  stationary point P₀ in the plate's plane (where the straight line A → T crosses it; for the reflection, the line
  from A's image), the Fresnel integral of a region R is the share F(R) of ∫∫ e^{−jk xᵀHx/2} over the plane (H the
  Hessian of |A − P| + |P − T| in the plane): the plate's blocking is 1 − F(P), an infinite edge's term
  [P₀ ∈ Hᵢ] − F(Hᵢ) (Hᵢ the half-plane beyond edge i's line that holds the plate), and
      K_through = ([P₀ ∈ P] − F(P)) − Σᵢ Wᵢ·([P₀ ∈ Hᵢ] − F(Hᵢ)),   K_reflected = −K_through at the image's P₀.
  Across edge i's shadow (reflection) boundary K jumps by exactly (step − Wᵢ)·c: what the truncated edge term
  leaves of the geometrical-optics jump; elsewhere it is continuous (the indicator functions jump only there). Far
  from corners it vanishes (Wᵢ → 1 and F(P) → F(Hᵢ) near one edge; for a strip, F is additive): it is a corner term.
  F(P) of a convex polygon is the sum over its sides of the signed triangles (P₀, side), each
  (1/2π)[Δθ − e^{−jd²} ∫ e^{−jd²t²}/(1 + t²) dt] in the coordinates y = Lx, LᵀL = kH/2 (d the side's distance from
  P₀ there, t = tan of the angle from its foot).
Everything else (direct, reflection, the plate's edge near field) is rfidray's first-order `full` on the plate. With
every W a step and K = 0 the assembly reproduces rfidray's first-order `full` (checked, 1e-9). FDTD from
OUT/<case>.csv (nothing recomputed). Writes OUT/corner_term.md; exit 2 when a CSV or the binary is missing.
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
from scipy.integrate import quad

import case_table
import cases
from corner_truncation import fresnel_phi
from geometry import K_RAD_M, Box
import rfidray_link
from rfidray_link import link_json, write_obj

FIRST_ORDER = ["--double-diffraction-max", "0"]
CASES = ("plate_corner_steep", "plate_corner", "plate_corner_line", "plate_grazing")


def fail(msg):
    print("corner_term: error: " + msg, file=sys.stderr)
    sys.exit(2)


def share_beyond(delta):
    """∫_δ^∞ e^{−jt²} dt / ∫_{−∞}^∞ e^{−jt²} dt = ½ − Φ(δ√(2/π))/(1 − j), Φ = C − jS."""
    return 0.5 - fresnel_phi(delta * math.sqrt(2.0 / math.pi)) / (1 - 1j)


def end_share(a, t, end, outward, k):
    """T(end): the share of the (infinite) edge integral on the inner side of `end`, the edge running from `end`
    along −outward. Exact detour, no amplitude correction."""
    d = -outward
    ra, rt = a - end, t - end
    za, zt = ra @ d, rt @ d
    rho_a, rho_t = np.linalg.norm(ra - za * d), np.linalg.norm(rt - zt * d)
    zq = za + (zt - za) * rho_a / (rho_a + rho_t)
    path = lambda z: np.linalg.norm(a - (end + z * d)) + np.linalg.norm(t - (end + z * d))
    lq = path(zq)
    u0 = math.copysign(math.sqrt(max(0.0, 2.0 * k / math.pi * (path(0.0) - lq))), 0.0 - zq)
    # the share of ∫ over z ≥ 0: beyond u0 in the Fresnel variable
    return 0.5 - fresnel_phi(u0) / (1 - 1j), zq


def oscillating(d, t0, t1):
    """∫_{t0}^{t1} e^{−jd²t²}/(1 + t²) dt (finite limits)."""
    if t0 == t1:
        return 0j
    re = quad(lambda x: math.cos(d * d * x * x) / (1 + x * x), t0, t1, limit=400)[0]
    im = quad(lambda x: -math.sin(d * d * x * x) / (1 + x * x), t0, t1, limit=400)[0]
    return re + 1j * im


def polygon_share(ys):
    """F of the convex polygon with vertices ys (2-D, counter-clockwise) about the origin, e^{−j|y|²} weight."""
    total = 0j
    n = len(ys)
    for i in range(n):
        p, q = ys[i], ys[(i + 1) % n]
        e = q - p
        length = np.linalg.norm(e)
        u = e / length
        foot = p - (p @ u) * u  # the foot of the perpendicular from the origin on the side's line
        d = np.linalg.norm(foot)
        cross = p[0] * q[1] - p[1] * q[0]
        dtheta = math.atan2(cross, p @ q)  # signed angle subtended at the origin
        if d < 1e-12:
            continue  # the side's line passes through the origin: the triangle is degenerate
        # t = tan(θ − θ_foot): the signed distance along the side from the foot, over d (the sense of p → q as
        # seen from the origin: counter-clockwise when the origin is on the side's left)
        sense = 1.0 if (foot[0] * u[1] - foot[1] * u[0]) > 0 else -1.0
        tp, tq = sense * (p @ u) / d, sense * (q @ u) / d
        total += (dtheta - cmath.exp(-1j * d * d) * oscillating(d, tp, tq)) / (2 * math.pi)
    return total


def plane_frame(normal):
    e1 = np.cross(normal, [1.0, 0.0, 0.0])
    if np.linalg.norm(e1) < 0.1:
        e1 = np.cross(normal, [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(normal, e1)


def k_term(src, tag, corners, normal, k):
    """([P₀∈P] − F(P), [(inside_i, F(H_i))]) for the line src → tag crossing the plate's plane, or None."""
    hs, ht = (src - corners[0]) @ normal, (tag - corners[0]) @ normal
    if hs * ht >= 0.0:
        return None
    p0 = src + (tag - src) * hs / (hs - ht)
    b1, b2 = plane_frame(normal)
    basis = np.stack([b1, b2])
    hess = np.zeros((2, 2))
    for x in (src, tag):
        r = x - p0
        rn = np.linalg.norm(r)
        uh = r / rn
        pu = basis @ uh
        hess += (np.eye(2) - np.outer(pu, pu)) / rn
    lmat = np.linalg.cholesky(0.5 * k * hess).T  # LᵀL = kH/2
    xs = [basis @ (c - p0) for c in corners]
    ys = [lmat @ x for x in xs]
    area = sum(ys[i][0] * ys[(i + 1) % 4][1] - ys[i][1] * ys[(i + 1) % 4][0] for i in range(4))
    if area < 0:
        ys = ys[::-1]
        xs = xs[::-1]
    inside_p = all((xs[(i + 1) % 4] - xs[i])[0] * (-xs[i][1]) - (xs[(i + 1) % 4] - xs[i])[1] * (-xs[i][0]) > 0
                   for i in range(4))
    fp = polygon_share(ys)
    halves = []
    linv_t = np.linalg.inv(lmat).T
    for i in range(4):
        a2, b2_ = xs[i], xs[(i + 1) % 4]
        e = b2_ - a2
        n_in = np.array([-e[1], e[0]])  # left of a counter-clockwise side: inward
        n_in /= np.linalg.norm(n_in)
        inside = n_in @ (-a2) > 0  # origin (P₀) inside the half-plane
        m = linv_t @ n_in
        delta = (n_in @ a2) / np.linalg.norm(m)  # half-plane {m̂·y ≥ δ}
        halves.append((inside, share_beyond(delta)))
    return (1.0 if inside_p else 0.0) - fp, halves


class PlateModel:
    """rfidray's first-order `full` for a case's one horizontal plate, step-weighted (as rfidray), truncated, and
    truncated with the corner term, at any tag position (h/h₀)."""

    def __init__(self, binary, case, scratch):
        self.binary, self.case, self.k = binary, case, K_RAD_M
        box = case.boxes[0]
        lo, hi = np.array(box.lo, float), np.array(box.hi, float)
        z = lo[2]
        self.corners = [np.array([lo[0], lo[1], z]), np.array([hi[0], lo[1], z]), np.array([hi[0], hi[1], z]),
                        np.array([lo[0], hi[1], z])]
        self.normal = np.array([0.0, 0.0, 1.0])
        self.plate = write_obj(case, os.path.join(scratch, case.name + ".obj"))
        big = dataclasses.replace(case, name=case.name + "_big", boxes=(Box((-10, -10, z), (10, 10, z), "metal"),))
        self.big_scene = write_obj(big, os.path.join(scratch, big.name + ".obj"))
        self.edges = []
        for i in range(4):
            p, q = self.corners[i], self.corners[(i + 1) % 4]
            d = (q - p) / np.linalg.norm(q - p)
            inward = np.cross(self.normal, d)  # left of the counter-clockwise side
            # A 10 m half-plane on the plate's side of the edge's line.
            lo_b = [min(p[0], q[0]) - 10, min(p[1], q[1]) - 10, z]
            hi_b = [max(p[0], q[0]) + 10, max(p[1], q[1]) + 10, z]
            axis = 1 if abs(d[0]) > 0.5 else 0
            if inward[axis] > 0:
                lo_b[axis] = p[axis]
            else:
                hi_b[axis] = p[axis]
            hp = dataclasses.replace(case, name=f"{case.name}_e{i}", boxes=(Box(tuple(lo_b), tuple(hi_b), "metal"),))
            on_line = (lambda p=p, d=d: (lambda x: np.linalg.norm(np.cross(x - p, d)) < 1e-6))()
            self.edges.append((p, q, d, write_obj(hp, os.path.join(scratch, hp.name + ".obj")), on_line))

    def _paths(self, scene, tag):
        j = link_json(self.binary, scene, self.case, tag, "full", extra_args=FIRST_ORDER)
        return rfidray_link.weighted_paths(j, self.case, tag), complex(j["ideal"]["h"]["re"], j["ideal"]["h"]["im"])

    def evaluate(self, tag, check=True):
        src, k = np.array(self.case.source, float), self.k
        paths, h0 = self._paths(self.plate, tag)
        first = sum(c for _, _, c in paths) / h0
        on_edges = lambda kind, pts: kind == "diffraction" and any(e[4](pts[0]) for e in self.edges)
        rest = sum(c for kind, pts, c in paths if not on_edges(kind, pts))
        step, trunc, weights = rest, rest, []
        for p, q, d, scene, on_line in self.edges:
            alone, _ = self._paths(scene, tag)
            term = [c for kind, pts, c in alone if kind == "diffraction" and on_line(pts[0])]
            t0, zq = end_share(src, tag, p, -d, k)
            t1, _ = end_share(src, tag, q, d, k)
            w = t0 + t1 - 1.0
            weights.append(w)
            if term:
                step += term[0] * (1.0 if 0.0 <= zq <= np.linalg.norm(q - p) else 0.0)
                trunc += term[0] * w
        step, trunc = step / h0, trunc / h0
        corner = trunc
        kt = k_term(src, tag, self.corners, self.normal, k)
        if kt is not None:
            base, halves = kt
            corner += base - sum(w * ((1.0 if ins else 0.0) - fh) for w, (ins, fh) in zip(weights, halves))
        image = src - 2.0 * ((src - self.corners[0]) @ self.normal) * self.normal
        kr = k_term(image, tag, self.corners, self.normal, k)
        if kr is not None:
            big_paths, _ = self._paths(self.big_scene, tag)
            cr = sum(c for kind, _, c in big_paths if kind == "reflection") / h0
            base, halves = kr
            corner -= cr * (base - sum(w * ((1.0 if ins else 0.0) - fh) for w, (ins, fh) in zip(weights, halves)))
        if check and abs(first - step) > 1e-9:
            fail(f"{self.case.name} {tag}: the step assembly ({step}) does not reproduce rfidray's first order ({first})")
        return first, trunc, corner


def continuity(binary, scratch):
    """h/h₀ 1e-6 rad either side of boundaries near plate_corner_steep's corner: each model's change."""
    case = cases.plate_corner_steep()
    model = PlateModel(binary, case, scratch)
    src = np.array(case.source, float)
    lines = []
    # The shadow boundary of the edge y = 0 (the plane through the source and that edge's line), 10 cm below the
    # plate, where the line from the source passes the edge at x = 0.03 (inside) and x = −0.03 (past its end); the
    # same for the reflection boundary above (the source's image). And the end cone of the edge y = 0 at the corner.
    def through(px, z, image=False):
        s = src.copy()
        if image:
            s[2] = -s[2]
        f = (s[2] - z) / s[2]
        return s + f * (np.array([px, 0.0, 0.0]) - s)
    probes = []
    for px in (0.03, -0.03):
        for z, image, name in ((-0.10, False, "shadow boundary"), (0.10, True, "reflection boundary")):
            on = through(px, z, image)
            # across the boundary: move along y (the boundary plane holds the edge's line, x)
            probes.append((f"{name} of the edge y = 0, passing x = {px:+.2f}", on, np.array([0.0, 1.0, 0.0])))
    # The end cone of the edge y = 0 at the corner: tags whose Keller point on the line y = 0 is x = 0.
    t = np.array([0.0, -0.15, -0.10])
    # move along x until z_Q = 0: for the line y = z = 0, z_Q = z_a + (z_t − z_a)·ρ_a/(ρ_a + ρ_t)
    rho_a, rho_t = math.hypot(src[1], src[2]), math.hypot(t[1], t[2])
    t[0] = -src[0] * rho_t / rho_a
    probes.append(("end cone of the edge y = 0 at the corner", t, np.array([1.0, 0.0, 0.0])))
    delta = 1e-3  # beyond the tracer's float band (4e-4 m here): the jump, with the smooth change extrapolated out
    for name, p, along in probes:
        h = {sd: model.evaluate(p + sd * along, check=False) for sd in (-2 * delta, -delta, delta, 2 * delta)}
        jumps = [abs(2.0 * (h[delta][i] - h[-delta][i]) - (h[2 * delta][i] - h[-2 * delta][i])) for i in range(3)]
        lines.append(f"| {name} | {p[0]:+.4f}, {p[1]:+.4f}, {p[2]:+.4f} | {jumps[0]:.4f} | {jumps[1]:.4f} | "
                     f"{jumps[2]:.4f} |")
        print(lines[-1], flush=True)
    return ["", "Continuity near plate_corner_steep's corner: the jump of h/h₀ across each (2Δ(1 mm) − Δ(2 mm), Δ(δ) = h(+δ) − h(−δ): the smooth change "
            "cancels to first order; first order / truncated / with the corner term):", "", "| where | tag (m) | first order | truncated | with the corner term |",
            "|---|---|---|---|---|"] + lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rfidray", default="build/rfidray")
    ap.add_argument("-o", "--out", default="bench/results/fullwave")
    a = ap.parse_args()
    if not os.path.isfile(a.rfidray):
        fail(a.rfidray + ": no rfidray binary")
    scratch = tempfile.mkdtemp(prefix="corner-term-")
    out_rows = []
    for name in CASES:
        case = getattr(cases, name)()
        rows = case_table.rows_by_observer(a.out, name, "corner_term", [o.label for o in case.observers])
        model = PlateModel(a.rfidray, case, scratch)
        for o in case.observers:
            r = rows[o.label]
            f = case_table.ratio(r, "fdtd")
            first, trunc, corner = model.evaluate(np.array(o.position, float))
            out_rows.append((name, o.label, o.krho, f, first, trunc, corner))
            print(name, o.label, f"fdtd {abs(f):.3f} first {abs(first - f):.3f} trunc {abs(trunc - f):.3f} "
                  f"corner {abs(corner - f):.3f}", flush=True)
    lines = ["# Plate corners: truncated edges plus a Kirchhoff corner term (prototype)", "",
             "`/usr/bin/python3 bench/fullwave/corner_term.py --rfidray build/rfidray -o bench/results/fullwave` (the "
             "script's header says what the model is). Errors |h/h₀ − E/E₀| against each case's cached FDTD, a "
             "fraction of the free-space field; `first order` is rfidray's `full` with `--double-diffraction-max 0`.",
             "", "| case | observer | kρ | FDTD \\|E/E₀\\| | first order (error) | truncated (error) | "
             "truncated + corner term (error) |", "|---|---|---|---|---|---|---|"]
    for name, label, krho, f, first, trunc, corner in out_rows:
        lines.append(f"| {name} | {label} | {krho:.2f} | {abs(f):.3f} | {abs(first):.3f} ({abs(first - f):.3f}) | "
                     f"{abs(trunc):.3f} ({abs(trunc - f):.3f}) | {abs(corner):.3f} ({abs(corner - f):.3f}) |")
    lines.append("")
    for name in CASES:
        sel = [r for r in out_rows if r[0] == name]
        e = lambda i: [abs(r[i] - r[3]) for r in sel]
        lines.append(f"- {name} ({len(sel)} observers), median / max error: first order {np.median(e(4)):.3f} / "
                     f"{max(e(4)):.3f}; truncated {np.median(e(5)):.3f} / {max(e(5)):.3f}; with the corner term "
                     f"{np.median(e(6)):.3f} / {max(e(6)):.3f}")
    lines += continuity(a.rfidray, scratch)
    text = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "corner_term.md"), "w") as fh:
        fh.write(text)
    print(text)


if __name__ == "__main__":
    main()
