"""The full-wave cases (issue #33). Each function returns a geometry.Case; CASES maps names to them."""
from __future__ import annotations

import math

from geometry import Box, Case, Observer

# Case (a): a finite perfectly conducting sheet 0.9 × 0.8 m in the plane y = 0, x ∈ [0, 0.9], z ∈ [−0.4, 0.4];
# its edge along z through the origin. The source is 1 m from the edge at φ' = 60° from the sheet (angles measured
# round the edge from the sheet's lit face, x > 0): reflection boundary φ = 180° − 60° = 120°, shadow boundary
# φ = 180° + 60° = 240°. Observers at ρ = 4, 8, 16, 32 cm from the edge, in the plane z = 0.
SHEET_RHOS_M = (0.04, 0.08, 0.16, 0.32)
SHEET_ANGLES_DEG = (20.0, 60.0, 100.0, 120.0, 140.0, 180.0, 220.0, 240.0, 260.0, 300.0, 340.0)
SOURCE_PHI_DEG = 60.0
SOURCE_RANGE_M = 1.0


def sheet_region(phi_deg: float) -> str:
    rb, sb = 180.0 - SOURCE_PHI_DEG, 180.0 + SOURCE_PHI_DEG
    if abs(phi_deg - rb) < 1e-9:
        return "reflection boundary"
    if abs(phi_deg - sb) < 1e-9:
        return "shadow boundary"
    if phi_deg < rb:
        return "lit + reflected"
    if phi_deg < sb:
        return "lit"
    return "shadow"


def sheet_edge(axis: str, rhos=SHEET_RHOS_M, angles=SHEET_ANGLES_DEG) -> Case:
    phi_s = math.radians(SOURCE_PHI_DEG)
    source = (SOURCE_RANGE_M * math.cos(phi_s), SOURCE_RANGE_M * math.sin(phi_s), 0.0)
    obs = []
    for rho in rhos:
        for a in angles:
            p = (rho * math.cos(math.radians(a)), rho * math.sin(math.radians(a)), 0.0)
            obs.append(Observer(f"rho{rho * 100:.0f}cm_phi{a:.0f}", p, rho, a, sheet_region(a)))
    pol = {"z": "soft (E ∥ edge: z dipole, E_z)", "x": "hard (E ⊥ edge: x dipole, E_x)"}[axis]
    return Case(
        name=f"sheet_edge_{'soft' if axis == 'z' else 'hard'}",
        description=f"finite PEC sheet 0.9 × 0.8 m (y = 0, x ∈ [0, 0.9], z ∈ [−0.4, 0.4]), edge along z; "
                    f"dipole 1 m from the edge at 60° from the sheet; {pol}",
        boxes=(Box((0.0, 0.0, -0.4), (0.9, 0.0, 0.4), "metal"),),
        source=source,
        axis=axis,
        observers=tuple(obs),
        domain_lo=(-0.40, -0.40, -0.50),
        domain_hi=(1.00, 0.98, 0.50),
        polarization_name="soft" if axis == "z" else "hard",
    )


CASES = {
    "sheet_edge_soft": lambda: sheet_edge("z"),
    "sheet_edge_hard": lambda: sheet_edge("x"),
}
