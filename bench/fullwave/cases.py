"""The full-wave cases (issue #33). Each function returns a geometry.Case; CASES maps names to them."""
from __future__ import annotations

import math

from geometry import FREQUENCY_HZ, K_RAD_M, Box, Case, Observer, nearest_edge_m

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


EDGE_POLARIZATION = {"z": "soft (E ∥ edge: z dipole, E_z)", "x": "hard (E ⊥ edge: x dipole, E_x)"}


def _edge_source_and_observers(rhos, angles):
    """The source 1 m from the edge (the z axis) at φ' = 60°, and observers at (ρ, φ) round it in the plane z = 0."""
    phi_s = math.radians(SOURCE_PHI_DEG)
    source = (SOURCE_RANGE_M * math.cos(phi_s), SOURCE_RANGE_M * math.sin(phi_s), 0.0)
    obs = []
    for rho in rhos:
        for a in angles:
            p = (rho * math.cos(math.radians(a)), rho * math.sin(math.radians(a)), 0.0)
            obs.append(Observer(f"rho{rho * 100:.0f}cm_phi{a:.0f}", p, rho, a, sheet_region(a)))
    return source, tuple(obs)


def sheet_edge(axis: str, rhos=SHEET_RHOS_M, angles=SHEET_ANGLES_DEG, half_height_m: float = 0.4) -> Case:
    """The sheet case; half_height_m > 0.4 makes the sheet taller (the same edge, source and observers, its corners
    farther): what the sheet's other edges and corners add near the edge, which the canonical half-plane has not."""
    source, obs = _edge_source_and_observers(rhos, angles)
    pol = EDGE_POLARIZATION[axis]
    h = half_height_m
    tall = "" if h == 0.4 else "_tall"
    # The domain ends 0.1 m beyond the sheet's top and bottom edges: 0.4 m more (z ∈ ±0.8) moves the field by
    # ≤ 0.003 of the free-space field at every observer (hard, 30 and 60 px/m, 2026-12-07).
    return Case(
        name=f"sheet_edge_{'soft' if axis == 'z' else 'hard'}{tall}",
        description=f"finite PEC sheet 0.9 × {2 * h:g} m (y = 0, x ∈ [0, 0.9], z ∈ [−{h:g}, {h:g}]), edge along z; "
                    f"dipole 1 m from the edge at 60° from the sheet; {pol}",
        boxes=(Box((0.0, 0.0, -h), (0.9, 0.0, h), "metal"),),
        source=source,
        axis=axis,
        observers=obs,
        domain_lo=(-0.40, -0.40, -h - 0.10),
        domain_hi=(1.00, 0.98, h + 0.10),
        polarization_name="soft" if axis == "z" else "hard",
    )


# Case (a′): the same edge, source and observers on a right-angled metal wedge: a box 0.9 × 0.5 × 0.8 m
# (x ∈ [0, 0.9], y ∈ [−0.5, 0], z ∈ [−0.4, 0.4]) whose top face is the sheet's plane and whose front face x = 0 closes
# the wedge (exterior angle 270°: a rack upright's or a crate's corner). Angles round the edge from the top face
# (φ = 0, along +x) to the front face (φ = 270°): the observers of the sheet case up to 260°. Boundaries as the
# sheet's (the source does not see the front face): reflection 120°, shadow 240°.
WEDGE_ANGLES_DEG = tuple(a for a in SHEET_ANGLES_DEG if a < 270.0)


def wedge_edge(axis: str) -> Case:
    source, obs = _edge_source_and_observers(SHEET_RHOS_M, WEDGE_ANGLES_DEG)
    pol = EDGE_POLARIZATION[axis]
    return Case(
        name=f"wedge_edge_{'soft' if axis == 'z' else 'hard'}",
        description="PEC box 0.9 × 0.5 × 0.8 m (x ∈ [0, 0.9], y ∈ [−0.5, 0], z ∈ [−0.4, 0.4]), its right-angled edge "
                    f"along z; dipole 1 m from the edge at 60° from the top face; {pol}",
        boxes=(Box((0.0, -0.5, -0.4), (0.9, 0.0, 0.4), "metal"),),
        source=source,
        axis=axis,
        observers=obs,
        domain_lo=(-0.40, -0.60, -0.50),
        domain_hi=(1.00, 0.98, 0.50),
        polarization_name="soft" if axis == "z" else "hard",
    )


