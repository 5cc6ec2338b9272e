#!/usr/bin/python3
"""Physical theory of diffraction (PTD) for the plate cases: physical optics (PO) of the lit face plus each straight
edge's fringe field from closed-form fringe coefficients, integrated along each FINITE edge, against the cached FDTD
(a prototype reference, not part of rfidray; issue #33).

  /usr/bin/python3 bench/fullwave/ptd_fringe.py -o bench/results/fullwave            # check + table
  /usr/bin/python3 bench/fullwave/ptd_fringe.py --check-only                           # the half-plane check only

PO is physical_optics.po_ratio (J = 2 n̂ × H_src on the face the source sees, 2 mm midpoint cells, reciprocity).
The fringe of each edge of that face (e^{+jωt} throughout; φ measured from the lit face, 0 ≤ φ ≤ nπ, n = 2 for a
sheet's edge, 1.5 for a closed box's 90° edge; β' the angle between the incident ray and the edge's unit vector t̂):

  exact (Keller) wedge coefficient, no transition function (Keller 1962, J. Opt. Soc. Am. 52, 116; the same
  bracket as Kouyoumjian & Pathak 1974, Proc. IEEE 62, 1448, eq. with F = 1; rfidray's UTD without F):
      D^ex_{s,h} = e^{-jπ/4} sin(π/n) / (n √(2πk) sin β') · [1/(cos(π/n) − cos((φ−φ')/n)) ∓ 1/(cos(π/n) − cos((φ+φ')/n))]
      (n = 2: −e^{-jπ/4}/(2√(2πk) sin β') · [sec((φ−φ')/2) ∓ sec((φ+φ')/2)], Sommerfeld's half-plane)
  PO coefficient of the lit face φ = 0 (the end-point term of the PO integral over the face; Ufimtsev's f⁽⁰⁾, g⁽⁰⁾,
  "Fundamentals of the Physical Theory of Diffraction", Wiley 2007, ch. 2; derived again here, and checked
  numerically by the check: the same residues as D^ex at the shadow and reflection boundaries φ = π ± φ'):
      D^PO_s = −e^{-jπ/4}/(2√(2πk) sin β') · (−2 sin φ' / (cos φ + cos φ'))
      D^PO_h = −e^{-jπ/4}/(2√(2πk) sin β') · ( 2 sin φ  / (cos φ + cos φ'))
  fringe coefficient D^f = D^ex − D^PO (Ufimtsev's f⁽¹⁾ = f − f⁽⁰⁾, g⁽¹⁾ = g − g⁽⁰⁾): finite at both boundaries.
  For n = 2 this is B^f_{s,h} = g(a) ∓ g(b), g(x) = sec x − tan x, a, b = (φ ∓ φ')/2 (fringe_brackets), infinite
  only at edge-on incidence with forward observation (Ufimtsev's singularity). The 'uniform' variant multiplies each
  term by the UTD transition F(2kL cos²x) (Kouyoumjian & Pathak's F; L = s s' sin²β'/(s + s') per element): an
  ad hoc uniformisation of this script, justified only by the check below (it fixes the near-edge-on points).
  Sources: the stored search corpora held none of these formula texts (only the Kouyoumjian–Pathak bracket, e.g.
  emagtech.com/wiki "SBR Method"); they are the standard ones from the references named, and every one is checked
  numerically here rather than taken on trust.
  Equivalent edge currents radiating the fringe (the Ryan–Peters / Knott–Senior "method of equivalent currents"
  form, Knott & Senior, Proc. IEEE 62 (1974) 1468; Michaeli, IEEE Trans. AP 34 (1986) 912 & 1034 gives the
  off-Keller-cone version, not used here): writing D = −e^{-jπ/4} B / (2√(2πk) sin β'),
      I = −j B_s E^i·t̂ / (kη sin²β'),   M = −j B_h η H^i·t̂ / (k sin²β')
  (normalisation derived in this script from the 2-D line-current field and verified by the check below), each edge
  element dl radiating as an electric (I dl t̂) and a magnetic (M dl t̂) current element, exact element fields
  (near-field terms kept). B is evaluated with the observer's φ (the projection of Q→T on the plane normal to
  the edge) and the incident β', φ' at each edge point Q, so off the Keller cone it is the MEC's approximation.
  The incident field at Q is the source dipole's exact field (physical_optics.dipole_fields), its direction Q − S.
The edges are integrated over their finite length only (midpoint rule, 1 mm), so a corner is where two edges'
integrals stop; nothing is added at the corner itself.

The check (always run first; --check-only stops after it): a plane wave on a PEC half-plane, normal incidence, soft (E ∥ edge) and hard
(H ∥ edge): the total field from (incident + the PO field of the lit face, integrated numerically in 2-D with a
tapered tail + the fringe, from THIS script's edge-current code integrated along a 120 m edge) against Sommerfeld's
exact solution (Fresnel integrals, scipy), at kρ = 2, 5, 20, 100 and several φ, φ' (including the shadow and
reflection boundaries), and the far-zone coefficient D^PO + D^f against Keller's.
"""
from __future__ import annotations

