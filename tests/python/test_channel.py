"""Scene, Endpoint, Channel: the two-ray closed form through one_way, paths identical to `rfidray link --json`."""
import cmath
import math

import numpy as np
import pytest

import rfidray
from conftest import SOURCE_DIR, link_json

F_HZ = 865.7e6
C_M_S = 299792458.0
LAMBDA = C_M_S / F_HZ
K = 2 * math.pi / LAMBDA


def ground_obj(tmp_path, material):
    """A 400 m x 400 m ground at z = 0 (two triangles), one radio material."""
    obj = tmp_path / f"ground_{material}.obj"
    obj.write_text(f"v -200 -200 0\nv 200 -200 0\nv 200 200 0\nv -200 200 0\nusemtl {material}\nf 1 2 3\nf 1 3 4\n")
    return obj


def gamma_te(material, cos_i):
    """Fresnel reflection of the E-field perpendicular to the plane of incidence at a half-space,
    Γ = (cos θ − √(η − sin²θ)) / (cos θ + √(η − sin²θ)), η = ε' − jσ/(ωε0) with ITU-R P.2040 Table 3's
    ε' = a·f^b, σ = c·f^d (f in GHz). A perfect conductor gives −1."""
    if material == "metal":
        return -1.0
    a, b, c, d = {"concrete": (5.24, 0.0, 0.0462, 0.7822)}[material]
    f_ghz = F_HZ / 1e9
    eta = a * f_ghz ** b - 1j * (c * f_ghz ** d) / (2 * math.pi * F_HZ * 8.8541878128e-12)
    sin2 = 1 - cos_i ** 2
    root = cmath.sqrt(eta - sin2)
    return (cos_i - root) / (cos_i + root)


@pytest.mark.parametrize("material", ["metal", "concrete"])
def test_one_way_matches_the_two_ray_closed_form(tmp_path, material):
    # Antenna and tags horizontally polarized across the link (TE): h = λ/4π (e^{−jkd1}/d1 + Γ e^{−jkd2}/d2).
    channel = rfidray.Channel(rfidray.Scene.load(ground_obj(tmp_path, material)), "single-bounce")
    te = {"kind": "linear", "axis": [0, 1, 0]}
    ha, ht = 1.2, 0.7
    antenna = rfidray.Endpoint([0.0, 0.0, ha], polarization=te)
    d = np.array([0.5, 1.0, 2.0, 3.5, 7.5, 15.0, 30.0])
    tags = np.column_stack([d, np.zeros_like(d), np.full_like(d, ht)])
    h = channel.one_way(antenna, tags, F_HZ, tag=rfidray.Endpoint([0, 0, 0], polarization=te))
    assert h.dtype == np.complex128 and h.shape == d.shape
    d1, d2 = np.hypot(d, ha - ht), np.hypot(d, ha + ht)
    expected = LAMBDA / (4 * math.pi) * (np.exp(-1j * K * d1) / d1 +
                                         np.array([gamma_te(material, (ha + ht) / r) for r in d2]) * np.exp(-1j * K * d2) / d2)
    # The library computes in double precision; 1e-9 leaves room for the different order of operations.
    np.testing.assert_allclose(h, expected, rtol=1e-9, atol=0)


def test_one_way_free_space_is_friis():
    h = rfidray.Channel(None, "ideal").one_way([0, 0, 0], [[3.0, 4.0, 0.0], [0.0, 0.0, 10.0]], F_HZ)
    dist = np.array([5.0, 10.0])
    np.testing.assert_allclose(h, LAMBDA / (4 * math.pi * dist) * np.exp(-1j * K * dist), rtol=1e-12)


def test_one_way_equals_the_sum_of_paths():
    scene = rfidray.Scene.load(SOURCE_DIR / "scenes" / "paper_warehouse.obj")
    channel = rfidray.Channel(scene, "single-bounce")
    antenna = [3.5, -4.0, 2.0]
    tags = np.array([[2.9, 0.57, 2.05], [-4.85, -3.03, 1.85], [2.9, -8.66, 2.05]])
    h = channel.one_way(antenna, tags)
    for i, t in enumerate(tags):
        assert h[i] == pytest.approx(sum(p.contribution for p in channel.paths(antenna, t)), rel=1e-12)


@pytest.mark.parametrize("antenna,tag,level", [
    ("3.5,-4.0,2.0", "2.90,0.57,2.05", "single-bounce"),
    ("-1.0,-2.0,1.68", "-4.85,-3.03,1.85", "single-bounce"),
    ("-1.0,-2.0,1.68", "2.90,-4.82,2.05", "los+blocked"),
])
def test_paths_are_identical_to_rfidray_link_json(antenna, tag, level):
    obj = SOURCE_DIR / "scenes" / "paper_warehouse.obj"
    expected = link_json("--scene", obj, "--antenna", antenna, "--tag", tag, "--channel", level)["raytraced"]
    channel = rfidray.Channel(rfidray.Scene.load(obj), level)
    a = [float(v) for v in antenna.split(",")]
    t = [float(v) for v in tag.split(",")]
    paths = channel.paths(a, t, F_HZ)
    assert channel.name == expected["channel"]
    assert len(paths) == len(expected["paths"]) >= 1
    # The same doubles: the JSON prints the shortest text that reads back exactly.
    for p, e in zip(paths, expected["paths"]):
        assert p.kind == e["kind"]
        assert p.length_m == e["length_m"]
        assert list(p.point) == e["point"]
        assert p.material == e["material"]
        assert p.crossings == e["crossings"]
        assert p.coefficient == complex(e["coefficient"]["re"], e["coefficient"]["im"])
        assert p.contribution == complex(e["contribution"]["re"], e["contribution"]["im"])
        pts = p.points
        assert pts.shape == ((3, 3) if p.kind == "reflection" else (2, 3))
        assert list(pts[0]) == a and list(pts[-1]) == t
    h = sum(p.contribution for p in paths)
    assert h == pytest.approx(complex(expected["h"]["re"], expected["h"]["im"]), rel=1e-14)