# Case (e): a concrete wall. ITU-R P.2040 Table 3 (core/material.cpp's builtin "concrete"): ε' = a·f^b,
# σ = c·f^d, f in GHz, a = 5.24, b = 0, c = 0.0462, d = 0.7822; the fit is given from 1 GHz and extrapolated
# to 866 MHz here, as rfidray does: ε' = 5.24, σ = 0.0413 S/m. The same ε', σ go to meep (fdtd.py: σ_D).
CONCRETE_EPS_R = 5.24 * (FREQUENCY_HZ / 1e9) ** 0.0
CONCRETE_SIGMA_S_M = 0.0462 * (FREQUENCY_HZ / 1e9) ** 0.7822
WALL_THICKNESS_M = 0.2
WALL_HALF_M = 0.6            # the slab is 1.2 × 1.2 m (x, z ∈ [−0.6, 0.6]), y ∈ [0, 0.2]
WALL_SOURCE_M = (0.0, -0.8, 0.0)


def _labelled(specs, boxes):
    """Observers from (label, position, region); rho = the distance to the nearest edge of the boxes."""
    out = []
    for label, p, region in specs:
        rho = nearest_edge_m(p, boxes)
        phi = math.degrees(math.atan2(p[1], p[0]))
        out.append(Observer(label, p, rho, phi, region))
    return tuple(out)


def concrete_wall() -> Case:
    wall = Box((-WALL_HALF_M, 0.0, -WALL_HALF_M), (WALL_HALF_M, 0.0, WALL_HALF_M), "concrete",
               eps_r=CONCRETE_EPS_R, sigma_s_m=CONCRETE_SIGMA_S_M, slab_m=WALL_THICKNESS_M)
    t = WALL_THICKNESS_M
    e = WALL_HALF_M
    specs = [
        # behind the wall, 10 and 25 cm from its back face, on the axis and off it
        ("behind_x0_10cm", (0.0, t + 0.10, 0.0), "behind (transmission)"),
        ("behind_x0_25cm", (0.0, t + 0.25, 0.0), "behind (transmission)"),
        ("behind_x0.2_10cm", (0.2, t + 0.10, 0.0), "behind (transmission)"),
        ("behind_x0.3_25cm", (0.3, t + 0.25, 0.0), "behind (transmission)"),
        ("behind_x0.2_z0.3_10cm", (0.2, t + 0.10, 0.3), "behind (transmission)"),
        ("behind_x0.4_25cm", (0.4, t + 0.25, 0.0), "behind (transmission)"),
        # in front: the reflection off the wall
        ("front_x0_30cm", (0.0, -0.30, 0.0), "front (reflection)"),
        ("front_x0_50cm", (0.0, -0.50, 0.0), "front (reflection)"),
        ("front_x0.3_20cm", (0.3, -0.20, 0.0), "front (reflection)"),
        ("front_x0.3_40cm", (0.3, -0.40, 0.0), "front (reflection)"),
        ("front_x0.2_z0.3_30cm", (0.2, -0.30, 0.3), "front (reflection)"),
        # beside its edge (x = 0.6): in front of the edge, level with the slab, behind it
        ("edge_front", (e + 0.10, -0.10, 0.0), "beside the edge"),
        ("edge_mid", (e + 0.10, t / 2, 0.0), "beside the edge"),
        ("edge_behind10", (e + 0.10, t + 0.10, 0.0), "beside the edge"),
        ("edge_behind_in", (e - 0.10, t + 0.15, 0.0), "beside the edge"),
        ("edge_mid20", (e + 0.20, t / 2, 0.0), "beside the edge"),
        ("edge_behind25", (e + 0.05, t + 0.25, 0.0), "beside the edge"),
    ]
    return Case(
        name="concrete_wall",
        description=f"concrete slab 1.2 × 1.2 × {t:g} m (x, z ∈ [−0.6, 0.6], y ∈ [0, {t:g}]; ε' = {CONCRETE_EPS_R:.2f}, "
                    f"σ = {CONCRETE_SIGMA_S_M:.4f} S/m, ITU-R P.2040 extrapolated to 866 MHz); z dipole at "
                    f"(0, −0.8, 0); rfidray: one quad at the front face y = 0 with --thickness {t:g}",
        boxes=(wall,),
        source=WALL_SOURCE_M,
        axis="z",
        observers=_labelled(specs, (wall,)),
        domain_lo=(-0.85, -0.90, -0.70),
        domain_hi=(0.85, 0.55, 0.70),
        polarization_name="vertical (z)",
        symmetries=(("x", 1), ("z", -1)),
        eps_averaging=True,
        convergence_order=2,
    )


