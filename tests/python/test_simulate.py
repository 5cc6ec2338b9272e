"""simulate() against the CSV files of `rfidray simulate`, load_readings, localize against `rfidray localize`."""
import csv
import json

import numpy as np
import pytest

import rfidray
from conftest import SOURCE_DIR, run_cli

SCENARIO = SOURCE_DIR / "scenes" / "paper_warehouse.yaml"
# The CSV writer's decimals per column (io/readings_csv.cpp).
DECIMALS = {"time": 6, "posx": 6, "posy": 6, "posz": 6, "q1": 9, "q2": 9, "q3": 9, "q4": 9, "dist": 6, "phase": 6,
            "rssi": 4, "frequency_hz": 0}


def as_csv_text(value, column):
    """The text the CSV writer prints: fixed decimals, correctly rounded, never '-0.…' (Python's formatting
    rounds correctly too)."""
    if column not in DECIMALS:
        return str(value)
    text = f"{value:.{DECIMALS[column]}f}"
    return text[1:] if text.startswith("-") and set(text[1:]) <= set("0.") else text


@pytest.fixture(scope="module")
def paper_run(tmp_path_factory):
    """The paper scenario, physical model on the traced channel (so the channel matters), 20 s."""
    out = tmp_path_factory.mktemp("paper")
    args = ["--model", "physical", "--channel", "los+blocked", "--duration", "20", "--seed", "7"]
    run_cli("simulate", SCENARIO, *args, "-o", out, "-q")
    sim = rfidray.simulate(SCENARIO, model="physical", channel="los+blocked", duration_s=20, seed=7)
    return out, sim


def test_simulate_arrays_are_identical_to_the_csv(paper_run):
    out, sim = paper_run
    assert list(sim) == ["mobile", "fixed"]
    assert sim.channel == "los+blocked" and sim.seed == 7 and sim.duration_s == 20
    for antenna, readings in sim.items():
        assert readings.dtype.names == rfidray.READINGS_COLUMNS
        with open(out / f"{antenna}.csv", newline="") as f:
            rows = list(csv.reader(f))
        assert tuple(rows[0]) == rfidray.READINGS_COLUMNS
        assert len(rows) - 1 == len(readings) > 100
        for row, r in zip(rows[1:], readings):
            assert row == [as_csv_text(r[c].item(), c) for c in rfidray.READINGS_COLUMNS]
    # tags.csv
    with open(out / "tags.csv", newline="") as f:
        rows = list(csv.reader(f))[1:]
    assert rows == [[t["name"]] + [as_csv_text(t[c].item(), "posx") for c in "xyz"] for t in sim.tags]


def test_load_readings_reads_the_csv_back(paper_run):
    out, sim = paper_run
    loaded = rfidray.load_readings(out / "fixed.csv")
    ref = sim["fixed"]
    assert loaded.dtype.names == rfidray.READINGS_COLUMNS and len(loaded) == len(ref)
    assert (loaded["name"] == ref["name"]).all() and (loaded["antenna"] == ref["antenna"]).all()
    assert (loaded["channel"] == ref["channel"]).all()
    for c, dec in DECIMALS.items():
        # the file holds the values rounded to its decimals: half a unit of the last digit (+ the parse's ulp)
        np.testing.assert_allclose(loaded[c], ref[c], rtol=1e-15, atol=0.5 * 10.0 ** -dec * (1 + 1e-9))


def test_simulate_takes_a_dict_like_the_file():
    scenario = {"seed": 3, "duration_s": 2.0, "model": "physical",
                "antennas": [{"name": "a", "position": [0, 0, 1], "update_rate": 10}],
                "tags": [{"name": "t1", "position": [2, 0, 1]}, {"name": "t2", "position": [0, 3, 1]}]}
    sim = rfidray.simulate(scenario)
    r = sim["a"]
    assert len(r) == 2 * 21  # ticks at 0, 0.1, …, 2.0 s; both tags in range, noise-free powers well above
    np.testing.assert_allclose(r["dist"][r["name"] == "t1"], 2.0)
    assert list(sim.tags["name"]) == ["t1", "t2"]