import argparse
import cmath
import math
import os

import numpy as np
from scipy import special

import case_table
import cases
from geometry import K_RAD_M, axis_vector
from physical_optics import C0, CASES, EPS0, dipole_fields, po_ratio

ETA0 = 1.0 / (EPS0 * C0)
SQ = math.sqrt


def brackets(phi, phi_s, n):
    """B_s, B_h of the exact (Keller) wedge coefficient and of the lit face's PO, with D = −e^{-jπ/4} B /
    (2√(2πk) sin β'). Arrays."""
    s = math.sin(math.pi / n) / n
    c = math.cos(math.pi / n)
    a = 1.0 / (c - np.cos((phi - phi_s) / n))
    b = 1.0 / (c - np.cos((phi + phi_s) / n))
    ex_s, ex_h = -2.0 * s * (a - b), -2.0 * s * (a + b)     # D = e^{-jπ/4} s (a ∓ b) / (√(2πk) sinβ') = −e^{-jπ/4}(−2s(a ∓ b))/(2√…)
    den = np.cos(phi) + np.cos(phi_s)
    po_s, po_h = -2.0 * np.sin(phi_s) / den, 2.0 * np.sin(phi) / den
    return ex_s, ex_h, po_s, po_h


def kp_transition(x):
    """Kouyoumjian–Pathak's transition function F(x) = 2j√x e^{jx} ∫_{√x}^∞ e^{−jτ²} dτ (x ≥ 0; F → 1 for large x,
    ≈ √(πx) e^{jπ/4} for small x)."""
    x = np.maximum(np.asarray(x, float), 1e-300)
    u = np.sqrt(x)
    s, c = special.fresnel(u * SQ(2 / math.pi))
    tail = SQ(math.pi / 2) * ((0.5 - 0.5j) - (c - 1j * s))
    return 2j * u * np.exp(1j * x) * tail


def fringe_brackets(phi, phi_s, n, kl=None):
    """B^f = B^ex − B^PO. For the half-plane (n = 2) in Ufimtsev's form: with a = (φ−φ')/2, b = (φ+φ')/2,
    B^ex_{s,h} = sec a ∓ sec b and B^PO_{s,h} = tan a ∓ tan b (the PO coefficient above, rewritten), so
    B^f_{s,h} = g(a) ∓ g(b), g(x) = sec x − tan x = cos x / (1 + sin x): zero at the boundaries (x = π/2), infinite
    only where sin x = −1 (edge-on incidence, observation along the face: Ufimtsev's singularity). With kl = kL
    given (L the UTD distance parameter) each term is multiplied by F(2kL cos²x), the UTD's own transition for that
    boundary (the 'uniform' fringe; see the check for where it is needed). For n ≠ 2: the difference of the
    brackets, non-uniform."""
    phi = np.array(phi, float, copy=True)
    if n == 2.0:
        a, b = 0.5 * (phi - phi_s), 0.5 * (phi + phi_s)
        ga, gb = np.cos(a) / (1.0 + np.sin(a)), np.cos(b) / (1.0 + np.sin(b))
        if kl is not None:
            ga = ga * kp_transition(2.0 * kl * np.cos(a) ** 2)
            gb = gb * kp_transition(2.0 * kl * np.cos(b) ** 2)
        return ga - gb, ga + gb
    bad = np.abs(np.cos(phi) + np.cos(phi_s)) < 1e-7
    phi[bad] += 1e-5
    ex_s, ex_h, po_s, po_h = brackets(phi, phi_s, n)
    return ex_s - po_s, ex_h - po_h