# Case (b): a tag in front of a metal plate 0.6 × 0.6 m (PEC sheet in y = 0, x, z ∈ [−0.3, 0.3]); z dipole 1 m in
# front of its centre; tags at d = λ/8, λ/4, λ/2 in front of it, at the centre and 3 cm inside the edge x = 0.3
# (an edge along E: soft) and 3 cm inside the edge z = 0.3 (an edge across E: hard). d = λ/100 (3.5 mm) is a fifth
# of a cell at 60 px/m: a uniform grid cannot place it (nor resolve the field between the tag and the plate).
PLATE_HALF_M = 0.3
PLATE_DISTANCES = (("lambda/8", 1 / 8), ("lambda/4", 1 / 4), ("lambda/2", 1 / 2))


def _plate_case(name: str, description: str, distances, off_wall_m: float = 0.0, symmetries=()) -> Case:
    """Case (b)'s plate and source, tags at `distances` (label, fraction of λ) in front of it at the centre and 3 cm
    inside the edges x = 0.3 (∥ E) and z = 0.3 (⊥ E), `off_wall_m` off the planes x = 0 and z = 0."""
    from geometry import WAVELENGTH_M
    plate = Box((-PLATE_HALF_M, 0.0, -PLATE_HALF_M), (PLATE_HALF_M, 0.0, PLATE_HALF_M), "metal")
    w = off_wall_m
    specs = []
    for label, frac in distances:
        d = frac * WAVELENGTH_M
        tag = label.replace("lambda/", "L")
        specs += [(f"centre_{tag}", (w, -d, w), "centre"),
                  (f"edge_soft_{tag}", (PLATE_HALF_M - 0.03, -d, w), "3 cm inside the edge ∥ E (soft)"),
                  (f"edge_hard_{tag}", (w, -d, PLATE_HALF_M - 0.03), "3 cm inside the edge ⊥ E (hard)")]
    return Case(
        name=name,
        description=description,
        boxes=(plate,),
        source=(0.0, -1.0, 0.0),
        axis="z",
        observers=_labelled(specs, (plate,)),
        domain_lo=(-0.45, -1.10, -0.45),
        domain_hi=(0.45, 0.15, 0.45),
        polarization_name="vertical (z)",
        symmetries=symmetries,
    )


def plate_front() -> Case:
    return _plate_case("plate_front",
                       "tag in front of a PEC plate 0.6 × 0.6 m (y = 0, x, z ∈ [−0.3, 0.3]); z dipole at (0, −1, 0); "
                       "tags at d = λ/8, λ/4, λ/2 (4.3, 8.7, 17.3 cm) at the centre and 3 cm inside the edges x = 0.3 "
                       "(∥ E) and z = 0.3 (⊥ E)",
                       PLATE_DISTANCES, symmetries=(("x", 1), ("z", -1)))


# Case (b′): the same plate with tags close to it, for the graded-mesh FDTD of fdtd_openems.py (meep's uniform grid
# cannot place d = λ/100): d = λ/100 (3.5 mm) and, to check that FDTD against meep's converged case (b), λ/8. Each
# observer is 4 mm off the planes x = 0 and z = 0 (z = 0 is the FDTD's electric wall: a probe there reads the
# wall's boundary node).
PLATE_NEAR_DISTANCES = (("lambda/100", 1 / 100), ("lambda/8", 1 / 8))
PLATE_NEAR_OFF_WALL_M = 0.004


def plate_front_near() -> Case:
    return _plate_case("plate_front_near",
                       "tag close to a PEC plate 0.6 × 0.6 m (y = 0, x, z ∈ [−0.3, 0.3]); z dipole at (0, −1, 0); "
                       "tags at d = λ/100 and λ/8 (3.5 mm, 4.3 cm) at the centre and 3 cm inside the edges x = 0.3 "
                       "(∥ E) and z = 0.3 (⊥ E), 4 mm off the planes x = 0 and z = 0; graded-mesh FDTD (openEMS)",
                       PLATE_NEAR_DISTANCES, off_wall_m=PLATE_NEAR_OFF_WALL_M)