def test_localize_matches_rfidray_localize_json(paper_run):
    out, _ = paper_run
    csv_file = out / "mobile.csv"
    expected = json.loads(run_cli("localize", csv_file, "--truth", out / "tags.csv", "--method", "nlls",
                                  "--height-known", "--mirror-prior", "truth", "--json").stdout)["results"]
    got = rfidray.localize(rfidray.load_readings(csv_file), method="nlls", truth=out / "tags.csv",
                           height_known=True, mirror_prior="truth")
    assert len(got) == len(expected) == 10
    for g, e in zip(got, expected):
        for key in ("name", "method", "status", "x", "y", "z", "uncertainty_m", "residual_rad", "reads"):
            assert g[key] == e.get(key), key
        assert g["error_m"] == e.get("error_m")
        assert g["reason"] == e.get("reason")
        assert g["systematic_rad"] == (e["radius_parts"]["systematic_rad"] if "radius_parts" in e else None)


def test_localize_takes_a_simulation(paper_run):
    _, sim = paper_run
    results = rfidray.localize(sim, method="nlls", truth=sim.tags, height_known=True, mirror_prior="truth")
    assert {r["name"] for r in results} == {f"tag{i}" for i in range(1, 11)}
    ok = [r for r in results if r["status"] == "ok"]
    assert ok and all(r["uncertainty_m"] > 0 and r["error_m"] is not None for r in ok)


def test_localize_gates_match_the_command(paper_run):
    out, _ = paper_run
    csv_file = out / "mobile.csv"
    args = ("--method", "nlls", "--height-known", "--mirror-prior", "truth", "--json", "--max-uncertainty-m", "0.1",
            "--max-residual-rad", "0.3")
    expected = json.loads(run_cli("localize", csv_file, "--truth", out / "tags.csv", *args).stdout)["results"]
    got = rfidray.localize(csv_file, method="nlls", truth=out / "tags.csv", height_known=True, mirror_prior="truth",
                           max_uncertainty_m=0.1, max_residual_rad=0.3)
    # The gate decides some, not all; a result over it keeps its position and radius (uncertain).
    assert {"ok", "uncertain"} <= {g["status"] for g in got} <= {"ok", "uncertain", "failed"}
    assert all(g["x"] is not None and g["uncertainty_m"] is not None for g in got if g["status"] == "uncertain")
    assert [g["status"] for g in got] == [e["status"] for e in expected]
    assert [g["detail"] for g in got] == [e.get("detail") for e in expected]
    with pytest.raises(rfidray.InputError, match="max_uncertainty_m"):
        rfidray.localize(csv_file, method="nlls", max_uncertainty_m=float("nan"))


def test_localize_with_the_known_scene_matches_the_command(paper_run):
    out, _ = paper_run
    csv_file = out / "mobile.csv"
    args = ("--method", "nlls", "--height-known", "--mirror-prior", "truth", "--json", "--scenario", SCENARIO,
            "--channel", "los+blocked")
    expected = json.loads(run_cli("localize", csv_file, "--truth", out / "tags.csv", *args).stdout)["results"]
    got = rfidray.localize(rfidray.load_readings(csv_file), method="nlls", truth=out / "tags.csv",
                           height_known=True, mirror_prior="truth", scenario=SCENARIO, channel="los+blocked")
    assert len(got) == len(expected) == 10
    assert any(g["multipath_phase_rad"] is not None for g in got)
    for g, e in zip(got, expected):
        for key in ("status", "x", "y", "uncertainty_m", "multipath_phase_rad"):
            assert g[key] == e.get(key), key
    with pytest.raises(rfidray.InputError, match="channel"):
        rfidray.localize(csv_file, method="nlls", channel="single-bounce")