def _electric_elements_e(cur_dl, t, nn, dist, k):
    """E of electric current elements (I dl) t̂ at distances dist along unit vectors nn: the exact short-dipole
    field of p = I dl t̂ / (jω)."""
    p = cur_dl[:, None] * t[None, :] / (1j * k * C0)
    phase = np.exp(-1j * k * dist)
    nxp = np.cross(nn, p)
    return (k * k * np.cross(nxp, nn) / dist[:, None] +
            (3.0 * nn * np.sum(nn * p, axis=1)[:, None] - p) * (1.0 / dist ** 3 + 1j * k / dist ** 2)[:, None]) \
        * phase[:, None] / (4.0 * math.pi * EPS0)


def edge_fringe_field(q, t, x_e, y_e, dl, n, e_inc, h_inc, k_inc_dir, obs, k=K_RAD_M, uniform=False, s_src=None):
    """Fringe (E, H) at obs (3,) of the edge samples q (N×3) with unit vector t, in-face inward x_e, lit-side
    normal y_e (t = x_e × y_e), element length dl (scalar or N), wedge n; the incident E, H (N×3) at q and its
    unit propagation direction(s) k_inc_dir (N×3). uniform: the fringe brackets with the UTD transition, L =
    s s' sin²β' / (s + s') per element (s' = s_src, the distance to the source; None: a plane wave, L = s sin²β')."""
    cos_b = np.clip(k_inc_dir @ t, -1.0, 1.0)
    sin2_b = 1.0 - cos_b ** 2
    to_src = -k_inc_dir
    phi_s = np.mod(np.arctan2(to_src @ y_e, to_src @ x_e), 2 * math.pi)
    r = obs[None, :] - q
    phi = np.mod(np.arctan2(r @ y_e, r @ x_e), 2 * math.pi)
    dist = np.linalg.norm(r, axis=1)
    kl = None
    if uniform:
        ell = dist if s_src is None else dist * s_src / (dist + s_src)
        kl = k * ell * sin2_b
    bs, bh = fringe_brackets(phi, phi_s, n, kl)
    cur_i = -1j * bs * (e_inc @ t) / (k * ETA0 * sin2_b)
    cur_m = -1j * bh * ETA0 * (h_inc @ t) / (k * sin2_b)
    nn = r / dist[:, None]
    g = np.exp(-1j * k * dist) / (4.0 * math.pi * dist)
    # electric element I dl t̂: E exact (dipole), H = (jk + 1/r) g I dl (t̂ × ŝ)
    e_el = _electric_elements_e(cur_i * dl, t, nn, dist, k)
    h_el = ((1j * k + 1.0 / dist) * g * cur_i * dl)[:, None] * np.cross(t[None, :], nn)
    # magnetic element M dl t̂ (duality): E = (jk + 1/r) g M dl (ŝ × t̂), H = E of an electric element M/η²
    e_mag = ((1j * k + 1.0 / dist) * g * cur_m * dl)[:, None] * np.cross(nn, t[None, :])
    h_mag = _electric_elements_e(cur_m * dl / ETA0 ** 2, t, nn, dist, k)
    return np.sum(e_el + e_mag, axis=0), np.sum(h_el + h_mag, axis=0)