# Case (c): the front edge of a rack bay: two horizontal PEC shelf plates 0.9 × 0.5 m (x ∈ [−0.45, 0.45],
# y ∈ [0, 0.5]) at z = ±0.2 (0.4 m apart), their front edges along x at y = 0; z dipole 1 m in front. Tags between
# the plates near the front edge and just outside it.
def rack_bay() -> Case:
    top = Box((-0.45, 0.0, 0.2), (0.45, 0.5, 0.2), "metal")
    bottom = Box((-0.45, 0.0, -0.2), (0.45, 0.5, -0.2), "metal")
    specs = [
        ("in_y5_z0", (0.0, 0.05, 0.0), "inside (between the plates)"),
        ("in_y5_z15", (0.0, 0.05, 0.15), "inside (between the plates)"),
        ("in_y15_z0", (0.0, 0.15, 0.0), "inside (between the plates)"),
        ("in_y15_z10", (0.0, 0.15, 0.10), "inside (between the plates)"),
        ("in_y5_x30_z0", (0.30, 0.05, 0.0), "inside (between the plates)"),
        ("in_y30_z0", (0.0, 0.30, 0.0), "inside (between the plates)"),
        ("out_y-5_z0", (0.0, -0.05, 0.0), "outside (in front of the bay)"),
        ("out_y-5_z15", (0.0, -0.05, 0.15), "outside (in front of the bay)"),
        ("out_y-10_z20", (0.0, -0.10, 0.20), "outside (in front of the bay)"),
        ("out_y-5_x30_z10", (0.30, -0.05, 0.10), "outside (in front of the bay)"),
        ("out_y-20_z0", (0.0, -0.20, 0.0), "outside (in front of the bay)"),
    ]
    return Case(
        name="rack_bay",
        description="two horizontal PEC shelf plates 0.9 × 0.5 m (x ∈ [−0.45, 0.45], y ∈ [0, 0.5]) at z = ±0.2 m, "
                    "front edges at y = 0; z dipole at (0, −1, 0); tags between the plates near the front edge and "
                    "just in front of it",
        boxes=(top, bottom),
        source=(0.0, -1.0, 0.0),
        axis="z",
        observers=_labelled(specs, (top, bottom)),
        domain_lo=(-0.60, -1.10, -0.35),
        domain_hi=(0.60, 0.65, 0.35),
        polarization_name="vertical (z)",
        symmetries=(("x", 1), ("z", -1)),
    )


# Case (d): a tag behind a rack upright: a PEC post 5 × 5 cm × 1 m (x ∈ [−0.025, 0.025], y ∈ [0, 0.05],
# z ∈ [−0.5, 0.5]); a dipole 1.5 m in front; tags 5–30 cm behind it. Run at 40, 80 and 120 px/m, where the post's
# faces are on the grid (±1, ±2 and ±3 cells), so every resolution models the same 5 cm post. `axis` "z": the
# dipole along the post (soft: E ∥ axis); "x": across it (hard: E ⊥ axis, horizontal, as a tag lying flat on a
# shelf sees an upright).
def upright(axis: str = "z") -> Case:
    post = Box((-0.025, 0.0, -0.5), (0.025, 0.05, 0.5), "metal")
    specs = []
    for d in (0.05, 0.10, 0.20, 0.30):
        specs.append((f"behind_{d * 100:.0f}cm", (0.0, 0.05 + d, 0.0), "behind, on the axis"))
    for d in (0.05, 0.10, 0.20, 0.30):
        specs.append((f"behind_{d * 100:.0f}cm_x10", (0.10, 0.05 + d, 0.0), "behind, 10 cm aside"))
    specs.append(("behind_10cm_z40", (0.0, 0.15, 0.40), "behind, near the top"))
    soft = axis == "z"
    return Case(
        name="upright" if soft else "upright_hard",
        description="PEC post 5 × 5 cm × 1 m (x ∈ [−0.025, 0.025], y ∈ [0, 0.05], z ∈ [−0.5, 0.5]); "
                    f"{axis} dipole at (0, −1.5, 0); tags 5–30 cm behind its back face, on the axis and 10 cm aside",
        boxes=(post,),
        source=(0.0, -1.5, 0.0),
        axis=axis,
        observers=_labelled(specs, (post,)),
        domain_lo=(-0.30, -1.60, -0.65),
        domain_hi=(0.30, 0.40, 0.65),
        polarization_name="vertical (z)" if soft else "horizontal (x), across the post",
        # meep mirror planes through the dipole: E_z is even in x and odd in z; E_x odd in x and even in z.
        symmetries=(("x", 1), ("z", -1)) if soft else (("x", -1), ("z", 1)),
    )