def test_endpoint_takes_the_scenario_keys():
    e = rfidray.Endpoint([1, 2, 3], rpy_deg=[0, 0, 90], pattern={"kind": "patch", "gain_dbi": 8}, polarization="rhcp")
    assert list(e.position) == [1, 2, 3]
    assert e.pattern == "patch" and e.gain_dbi == 8 and e.polarization == "rhcp"
    # yaw 90°: quaternion (0, 0, sin 45°, cos 45°)
    np.testing.assert_allclose(e.quaternion, [0, 0, math.sqrt(0.5), math.sqrt(0.5)], atol=1e-15)
    # Bare positions take link's defaults: a patch antenna facing away from the tag loses its front gain.
    channel = rfidray.Channel(None, "ideal")
    facing = channel.one_way(rfidray.Endpoint([0, 0, 0], pattern={"kind": "patch", "gain_dbi": 8}), [[2, 0, 0]])
    away = channel.one_way(rfidray.Endpoint([0, 0, 0], rpy_deg=[0, 0, 180], pattern={"kind": "patch", "gain_dbi": 8}),
                           [[2, 0, 0]])
    iso = channel.one_way([0, 0, 0], [[2, 0, 0]])
    assert abs(facing[0]) ** 2 / abs(iso[0]) ** 2 == pytest.approx(10 ** 0.8, rel=1e-9)
    assert abs(away[0]) < abs(facing[0]) / 5


def test_scene_reports_its_geometry():
    scene = rfidray.Scene.load(SOURCE_DIR / "scenes" / "ground_wall.obj")
    assert scene.triangles == 4
    assert scene.materials == ["concrete"]
    # The README's hand check: LoS 3.0414 m, ground 3.9051 m, wall 7.0178 m.
    lengths = sorted(p.length_m for p in rfidray.Channel(scene).paths([0, 0, 1], [3, 0, 1.5]))
    assert lengths == pytest.approx([math.sqrt(9.25), math.sqrt(15.25), math.sqrt(49.25)], abs=1e-12)


def test_world_scene_matches_rfidray_link_world():
    world_dir = SOURCE_DIR / "scenes" / "tests" / "gazebo"
    try:
        scene = rfidray.Scene.load(world_dir / "rfid_test.world", resource_path=[str(world_dir / "models")])
    except ValueError as e:
        if "built without sdformat" in str(e):
            pytest.skip(str(e))
        raise
    expected = link_json("--world", world_dir / "rfid_test.world", "--resource-path", world_dir / "models",
                         "--antenna", "reader", "--tag", "tag_1::link")
    assert scene.triangles == expected["scene"]["triangles"]
    antennas, tags = dict(scene.antennas), dict(scene.tags)
    assert set(antennas) == {"reader", "gate"} and "tag_1::link" in tags
    # link --world takes the world's poses with its own pattern and polarization flags; lengths and materials
    # depend on the positions alone.
    paths = rfidray.Channel(scene).paths(antennas["reader"].position, tags["tag_1::link"].position)
    assert [(p.kind, p.length_m, p.material) for p in paths] == \
        [(e["kind"], e["length_m"], e["material"]) for e in expected["raytraced"]["paths"]]


def test_tag_coupling_beside_metal_matches_link():
    # The tag antenna model (docs/tag-antenna.md): a half-wave dipole 1 cm from metal, as `rfidray link` gives it.
    free = rfidray.tag_coupling("dipole:0.166:0.0005", frequency_hz=866e6)
    assert abs(free["power_transfer"] - 1.0) < 1e-12
    assert abs(free["modulation_factor"] - 0.25) < 1e-12
    on_metal = rfidray.tag_coupling("dipole:0.166:0.0005", "matched", "metal:0.01", 866e6)
    assert abs(on_metal["power_transfer_db"] + 10.3) < 0.3  # NEC-2: -10.3 dB (tests/core/test_tag_antenna.cpp)
    assert abs(on_metal["impedance_ohm"].real - 1.9) < 0.2
    assert isinstance(on_metal["impedance_ohm"], complex)
    with pytest.raises(rfidray.InputError, match="backing"):
        rfidray.tag_coupling("dipole:0.166:0.0005", "matched", "scene")
    with pytest.raises(rfidray.InputError, match="antenna"):
        rfidray.tag_coupling("dipole:0.166")