def face_edges(case, box=None):
    """The lit face of the case's first box: its 4 edges as (p, q, t, x_e, y_e, n)."""
    box = box or case.boxes[0]
    lo, hi = np.array(box.lo, float), np.array(box.hi, float)
    src = np.array(case.source, float)
    ta = box.thin_axis
    n_wedge = 2.0
    if ta is None:
        ta = next(i for i in range(3) if src[i] > hi[i] or src[i] < lo[i])
        n_wedge = 1.5
    u, v = [i for i in range(3) if i != ta]
    normal = np.zeros(3)
    normal[ta] = 1.0 if src[ta] > hi[ta] else -1.0
    face = hi[ta] if normal[ta] > 0 else lo[ta]
    cs = []
    for cu, cv in ((lo[u], lo[v]), (hi[u], lo[v]), (hi[u], hi[v]), (lo[u], hi[v])):
        c = np.zeros(3)
        c[u], c[v], c[ta] = cu, cv, face
        cs.append(c)
    centre = sum(cs) / 4.0
    edges = []
    for i in range(4):
        p, q = cs[i], cs[(i + 1) % 4]
        t = (q - p) / np.linalg.norm(q - p)
        mid = 0.5 * (p + q)
        x_e = centre - mid
        x_e -= t * (x_e @ t)
        x_e /= np.linalg.norm(x_e)
        y_e = normal
        if np.cross(x_e, y_e) @ t < 0:
            p, q, t = q, p, -t
        edges.append((p, q, t, x_e, y_e, n_wedge))
    return edges


def fringe_ratio(case, tag, dl_m=0.001, box=None, uniform=False):
    """Σ over the lit face's edges of E_fringe(tag)·p̂ / E_src(tag)·p̂."""
    k = K_RAD_M
    a = np.array(axis_vector(case.axis), float)
    src = np.array(case.source, float)
    total = np.zeros(3, complex)
    for p, q, t, x_e, y_e, n in face_edges(case, box):
        length = np.linalg.norm(q - p)
        m = max(2, int(math.ceil(length / dl_m)))
        s = (np.arange(m) + 0.5) / m
        pts = p[None, :] + s[:, None] * (q - p)[None, :]
        e_i, h_i = dipole_fields(a, src, pts, k)
        kd = pts - src
        s_src = np.linalg.norm(kd, axis=1)
        kd /= s_src[:, None]
        total += edge_fringe_field(pts, t, x_e, y_e, length / m, n, e_i, h_i, kd, tag, k, uniform, s_src)[0]
    e_direct, _ = dipole_fields(a, src, tag[None, :], k)
    return (total @ a) / (e_direct[0] @ a)


# ---------------------------------------------------------------------------------------------------------- check
def sommerfeld(rho, phi, phi_s, hard, k=K_RAD_M):
    """Exact total field of a unit plane wave u_i = e^{jkρ cos(φ−φ')} on the PEC half-plane φ = 0 (= 2π):
    u = V(φ−φ') ∓ V(φ+φ'), V(ψ) = e^{jkρ cos ψ} (e^{jπ/4}/√π) ∫_{−∞}^{√(2kρ) cos(ψ/2)} e^{−jτ²} dτ (soft −, hard +)."""
    def v(psi):
        a = SQ(2 * k * rho) * math.cos(psi / 2)
        s, c = special.fresnel(a * SQ(2 / math.pi))      # ∫_0^x e^{−jτ²} dτ = √(π/2)(C − jS)(x√(2/π))
        integ = SQ(math.pi / 2) * (0.5 - 0.5j) + SQ(math.pi / 2) * (c - 1j * s)
        return cmath.exp(1j * k * rho * math.cos(psi)) * cmath.exp(1j * math.pi / 4) / SQ(math.pi) * integ
    return v(phi - phi_s) + (1 if hard else -1) * v(phi + phi_s)


def po_2d(rho, phi, phi_s, hard, k=K_RAD_M, x_max_wl=400.0):
    """Scattered field of the lit face's PO current (face y = 0, x > 0, lit from y > 0), by the 2-D integral
    with a cos² taper over the outer half of [0, x_max] (x_max ≥ 20 λ/(1 − cos φ')): soft E_z = −(kη/4)∫ J_z H₀⁽²⁾(kR) dx', J_z = 2 sinφ' E_z^i/η;
    hard H_z = −(jk/4)∫ J_x H₁⁽²⁾(kR) (y/R) dx', J_x = 2 H_z^i."""
    lam = 2 * math.pi / k
    # the tail's phase turns at k(1 − cos φ') per metre: the taper must span many of its periods (grazing φ')
    x_max = max(x_max_wl, 20.0 / (1.0 - math.cos(phi_s))) * lam
    m = int(x_max / (lam / 40.0))
    dx = x_max / m
    xs = (np.arange(m) + 0.5) * dx
    w = np.ones(m)
    tail = xs > 0.5 * x_max
    w[tail] = np.cos(0.5 * math.pi * (xs[tail] - 0.5 * x_max) / (0.5 * x_max)) ** 2
    ox, oy = rho * math.cos(phi), rho * math.sin(phi)
    ui = np.exp(1j * k * xs * math.cos(phi_s))
    rr = np.hypot(ox - xs, oy)
    if hard:
        return complex(np.sum(-0.25j * k * 2.0 * ui * special.hankel2(1, k * rr) * (oy / rr) * w) * dx)
    return complex(np.sum(-0.25 * k * 2.0 * math.sin(phi_s) * ui * special.hankel2(0, k * rr) * w) * dx)