# Case (d2): a rack post with its shelves: the rack bay of case (c) (plates 0.9 × 0.5 m at z = ±0.2, front edges at
# y = 0) with a 5 × 5 cm × 1 m PEC post at the middle of its front, half proud of the plates (x, y ∈ [−0.025, 0.025],
# z ∈ [−0.5, 0.5]; on the grid at 40, 80 and 120 px/m), the plates running through it; z dipole 1 m in front. The
# post model (raytrace/thin_posts.h) treats the post as free-standing: this checks it where shelves touch it, as in
# a warehouse. Tags on the shelves' front beside the post, in front of the post, and in the bay behind it.
def rack_post() -> Case:
    top = Box((-0.45, 0.0, 0.2), (0.45, 0.5, 0.2), "metal")
    bottom = Box((-0.45, 0.0, -0.2), (0.45, 0.5, -0.2), "metal")
    post = Box((-0.025, -0.025, -0.5), (0.025, 0.025, 0.5), "metal")
    specs = [
        ("front_x10", (0.10, -0.06, 0.0), "beside the post, in front of the shelves"),
        ("front_x20", (0.20, -0.06, 0.0), "beside the post, in front of the shelves"),
        ("front_x10_z15", (0.10, -0.06, 0.15), "beside the post, in front of the shelves"),
        ("front_x30_z10", (0.30, -0.06, 0.10), "beside the post, in front of the shelves"),
        ("before_y10", (0.0, -0.125, 0.0), "in front of the post"),
        ("before_y20_z10", (0.0, -0.225, 0.10), "in front of the post"),
        ("bay_y10", (0.0, 0.10, 0.0), "in the bay behind the post"),
        ("bay_y20", (0.0, 0.20, 0.0), "in the bay behind the post"),
        ("bay_x10_y10", (0.10, 0.10, 0.0), "in the bay behind the post"),
    ]
    return Case(
        name="rack_post",
        description="rack bay (plates 0.9 × 0.5 m at z = ±0.2, front edges at y = 0) with a 5 × 5 cm × 1 m PEC post at "
                    "the middle of its front (x, y ∈ [−0.025, 0.025]), the plates through it; z dipole at (0, −1, 0)",
        boxes=(top, bottom, post),
        source=(0.0, -1.0, 0.0),
        axis="z",
        observers=_labelled(specs, (top, bottom, post)),
        domain_lo=(-0.60, -1.10, -0.65),
        domain_hi=(0.60, 0.65, 0.65),
        polarization_name="vertical (z)",
        symmetries=(("x", 1), ("z", -1)),
    )


# Case (f): a concrete wall with a doorway (issue #33): the wall of case (e), 2.1 × 1.6 × 0.2 m (x ∈ [−1.05, 1.05],
# z ∈ [−0.8, 0.8], y ∈ [0, 0.2]), with an opening 0.9 m wide and 1.1 m high centred on the origin (|x| < 0.45,
# |z| < 0.55; the meep mirror plane z = 0 needs the opening centred in z, so it has a lintel and a sill 25 cm deep);
# z dipole 0.8 m in front of the opening's centre, so its E is along the jambs. Observers in the opening, behind
# it, just behind a jamb (in and beside the jamb's shadow boundary x ≈ 0.45·(0.8 + y)/0.8) and in the wall's
# shadow. The wall is 8 slab boxes on a 3 × 3 grid without the centre, corners shared (rfidray welds them into one
# facet with a hole: no T-junction makes a false edge); rho is the distance to the real edges (the outline and the
# opening's), not to the seams.
DOOR_HALF_WIDTH_M = 0.45
DOOR_HALF_HEIGHT_M = 0.55
DOORWAY_WALL_HALF_M = (1.05, 0.8)   # x, z


