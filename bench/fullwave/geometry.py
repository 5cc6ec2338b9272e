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


def axis_vector(axis: str) -> tuple[float, float, float]:
    return {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}[axis]