def fringe_2d(rho, phi, phi_s, hard, k=K_RAD_M, z_max=60.0, uniform=False):
    """The fringe E_z (soft) or H_z (hard) of an edge along z through the 3-D edge-current code, the edge z ∈
    [−z_max, z_max] with a cos² taper on the outer half, under a unit plane wave at normal incidence."""
    m = int(2 * z_max / 0.004)
    zs = -z_max + (np.arange(m) + 0.5) * (2 * z_max / m)
    w = np.ones(m)
    tail = np.abs(zs) > 0.5 * z_max
    w[tail] = np.cos(0.5 * math.pi * (np.abs(zs[tail]) - 0.5 * z_max) / (0.5 * z_max)) ** 2
    q = np.zeros((m, 3))
    q[:, 2] = zs
    t, x_e, y_e = np.array([0.0, 0, 1]), np.array([1.0, 0, 0]), np.array([0.0, 1, 0])
    kdir = np.tile([-math.cos(phi_s), -math.sin(phi_s), 0.0], (m, 1))
    obs = np.array([rho * math.cos(phi), rho * math.sin(phi), 0.0])
    dl = (2 * z_max / m) * w
    unit = np.tile([0, 0, 1.0 + 0j], (m, 1))
    zero = np.zeros((m, 3), complex)
    if hard:   # unit H_z^i at the edge (only H·t̂ enters M; E·t̂ = 0 at normal incidence for this polarisation)
        _, h = edge_fringe_field(q, t, x_e, y_e, dl, 2.0, zero, unit, kdir, obs, k, uniform)
        return complex(h[2])
    e, _ = edge_fringe_field(q, t, x_e, y_e, dl, 2.0, unit, zero, kdir, obs, k, uniform)
    return complex(e[2])