def doorway() -> Case:
    t = WALL_THICKNESS_M
    xs = (-DOORWAY_WALL_HALF_M[0], -DOOR_HALF_WIDTH_M, DOOR_HALF_WIDTH_M, DOORWAY_WALL_HALF_M[0])
    zs = (-DOORWAY_WALL_HALF_M[1], -DOOR_HALF_HEIGHT_M, DOOR_HALF_HEIGHT_M, DOORWAY_WALL_HALF_M[1])
    boxes = tuple(Box((xs[i], 0.0, zs[j]), (xs[i + 1], 0.0, zs[j + 1]), "concrete", eps_r=CONCRETE_EPS_R,
                      sigma_s_m=CONCRETE_SIGMA_S_M, slab_m=t)
                  for i in range(3) for j in range(3) if (i, j) != (1, 1))
    outline = (Box((xs[0], 0.0, zs[0]), (xs[3], 0.0, zs[3]), "concrete", slab_m=t),
               Box((xs[1], 0.0, zs[1]), (xs[2], 0.0, zs[2]), "concrete", slab_m=t))
    j = DOOR_HALF_WIDTH_M
    specs = [
        ("open_x0_mid", (0.0, t / 2, 0.0), "in the opening"),
        ("open_x30_mid", (0.30, t / 2, 0.0), "in the opening"),
        ("open_x40_mid", (0.40, t / 2, 0.0), "in the opening"),
        ("behind_x0_15cm", (0.0, t + 0.15, 0.0), "behind the opening"),
        ("behind_x30_20cm", (0.30, t + 0.20, 0.0), "behind the opening"),
        ("behind_x0_15cm_z45", (0.0, t + 0.15, 0.45), "behind the opening"),
        ("jamb_in_10cm", (j - 0.05, t + 0.10, 0.0), "just behind a jamb"),
        ("jamb_out_10cm", (j + 0.05, t + 0.10, 0.0), "just behind a jamb"),
        ("jamb_out_25cm", (j + 0.10, t + 0.25, 0.0), "just behind a jamb"),
        ("jamb_deep_10cm", (j + 0.15, t + 0.10, 0.0), "just behind a jamb"),
        ("shadow_x80_10cm", (0.80, t + 0.10, 0.0), "in the wall's shadow"),
        ("shadow_x80_25cm", (0.80, t + 0.25, 0.0), "in the wall's shadow"),
        ("shadow_x75_z30", (0.75, t + 0.20, 0.30), "in the wall's shadow"),
        ("front_x30_30cm", (0.30, -0.30, 0.0), "in front"),
        ("front_x70_20cm", (0.70, -0.20, 0.0), "in front"),
    ]
    obs = []
    for label, p, region in specs:
        p = tuple(round(v, 9) for v in p)
        obs.append(Observer(label, p, nearest_edge_m(p, outline), math.degrees(math.atan2(p[1], p[0])), region))
    return Case(
        name="doorway",
        description=f"concrete wall 2.1 × 1.6 × {t:g} m (x ∈ [−1.05, 1.05], z ∈ [−0.8, 0.8], y ∈ [0, {t:g}]; "
                    f"ε' = {CONCRETE_EPS_R:.2f}, σ = {CONCRETE_SIGMA_S_M:.4f} S/m) with a doorway 0.9 × 1.1 m "
                    f"(|x| < 0.45, |z| < 0.55); z dipole at (0, −0.8, 0); rfidray: the front face y = 0 (one facet "
                    f"with a hole) with --thickness {t:g}",
        boxes=boxes,
        source=WALL_SOURCE_M,
        axis="z",
        observers=tuple(obs),
        domain_lo=(-1.20, -0.95, -0.95),
        domain_hi=(1.20, 0.65, 0.95),
        polarization_name="vertical (z)",
        symmetries=(("x", 1), ("z", -1)),
        eps_averaging=True,
        convergence_order=2,
    )


# Case (g): a link grazing a shelf plate's corner (the paper warehouse's fixed antenna reads a tag past a shelf's
# corner so): a horizontal PEC plate 0.6 × 0.6 m (z = 0, x, y ∈ [0, 0.6]), its corner at the origin; a z dipole
# (normal to the plate: E across both edges) in front of the edge y = 0, just above the plate's plane; tags beyond the
# edge x = 0, just above and below the plane. The paths that diffract at the edge y = 0 and then at the edge x = 0,
# across the plate near its corner, are second-order diffraction between two edges of one facet.
def plate_corner() -> Case:
    plate = Box((0.0, 0.0, 0.0), (0.6, 0.6, 0.0), "metal")
    source = (0.45, -0.8, 0.05)
    specs = []
    # Below the plane: the direct line crosses the plate at (cx, cy), a few centimetres from its corner (shadowed);
    # above it at the same x, y: lit.
    for cx, cy, z in ((0.03, 0.03, -0.02), (0.08, 0.03, -0.02), (0.03, 0.08, -0.02), (0.10, 0.10, -0.02),
                      (0.03, 0.03, -0.03), (0.08, 0.08, -0.03)):
        f = (source[2] - z) / source[2]
        x, y = source[0] + f * (cx - source[0]), source[1] + f * (cy - source[1])
        x, y = round(x, 3), round(y, 3)
        specs.append((f"shadow_c{cx * 100:.0f}_{cy * 100:.0f}_z{z * 100:+.0f}", (x, y, z), "shadowed by the corner"))
        specs.append((f"lit_c{cx * 100:.0f}_{cy * 100:.0f}_z{-z * 100:+.0f}", (x, y, -z), "lit, beyond the corner"))
    return Case(
        name="plate_corner",
        description="horizontal PEC plate 0.6 × 0.6 m (z = 0, x, y ∈ [0, 0.6]), corner at the origin; z dipole at "
                    "(0.45, −0.8, 0.05); tags beyond the corner 2–3 cm below the plate's plane, shadowed by it a few "
                    "centimetres from the corner, and as far above it, lit",
        boxes=(plate,),
        source=source,
        axis="z",
        observers=_labelled(specs, (plate,)),
        domain_lo=(-0.40, -0.95, -0.30),
        domain_hi=(0.75, 0.80, 0.30),
        polarization_name="vertical (z), across both edges",
    )


