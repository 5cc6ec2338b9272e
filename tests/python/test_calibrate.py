"""rfidray.calibrate: the same calibration as `rfidray calibrate` from readings and truth in any form localize
takes, the antenna file it writes, and its errors."""
import json

import numpy as np
import pytest

import rfidray
from conftest import SOURCE_DIR, run_cli

STAGE = SOURCE_DIR / "scenes" / "stage_1m.yaml"


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Two reference runs of the 1 m stage (3 tags at known positions each), ideal channel, other noise."""
    out = []
    for seed in (3, 4):
        d = tmp_path_factory.mktemp(f"stage{seed}")
        run_cli("simulate", STAGE, "--channel", "ideal", "--seed", seed, "-q", "-o", d)
        out.append(d)
    return out


def test_calibrate_matches_the_command(runs, tmp_path):
    a, b = runs
    cli_file = tmp_path / "cli.yaml"
    expected = json.loads(run_cli("calibrate", "--pair", f"{a / 'stage.csv'},{a / 'tags.csv'}", "--pair",
                                  f"{b / 'stage.csv'},{b / 'tags.csv'}", "--height-known", "--json",
                                  "-o", cli_file).stdout)
    # The second run as arrays and a dict: the same reads, the same calibration.
    truth_b = {row["name"]: (row["x"], row["y"], row["z"]) for row in
               (dict(zip(["name", "x", "y", "z"], line.strip().split(","))) for line in
                (b / "tags.csv").read_text().splitlines()[1:])}
    truth_b = {k: tuple(float(x) for x in v) for k, v in truth_b.items()}
    py_file = tmp_path / "py.yaml"
    got = rfidray.calibrate([(a / "stage.csv", a / "tags.csv"), (rfidray.load_readings(b / "stage.csv"), truth_b)],
                            height_known=True, output=py_file)
    assert got["antenna"] == expected["antenna"] == "stage"
    assert got["tags_used"] == expected["tags_used"] == 6
    for key in ("phase_centre_offset_m", "phase_centre_offset_sd_m", "frequencies_hz", "carrier_offsets_rad",
                "carrier_offsets_sd_rad", "pattern_rad", "pattern_sd_rad", "geometry_covariance"):
        np.testing.assert_array_equal(got[key], np.array(expected[key]), err_msg=key)
    # What the command says about its own and held-out references, under the same keys (too few tags here to
    # measure either: 6 of the 10 needed, so both are None in both).
    for key in ("references_localized", "held_out", "carrier_offsets_not_fitted", "residual_rms_rad"):
        assert got[key] == expected[key], key
    assert expected["held_out"] is None
    assert got["geometry_covariance"].shape == (8, 8)
    assert got["geometry_covariance"][0, 0] > 0  # the offset along boresight is fitted, with an uncertainty
    assert py_file.read_text() == cli_file.read_text()
    # The file is what localize takes.
    results = rfidray.localize(b / "stage.csv", method="nlls", truth=b / "tags.csv", height_known=True,
                               mirror_prior="boresight", max_range_m=3, antenna_file=py_file)
    assert len(results) == 3 and all(r["status"] in ("ok", "uncertain", "failed") for r in results)


def test_calibrate_errors_name_the_argument(runs, tmp_path):
    a, _ = runs
    with pytest.raises(rfidray.InputError, match="pair"):
        rfidray.calibrate([a / "stage.csv"])
    with pytest.raises(rfidray.InputError, match="truth is None"):
        rfidray.calibrate([(a / "stage.csv", None)])
    with pytest.raises(rfidray.InputError, match="at least 2 tags"):
        rfidray.calibrate([(a / "stage.csv", {"tag1": (0.3, 0.88, 0.0)})])
    with pytest.raises(rfidray.InputError, match="truth\\['tag1'\\]"):
        rfidray.calibrate([(a / "stage.csv", {"tag1": (0.3, float("nan"), 0.0)})])
    # Readings of two antennas: which one must be said.
    two = rfidray.load_readings(a / "stage.csv")
    two = np.concatenate([two, two])
    two["antenna"][: len(two) // 2] = "other"
    with pytest.raises(rfidray.InputError, match="antenna"):
        rfidray.calibrate([(two, a / "tags.csv")])
    # A failed call writes no file.
    target = tmp_path / "never.yaml"
    with pytest.raises(rfidray.InputError):
        rfidray.calibrate([(a / "stage.csv", {"tag1": (0.3, 0.88, 0.0)})], output=target)
    assert not target.exists()


def test_localize_takes_the_allowance_of_the_tag_spacing(runs, tmp_path):
    """An antenna file with an allowance per band of tag spacing (as calibrate writes it from reference rows of
    different spacings): tag_spacing_m picks the band, whose σ_sys each result reports as systematic_rad; without
    it the pooled allowance; without an antenna file it is refused, naming the keyword."""
    a, b = runs
    cli_file = tmp_path / "cli.yaml"
    run_cli("calibrate", "--pair", f"{a / 'stage.csv'},{a / 'tags.csv'}", "--pair", f"{b / 'stage.csv'},{b / 'tags.csv'}",
            "--height-known", "-o", cli_file)
    text = cli_file.read_text() + (
        "allowance:\n  base_rad: 0.2\n  smooth_factor: 0\n  samples: 40\n  bands:\n"
        "    - {spacing_from_m: 0, spacing_below_m: 0.17, base_rad: 0.35, smooth_factor: 0, samples: 20}\n"
        "    - {spacing_from_m: 0.17, base_rad: 0.05, smooth_factor: 0, samples: 20}\n")
    banded = tmp_path / "banded.yaml"
    banded.write_text(text)
    common = dict(method="nlls", truth=b / "tags.csv", height_known=True, mirror_prior="boresight", max_range_m=3,
                  antenna_file=banded)
    for spacing, sigma in ((0.08, 0.35), (0.3, 0.05), (None, 0.2)):
        results = rfidray.localize(b / "stage.csv", tag_spacing_m=spacing, **common)
        positioned = [r for r in results if r["status"] != "failed"]
        assert positioned, results
        for r in positioned:
            assert r["systematic_rad"] == pytest.approx(sigma, abs=1e-12), (spacing, r)
    with pytest.raises(rfidray.InputError, match="tag_spacing_m.*needs antenna_file"):
        rfidray.localize(b / "stage.csv", method="nlls", tag_spacing_m=0.08)
    with pytest.raises(rfidray.InputError, match="tag_spacing_m"):
        rfidray.localize(b / "stage.csv", method="nlls", antenna_file=banded, tag_spacing_m=-1.0)
