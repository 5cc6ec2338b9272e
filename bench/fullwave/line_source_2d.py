#!/usr/bin/python3
"""Is the source's curvature what `full` misses across a sheet's edge? A 2-D check of the edge's near field.

rfidray's edge near field (core/edge_near_field.h) is the exact minus the GO + UTD field of the canonical problem, a
plane wave on an infinite half-plane, scaled by the incident field at the edge; the rest of the field is GO + UTD of
the real source. Here the real source is a line source 1 m from the edge at φ' = 60° (the sheet case's, in 2-D), whose
exact field beside the half-plane is known (Harrington, Time-Harmonic Electromagnetic Fields §5.10; halfplane2d.py):
the hard case (H_z, E in the plane), E = (1/jk)(∂H_z/∂y, −∂H_z/∂x) in units of η. Printed per observer (ρ, φ of the
3-D case): |model − exact| / |E_free| for the model above, and for GO + UTD alone.

  /usr/bin/python3 bench/fullwave/line_source_2d.py

e^{+jωt}; UTD is Kouyoumjian–Pathak's (core/utd.h) with L = ρρ'/(ρ + ρ') for the line source, L = ρ for the plane wave.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import special as sp

from cases import SHEET_ANGLES_DEG, SHEET_RHOS_M, SOURCE_PHI_DEG, SOURCE_RANGE_M
from geometry import K_RAD_M
from ptd_fringe import kp_transition

K = K_RAD_M
PHI_S = math.radians(SOURCE_PHI_DEG)
RHO_S = SOURCE_RANGE_M
N_TERMS = 120  # J_{n/2}(kρ) is below 1e-30 long before n = 120 at kρ ≤ 6


def _e_from_h(h_rho_deriv, h_phi_deriv, rho, phi):
    """E (units η, Cartesian) from ∂H/∂ρ and ∂H/∂φ: E_ρ = (1/jkρ)∂H/∂φ, E_φ = −(1/jk)∂H/∂ρ."""
    e_rho = h_phi_deriv / (1j * K * rho)
    e_phi = -h_rho_deriv / (1j * K)
    return np.array([e_rho * math.cos(phi) - e_phi * math.sin(phi), e_rho * math.sin(phi) + e_phi * math.cos(phi)])


def line_source_exact(rho, phi):
    """Hard half-plane φ = 0, line source (−j/4)H₀⁽²⁾ at (ρ', φ'), observer inside ρ < ρ'."""
    n = np.arange(N_TERMS)
    nu = n / 2.0
    a = np.where(n == 0, 0.5, 1.0) * np.cos(nu * PHI_S) * sp.hankel2(nu, K * RHO_S)
    c = -0.5j
    d_rho = c * K * np.sum(a * np.cos(nu * phi) * sp.jvp(nu, K * rho))
    d_phi = c * np.sum(a * (-nu) * np.sin(nu * phi) * sp.jv(nu, K * rho))
    return _e_from_h(d_rho, d_phi, rho, phi)


def plane_wave_exact(rho, phi):
    """The canonical problem: unit H_z plane wave from φ' (Bowman et al. ch. 6; core/wedge_series.h, n = 2)."""
    n = np.arange(N_TERMS)
    nu = n / 2.0
    a = np.where(n == 0, 1.0, 2.0) * (1j ** nu) * np.cos(nu * PHI_S)
    d_rho = K * np.sum(a * np.cos(nu * phi) * sp.jvp(nu, K * rho))
    d_phi = np.sum(a * (-nu) * np.sin(nu * phi) * sp.jv(nu, K * rho))
    return _e_from_h(d_rho, d_phi, rho, phi)


def line_source_free(src, obs):
    """E of the line source alone (units η)."""
    d = np.asarray(obs) - np.asarray(src)
    r = math.hypot(*d)
    dh_dr = -0.25j * K * sp.h2vp(0, K * r)
    g = dh_dr * d / r
    return np.array([g[1], -g[0]]) / (1j * K), -0.25j * sp.hankel2(0, K * r)


def plane_wave_ray(from_phi, rho, phi):
    """A unit H_z plane wave arriving from direction from_phi: E = H ẑ × d̂."""
    d = -np.array([math.cos(from_phi), math.sin(from_phi)])
    h = np.exp(-1j * K * (d @ np.array([rho * math.cos(phi), rho * math.sin(phi)])))
    return h * np.array([-d[1], d[0]])


def d_hard(phi, big_l, n=2.0):
    total = 0.0
    for beta in (phi - PHI_S, phi + PHI_S):
        for sign in (1, -1):
            big_n = round((beta + sign * math.pi) / (2.0 * math.pi * n))
            a = 2.0 * math.cos((2.0 * math.pi * n * big_n - beta) / 2.0) ** 2
            total += kp_transition(K * big_l * a) / math.tan((math.pi + sign * beta) / (2.0 * n))
    return -np.exp(-1j * math.pi / 4.0) / (2.0 * n * math.sqrt(2.0 * math.pi * K)) * total


def utd(h_edge, rho, phi, big_l):
    h = h_edge * d_hard(phi, big_l) * np.exp(-1j * K * rho) / math.sqrt(rho)
    return h * np.array([-math.sin(phi), math.cos(phi)])


def main():
    src = (RHO_S * math.cos(PHI_S), RHO_S * math.sin(PHI_S))
    img = (RHO_S * math.cos(PHI_S), -RHO_S * math.sin(PHI_S))
    _, h_edge = line_source_free(src, (0.0, 0.0))
    print("rho_m,phi_deg,near_field_model_error,go_utd_error,near_field_term")
    worst = {}
    for rho in SHEET_RHOS_M:
        for deg in SHEET_ANGLES_DEG:
            # On a shadow or reflection boundary UTD's cotangent is singular; 0.01° off it the field is continuous.
            phi = math.radians(deg + (0.01 if deg in (120.0, 240.0) else 0.0))
            obs = (rho * math.cos(phi), rho * math.sin(phi))
            exact = line_source_exact(rho, phi)
            e_free, _ = line_source_free(src, obs)
            lit, reflected = phi <= math.pi + PHI_S, phi < math.pi - PHI_S
            go = (e_free if lit else 0) + (line_source_free(img, obs)[0] if reflected else 0)
            go_pw = (plane_wave_ray(PHI_S, rho, phi) if lit else 0) + (plane_wave_ray(-PHI_S, rho, phi) if reflected else 0)
            ray = go + utd(h_edge, rho, phi, rho * RHO_S / (rho + RHO_S))
            near = h_edge * (plane_wave_exact(rho, phi) - go_pw - utd(1.0, rho, phi, rho))
            scale = np.linalg.norm(e_free)
            model_error = np.linalg.norm(ray + near - exact) / scale
            worst[rho] = max(worst.get(rho, 0.0), model_error)
            print(f"{rho:g},{deg:g},{model_error:.4f},{np.linalg.norm(ray - exact) / scale:.4f},"
                  f"{np.linalg.norm(near) / scale:.4f}")
    print("# worst near-field model error per rho: " + ", ".join(f"{r:g} m {w:.3f}" for r, w in worst.items()))


if __name__ == "__main__":
    main()