def plate_corner_line() -> Case:
    """Case (g)'s plate and source, tags along the line (x, 0.9, −0.05) across the two places where `full` jumps
    (docs/fullwave.md, "Where `full` is discontinuous": x = −0.50604, the edge y = 0's Keller point at its end, and
    x = −0.34543, the corner pair's path at the corner), to check the edge-end check's estimate against FDTD."""
    plate = Box((0.0, 0.0, 0.0), (0.6, 0.6, 0.0), "metal")
    specs = []
    for x in (-0.70, -0.60, -0.55, -0.52, -0.50, -0.48, -0.45, -0.40, -0.36, -0.33, -0.30, -0.20, -0.10, 0.0, 0.10):
        region = "past x = -0.506" if x < -0.50604 else ("between the jumps" if x < -0.34543 else "past x = -0.345")
        specs.append((f"line_x{x * 100:+.0f}", (x, 0.9, -0.05), region))
    return Case(
        name="plate_corner_line",
        description="case (g)'s horizontal PEC plate 0.6 × 0.6 m (z = 0, x, y ∈ [0, 0.6]) and z dipole at "
                    "(0.45, −0.8, 0.05); tags along (x, 0.9, −0.05), x = −0.70 … 0.10, across the two jumps of `full`",
        boxes=(plate,),
        source=(0.45, -0.8, 0.05),
        axis="z",
        observers=_labelled(specs, (plate,)),
        domain_lo=(-0.85, -0.95, -0.30),
        domain_hi=(0.75, 1.05, 0.30),
        polarization_name="vertical (z), across both edges",
    )


def plate_grazing() -> Case:
    """A wide plate (a shelf) crossed by the direct line near grazing, far from its corners: the source 5 cm above
    its plane, tags a few centimetres below it beyond the far side, so that the line passes through the plate close
    to its front edge with E normal to it (issue #33: what the corner line showed, without an edge's end nearby)."""
    plate = Box((-0.9, 0.0, 0.0), (0.9, 0.6, 0.0), "metal")
    source = (0.0, -0.8, 0.05)
    specs = []
    for y, z in ((0.9, -0.02), (0.9, -0.05), (0.9, -0.10), (0.9, -0.20), (1.3, -0.05), (1.3, -0.10), (0.9, 0.02),
                 (0.9, 0.05), (0.3, -0.05), (0.3, 0.05)):
        region = ("beyond the plate, below its plane" if z < 0 else "beyond the plate, above its plane") if y > 0.6 \
            else ("under the plate" if z < 0 else "over the plate")
        specs.append((f"y{y * 100:.0f}_z{z * 100:+.0f}", (0.0, y, z), region))
    return Case(
        name="plate_grazing",
        description="horizontal PEC plate 1.8 × 0.6 m (z = 0, x ∈ [−0.9, 0.9], y ∈ [0, 0.6]); z dipole at (0, −0.8, 0.05), "
                    "5 cm above its plane; tags on x = 0 beyond the far side and over and under the plate: the direct "
                    "line crosses the plate near grazing, 0.9 m from its corners",
        boxes=(plate,),
        source=source,
        axis="z",
        observers=_labelled(specs, (plate,)),
        domain_lo=(-1.05, -0.95, -0.35),
        domain_hi=(1.05, 1.45, 0.30),
        polarization_name="vertical (z), normal to the plate",
    )


