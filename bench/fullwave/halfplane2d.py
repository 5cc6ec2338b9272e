"""The 2-D check of the FDTD near an edge: a line source beside a perfectly conducting half-plane, meep (TM: E_z,
soft; TE: H_z, hard) against the exact eigenfunction series, on the sheet case's observers (same ρ, φ, source
1 m away at φ' = 60°).

Exact (e^{+jωt}; Harrington, Time-Harmonic Electromagnetic Fields §5.10, a wedge of exterior angle 2π):
  the radial Green's function of order ν is (−jπ/2)·J_ν(kρ<)·H⁽²⁾_ν(kρ>) and the angular eigenfunctions of the
  half-plane are sin(νφ) (soft) or cos(νφ) (hard), ν = n/2, normalised over 2π:
  soft  G = (−j/2)·Σ_{n≥1} sin(nφ/2) sin(nφ'/2) J_{n/2}(kρ<) H⁽²⁾_{n/2}(kρ>)
  hard  G = (−j/2)·[½ J₀ H⁽²⁾₀ + Σ_{n≥1} cos(nφ/2) cos(nφ'/2) J_{n/2}(kρ<) H⁽²⁾_{n/2}(kρ>)]
  free  G₀ = (−j/4)·H⁽²⁾₀(k|r − r'|)
This measures the FDTD grid's own error near a zero-thickness edge (what a resolution costs at each kρ) where
2-D is cheap enough to reach 480 px/m; the 3-D runs of the same sheet cannot.
"""
from __future__ import annotations

import math
import time

import numpy as np
from scipy import special

from geometry import C0_M_S, FREQUENCY_HZ, K_RAD_M


def exact_ratio(rho, phi_rad, rho_s, phi_s_rad, hard: bool, n_terms: int = 200) -> complex:
    """E/E_free (e^{+jωt}) at (ρ, φ) for a line source at (ρ', φ') beside the half-plane φ = 0 (= 2π)."""
    k = K_RAD_M
    r_lt, r_gt = min(rho, rho_s), max(rho, rho_s)
    n = np.arange(1, n_terms + 1)
    nu = n / 2.0
    radial = special.jv(nu, k * r_lt) * special.hankel2(nu, k * r_gt)
    ang = (np.cos(nu * phi_rad) * np.cos(nu * phi_s_rad)) if hard else (np.sin(nu * phi_rad) * np.sin(nu * phi_s_rad))
    s = np.sum(ang * radial)
    if hard:
        s += 0.5 * special.jv(0, k * r_lt) * special.hankel2(0, k * r_gt)
    g = -0.5j * s
    dist = math.hypot(rho * math.cos(phi_rad) - rho_s * math.cos(phi_s_rad),
                      rho * math.sin(phi_rad) - rho_s * math.sin(phi_s_rad))
    g0 = -0.25j * special.hankel2(0, k * dist)
    return complex(g / g0)


def fdtd_ratio(observers_xy, source_xy, hard: bool, resolution: float, dpml_m: float = 0.3,
               settle_periods: float = 14.0, log=print):
    """E_z (soft) or H_z (hard) over its free-space value at the observers, meep's e^{-iωt} convention."""
    import meep as mp
    mp.verbosity(0)
    d = 1.0 / resolution
    f = FREQUENCY_HZ / C0_M_S
    period = 1.0 / f
    lo = np.array([-0.40, -0.40])
    hi = np.array([1.00, 0.98])
    lo = np.floor(lo / d) * d - math.ceil(dpml_m / d) * d
    hi = np.ceil(hi / d) * d + math.ceil(dpml_m / d) * d
    for i in range(2):  # an even number of cells: the grid's centre, and so y = 0, on a grid point (fdtd.py)
        if round((hi[i] - lo[i]) / d) % 2:
            hi[i] += d
    size = hi - lo
    center = mp.Vector3(*((hi + lo) / 2))
    comp = mp.Hz if hard else mp.Ez
    out = {}
    for with_sheet in (False, True):
        # The half-plane y = 0, x ≥ 0 (into the PML): one grid row of tangential E forced to zero.
        geo = [mp.Block(center=mp.Vector3((hi[0] - 0.25 * d) / 2, 0), size=mp.Vector3(hi[0] + 0.25 * d, 0.5 * d, mp.inf),
                        material=mp.metal)] if with_sheet else []
        sim = mp.Simulation(cell_size=mp.Vector3(size[0], size[1], 0), geometry_center=center, resolution=resolution,
                            geometry=geo, boundary_layers=[mp.PML(math.ceil(dpml_m / d) * d)], eps_averaging=False,
                            sources=[mp.Source(mp.ContinuousSource(frequency=f, width=period), component=comp,
                                               center=mp.Vector3(*source_xy))])
        pts = [mp.Vector3(*p) for p in observers_xy]
        times, samples = [], []
        t_sample = settle_periods * period - 1e-9

        def sample(s):
            if s.meep_time() >= t_sample:
                times.append(s.meep_time())
                samples.append([s.get_field_point(comp, p) for p in pts])

        t0 = time.time()
        sim.run(sample, until=(settle_periods + 1.0) * period)
        times = np.asarray(times)
        m = np.stack([np.cos(2 * math.pi * f * times), np.sin(2 * math.pi * f * times)], axis=1)
        coef, *_ = np.linalg.lstsq(m, np.real(np.asarray(samples)), rcond=None)
        out[with_sheet] = coef[0] + 1j * coef[1]
        log(f"  2-D {'hard' if hard else 'soft'} res {resolution:g} sheet {with_sheet}: {time.time() - t0:.1f} s")
    return out[True] / out[False]
