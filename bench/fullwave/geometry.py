"""One description of a full-wave case: the metal (and dielectric) boxes, the source dipole, the observers.

The same description builds the FDTD geometry (bench/fullwave/fdtd.py) and the rfidray OBJ scene
(bench/fullwave/rfidray_link.py), so the two sides cannot drift apart. Units: metres, hertz.

A Box with one zero size is a zero-thickness sheet (rfidray: one quad; FDTD: one grid plane of tangential E
forced to zero). Materials: "metal" (perfect conductor on both sides) or a dielectric (eps_r, sigma_s_m) that
rfidray knows by name (core/material.cpp).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

C0_M_S = 299792458.0
FREQUENCY_HZ = 866e6
WAVELENGTH_M = C0_M_S / FREQUENCY_HZ
K_RAD_M = 2.0 * math.pi / WAVELENGTH_M


@dataclass(frozen=True)
class Box:
    """An axis-aligned box (lo, hi corners); one zero extent = a zero-thickness sheet."""
    lo: tuple[float, float, float]
    hi: tuple[float, float, float]
    material: str = "metal"          # rfidray radio material name
    eps_r: float = 1.0               # dielectric only (FDTD side); rfidray uses its own table for the name
    sigma_s_m: float = 0.0
    # A sheet with slab_m > 0 is a wall: FDTD builds a solid block slab_m thick behind the sheet's plane (towards
    # +thin axis); rfidray gets the one quad in that plane (the front face: P.2040's slab reflection is referred
    # to it, and the slab transmission is relative to free space over the same line) and `--thickness slab_m`.
    slab_m: float = 0.0

    @property
    def thin_axis(self) -> int | None:
        zero = [i for i in range(3) if self.hi[i] - self.lo[i] == 0.0]
        if len(zero) > 1:
            raise ValueError(f"box {self}: more than one zero extent")
        return zero[0] if zero else None


@dataclass(frozen=True)
class Observer:
    """A tag position and what it is: distance to the nearest edge (rho_m), angle round it, region label."""
    label: str
    position: tuple[float, float, float]
    rho_m: float = float("nan")
    phi_deg: float = float("nan")
    region: str = ""
    extra: dict = field(default_factory=dict)

    @property
    def krho(self) -> float:
        return K_RAD_M * self.rho_m


@dataclass(frozen=True)
class Case:
    name: str
    description: str
    boxes: tuple[Box, ...]
    source: tuple[float, float, float]
    # The dipole axis of the source and the field component the tag reads (one of "x", "y", "z").
    axis: str
    observers: tuple[Observer, ...]
    # FDTD domain (without PML): lo/hi corners. Everything (boxes, source, observers) must be inside.
    domain_lo: tuple[float, float, float]
    domain_hi: tuple[float, float, float]
    polarization_name: str = ""
    # meep mirror symmetries [(axis, phase)] the geometry, source and observers' fields share (a z dipole on the
    # mirror planes x = 0 and z = 0: ("x", +1), ("z", -1)); each halves the FDTD's work and changes nothing else.
    symmetries: tuple = ()
    # Subpixel averaging (meep's eps_averaging): on for dielectric blocks (second-order convergence at their
    # faces); off whenever the case has zero-thickness sheets, which need it off (fdtd.py).
    eps_averaging: bool = False
    # Order of the FDTD's convergence with resolution, for the Richardson extrapolation (run.py): 1 near a
    # zero-thickness sheet's edge (richardson_2d.py), 2 for averaged dielectric blocks and the Yee scheme's dispersion.
    convergence_order: int = 1

    def check(self) -> None:
        pts = [self.source] + [o.position for o in self.observers]
        for b in self.boxes:
            pts += [b.lo, b.hi]
        for p in pts:
            for i in range(3):
                if not (self.domain_lo[i] <= p[i] <= self.domain_hi[i]):
                    raise ValueError(f"case {self.name}: point {p} outside the FDTD domain "
                                     f"{self.domain_lo}..{self.domain_hi}")
        if self.axis not in ("x", "y", "z"):
            raise ValueError(f"case {self.name}: axis must be x, y or z (got {self.axis!r})")


def nearest_edge_m(p, boxes) -> float:
    """Distance (m) from p to the nearest edge (segment) of any of the boxes (a sheet's 4 edges, a box's 12)."""
    best = float("inf")
    for b in boxes:
        hi_eff = list(b.hi)
        if b.slab_m > 0.0:
            hi_eff[b.thin_axis] = b.lo[b.thin_axis] + b.slab_m
        corners = [(x, y, z) for x in (b.lo[0], hi_eff[0]) for y in (b.lo[1], hi_eff[1]) for z in (b.lo[2], hi_eff[2])]
        for i, a in enumerate(corners):
            for c in corners[i + 1:]:
                diff = [c[k] - a[k] for k in range(3)]
                if sum(1 for v in diff if v != 0.0) != 1:
                    continue
                L2 = sum(v * v for v in diff)
                t = max(0.0, min(1.0, sum((p[k] - a[k]) * diff[k] for k in range(3)) / L2))
                q = [a[k] + t * diff[k] for k in range(3)]
                best = min(best, math.dist(p, q))
    return best


def axis_vector(axis: str) -> tuple[float, float, float]:
    return {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}[axis]