def plate_corner_steep(thickness_m: float = 0.0) -> Case:
    """Case (g)'s plate lit steeply (34° from its normal) by a horizontal dipole, E along the plate: the corner's
    shadow and reflection near the tags without grazing, to tell what is the corner's and what is grazing's in the
    errors of cases (g) and its line (issue #33). With `thickness_m` > 0 the plate is a closed metal box that thick
    below z = 0, as the shelves of rfidray's warehouses are (3 cm in scenes/paper_warehouse.obj): its corner is
    three wedge edges, not a sheet's two."""
    plate = Box((0.0, 0.0, -thickness_m), (0.6, 0.6, 0.0), "metal")
    source = (0.35, 0.35, 0.5)
    specs = []
    # The direct line (below the plane) or the reflected one (above it, from the source's image) meets the plane at
    # (cx, cy), a few centimetres from the corner: shadowed when (cx, cy) is on the plate, lit past its edges.
    for cx, cy in ((0.03, 0.03), (0.08, 0.03), (0.03, 0.08), (-0.03, 0.03), (0.03, -0.03), (-0.03, -0.03),
                   (-0.08, 0.05), (0.10, 0.10)):
        for z in (-0.10, 0.10):
            f = (source[2] + abs(z)) / source[2]
            x, y = round(source[0] + f * (cx - source[0]), 4), round(source[1] + f * (cy - source[1]), 4)
            on_plate = cx > 0.0 and cy > 0.0
            region = ("shadowed" if on_plate else "lit, past the corner") if z < 0 else \
                ("reflected" if on_plate else "no reflection, past the corner")
            specs.append((f"{'below' if z < 0 else 'above'}_c{cx * 100:+.0f}_{cy * 100:+.0f}", (x, y, z), region))
    return Case(
        name="plate_corner_steep" + ("_box" if thickness_m > 0.0 else ""),
        description=("horizontal PEC plate 0.6 × 0.6 m (z = 0, x, y ∈ [0, 0.6])" +
                     (f", a closed box {thickness_m * 100:.0f} cm thick below z = 0" if thickness_m > 0.0 else "") +
                     ", corner at the origin; x dipole at "
                     "(0.35, 0.35, 0.5); tags 10 cm below the plane where the direct line passes a few centimetres "
                    "from the corner, and 10 cm above it where the reflected line does"),
        boxes=(plate,),
        source=source,
        axis="x",
        observers=_labelled(specs, (plate,)),
        domain_lo=(-0.30, -0.30, -0.30),
        domain_hi=(0.75, 0.75, 0.65),
        polarization_name="horizontal (x), along the plate",
    )


# How each case's stored reference was made (run.py --all runs them all so, in this order, which is also the order of
# the validity table): FDTD resolutions (px/m; the two finest are extrapolated), PML thicknesses (m; the second is a
# check at the coarsest resolution) and a sheet thickness checked at the coarsest resolution (m; 0: none).
RUNS = {
    "sheet_edge_soft": ((30, 60, 90), (0.2, 0.35), 0.02),
    "sheet_edge_hard": ((30, 60, 90, 120), (0.2,), 0.0),
    "sheet_edge_soft_tall": ((30, 60, 90), (0.2,), 0.0),
    "sheet_edge_hard_tall": ((30, 60, 90), (0.2,), 0.0),
    "wedge_edge_soft": ((30, 60, 90), (0.2,), 0.0),
    "wedge_edge_hard": ((30, 60, 90), (0.2,), 0.0),
    "concrete_wall": ((30, 60, 90), (0.2, 0.35), 0.0),
    "doorway": ((30, 60), (0.2, 0.35), 0.0),
    "plate_front": ((30, 60, 90), (0.2, 0.35), 0.0),
    "rack_bay": ((30, 60, 90), (0.2, 0.35), 0.0),
    "upright": ((40, 80, 120), (0.2, 0.35), 0.0),
    "upright_hard": ((40, 80, 120), (0.2, 0.35), 0.0),
    "rack_post": ((40, 80, 120), (0.2, 0.35), 0.0),
    "plate_corner": ((30, 60), (0.2,), 0.0),
    "plate_corner_line": ((30, 60), (0.2,), 0.02),
    "plate_grazing": ((30, 60), (0.2,), 0.0),
    "plate_corner_steep": ((30, 60), (0.2,), 0.0),
    "plate_corner_steep_box": ((60, 120), (0.2,), 0.0),
}

CASES = {
    "sheet_edge_soft": lambda: sheet_edge("z"),
    "sheet_edge_hard": lambda: sheet_edge("x"),
    "sheet_edge_soft_tall": lambda: sheet_edge("z", half_height_m=0.8),
    "sheet_edge_hard_tall": lambda: sheet_edge("x", half_height_m=0.8),
    "wedge_edge_soft": lambda: wedge_edge("z"),
    "wedge_edge_hard": lambda: wedge_edge("x"),
    "concrete_wall": concrete_wall,
    "plate_front": plate_front,
    "plate_front_near": plate_front_near,
    "rack_bay": rack_bay,
    "upright": upright,
    "upright_hard": lambda: upright("x"),
    "rack_post": rack_post,
    "doorway": doorway,
    "plate_corner": plate_corner,
    "plate_corner_line": plate_corner_line,
    "plate_grazing": plate_grazing,
    "plate_corner_steep": plate_corner_steep,
    "plate_corner_steep_box": lambda: plate_corner_steep(0.04),
}