def run_check(log=print):
    """The half-plane check; returns (lines for the md, worst far-zone coefficient error, rows)."""
    k = K_RAD_M
    rows = []
    worst_coef = 0.0
    # far-zone PO coefficient: the numerical PO integral at kρ = 400, its GO part removed, against D^PO's formula
    # (B^PO + B^f = B^Keller holds by construction; what needs checking is that B^PO is PO's own edge term)
    krho = 400.0
    rho = krho / k
    for phi_s_deg in (30.0, 60.0, 120.0):
        for phi_deg in (45.0, 140.0, 200.0, 260.0, 330.0):
            ps, ph = math.radians(phi_s_deg), math.radians(phi_deg)
            for hard in (False, True):
                _, _, po_s, po_h = brackets(np.array([ph]), ps, 2.0)
                d_formula = -cmath.exp(-1j * math.pi / 4) * (po_h if hard else po_s)[0] / (2 * SQ(2 * math.pi * k))
                go = 0.0
                if ph < math.pi - ps:
                    go += (1 if hard else -1) * cmath.exp(1j * krho * math.cos(ph + ps))
                if ph > math.pi + ps:
                    go -= cmath.exp(1j * krho * math.cos(ph - ps))
                d_num = (po_2d(rho, ph, ps, hard, x_max_wl=800.0) - go) * SQ(rho) * cmath.exp(1j * krho)
                worst_coef = max(worst_coef, abs(d_num - d_formula) / abs(d_formula))
    lines = ["| pol. | φ' | φ | kρ | exact \\|u\\| | PO: error | PO + fringe: error | PO + uniform fringe: error | "
             "GO + Keller: error |", "|---|---|---|---|---|---|---|---|---|"]
    pairs = ((60.0, 240.0), (60.0, 120.0), (60.0, 200.0), (60.0, 300.0), (30.0, 150.0), (120.0, 330.0),
             (60.0, 30.0),
             # near grazing: edge-on from outside (φ' → π) with the observer near the shadow boundary π + φ' and
             # past it, near the face's continuation; and grazing over the lit face (φ' → 0), observer beyond
             (176.0, 356.0), (176.0, 359.0), (176.0, 350.0), (170.0, 345.0), (4.0, 184.0), (4.0, 190.0))
    for hard in (False, True):
        for phi_s_deg, phi_deg in pairs:
            for krho in (2.0, 5.0, 20.0, 100.0):
                rho = krho / k
                ps, ph = math.radians(phi_s_deg), math.radians(phi_deg)
                exact = sommerfeld(rho, ph, ps, hard)
                ui = cmath.exp(1j * k * rho * math.cos(ph - ps))
                po = ui + po_2d(rho, ph, ps, hard)
                fr = fringe_2d(rho, ph, ps, hard)
                fru = fringe_2d(rho, ph, ps, hard, uniform=True)
                ex_s, ex_h, _, _ = brackets(np.array([ph]), ps, 2.0)
                b = (ex_h if hard else ex_s)[0]
                go = (ui if abs(ph - ps) < math.pi else 0.0) + \
                    ((1 if hard else -1) * cmath.exp(1j * k * rho * math.cos(ph + ps)) if ph + ps < math.pi else 0.0)
                on_boundary = abs(abs(ph - ps) - math.pi) < 1e-9 or abs(ph + ps - math.pi) < 1e-9
                gtd = go - cmath.exp(-1j * math.pi / 4) * b / (2 * SQ(2 * math.pi * k)) * cmath.exp(-1j * krho) / \
                    SQ(rho) if not on_boundary else None
                rows.append((hard, phi_s_deg, phi_deg, krho, exact, po, po + fr, po + fru, gtd))
                lines.append(f"| {'hard' if hard else 'soft'} | {phi_s_deg:.0f}° | {phi_deg:.0f}° | {krho:g} | "
                             f"{abs(exact):.4f} | {abs(po - exact):.4f} | {abs(po + fr - exact):.4f} | "
                             f"{abs(po + fru - exact):.4f} | " +
                             (f"{abs(gtd - exact):.4f} |" if gtd is not None else "— (on a boundary) |"))
                log(lines[-1])
    return lines, worst_coef, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--out", default="bench/results/fullwave")
    ap.add_argument("--grid", type=int, default=300)
    ap.add_argument("--check-only", action="store_true")
    a = ap.parse_args()
    check_lines, worst_coef, rows = run_check()
    print(f"max relative |D^PO(numerical, kρ = 400) − D^PO(formula)|: {worst_coef:.2e}")
    if a.check_only:
        return
    table = ["| case | observer | kρ | FDTD E/E₀ | `full` (error) | PO (error) | PO + fringe (error) | "
             "PO + uniform fringe (error) |", "|---|---|---|---|---|---|---|---|"]
    summary = []
    for name in CASES:
        case = cases.CASES[name]()
        rows_csv = case_table.rows_by_observer(a.out, name, "ptd_fringe", [o.label for o in case.observers])
        ef, ep, et, eu = [], [], [], []
        for o in case.observers:
            r = rows_csv[o.label]
            f, full = case_table.ratio(r, "fdtd"), case_table.ratio(r, "full")
            tag = np.array(o.position, float)
            po = po_ratio(case, tag, a.grid)
            ptd = po + fringe_ratio(case, tag)
            ptu = po + fringe_ratio(case, tag, uniform=True)
            ef.append(abs(full - f))
            ep.append(abs(po - f))
            et.append(abs(ptd - f))
            eu.append(abs(ptu - f))
            table.append(f"| {name} | {o.label} | {o.krho:.2f} | {abs(f):.3f}∠{cmath.phase(f):+.2f} | "
                         f"{abs(full):.3f} ({ef[-1]:.3f}) | {abs(po):.3f} ({ep[-1]:.3f}) | "
                         f"{abs(ptd):.3f} ({et[-1]:.3f}) | {abs(ptu):.3f} ({eu[-1]:.3f}) |")
        summary.append((name, len(ef), np.median(ef), max(ef), np.median(ep), max(ep), np.median(et), max(et),
                        np.median(eu), max(eu)))
        print(f"{name}: full {summary[-1][2]:.3f}/{summary[-1][3]:.3f}  PO {summary[-1][4]:.3f}/{summary[-1][5]:.3f}  "
              f"PO+fringe {summary[-1][6]:.3f}/{summary[-1][7]:.3f}  PO+uniform {summary[-1][8]:.3f}/{summary[-1][9]:.3f}",
              flush=True)
    # the md: the generated part, then whatever follows the marker in an existing file (the discussion) is kept
    marker = "<!-- end of the generated part: text below is kept when the script rewrites the file -->"
    md = os.path.join(a.out, "ptd_fringe.md")
    kept = ""
    if os.path.isfile(md):
        old = open(md).read()
        if marker in old:
            kept = old.split(marker, 1)[1]
    compact = ["| pol. | φ' | φ | PO alone, kρ = 2 / 5 / 20 / 100 | PO + fringe | PO + uniform fringe |",
               "|---|---|---|---|---|---|"]
    keys = []
    for r in rows:
        if (r[0], r[1], r[2]) not in keys:
            keys.append((r[0], r[1], r[2]))
    for key in keys:
        rs = [r for r in rows if (r[0], r[1], r[2]) == key]
        fmt = lambda i: " / ".join(f"{abs(r[i] - r[4]):.4f}" for r in rs)  # noqa: E731
        compact.append(f"| {'hard' if key[0] else 'soft'} | {key[1]:.0f}° | {key[2]:.0f}° | {fmt(5)} | {fmt(6)} | "
                       f"{fmt(7)} |")
    text = ["# PTD: physical optics + closed-form edge fringe against FDTD (prototype reference)", "",
            "`cd bench/fullwave && /usr/bin/python3 ptd_fringe.py -o ../results/fullwave` (≈ 45 s; the script's "
            "header gives every formula and its source). Errors are |h/h₀ − E/E₀| (a fraction of the free-space "
            "field).", "",
            "## Check: a PEC half-plane under a unit plane wave (2-D, normal incidence)", "",
            "Total field error against Sommerfeld's exact solution (Fresnel integrals): `PO alone` = incident + the "
            "lit face's PO field (numerical 2-D integral); `PO + fringe` adds the fringe radiated by this script's "
            "equivalent edge currents integrated along a 120 m edge (the same code the plates use); `uniform` "
            "multiplies each fringe term by the UTD transition F(2kL cos²x). Observers on the shadow or reflection "
            "boundary are where GO + Keller is infinite.", ""] + compact + [
            "", f"PO's closed-form edge coefficient against the numerical PO integral at kρ = 400 (its GO part "
            f"removed), φ' ∈ {{30°, 60°, 120°}}, φ ∈ {{45°, 140°, 200°, 260°, 330°}}: largest relative difference "
            f"{worst_coef:.3f} (at 10° from a boundary; 0.02–0.04 at 15–20°, ≤ 0.013 at 30° or more: the "
            f"non-uniform coefficient's own error near a boundary at this kρ).", "",
            "## Plates against FDTD", ""] + table + ["", "| case | observers | `full` | PO | PO + fringe | "
                                                      "PO + uniform fringe |", "|---|---|---|---|---|---|"]
    for s_ in summary:
        text.append(f"| {s_[0]} | {s_[1]} | {s_[2]:.3f} / {s_[3]:.3f} | {s_[4]:.3f} / {s_[5]:.3f} | "
                    f"{s_[6]:.3f} / {s_[7]:.3f} | {s_[8]:.3f} / {s_[9]:.3f} |")
    text.append("")
    with open(md, "w") as fh:
        fh.write("\n".join(text) + "\n" + marker + (kept if kept else "\n"))

if __name__ == "__main__":
    main()
