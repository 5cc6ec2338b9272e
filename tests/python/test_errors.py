"""Bad input raises ValueError (rfidray.InputError) with the message the command prints."""
import numpy as np
import pytest

import rfidray
from conftest import SOURCE_DIR, run_cli


def cli_error(*args):
    proc = run_cli(*args, check=False)
    assert proc.returncode == 2, proc.stderr
    line = proc.stderr.strip().splitlines()[-1]
    assert line.startswith("rfidray: error: ")
    return line[len("rfidray: error: "):]


def test_input_error_is_a_value_error():
    assert issubclass(rfidray.InputError, ValueError)


def test_scenario_errors_carry_the_commands_message(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("antennas:\n  - name: a\n    position: [0, 0, 1]\n    frequency: -5\ntags:\n  - {name: t, position: [1, 0, 1]}\n")
    with pytest.raises(ValueError) as e:
        rfidray.simulate(bad)
    assert str(e.value) == cli_error("simulate", bad, "-o", tmp_path / "out")
    assert f"{bad}:4: field 'antennas[0].frequency'" in str(e.value)
    missing = tmp_path / "missing.yaml"
    with pytest.raises(ValueError) as e:
        rfidray.simulate(missing)
    assert str(e.value) == cli_error("simulate", missing, "-o", tmp_path / "out")


def test_dict_scenario_errors_name_the_field():
    # The dict's lines mean nothing to the user: the message names the field alone.
    with pytest.raises(ValueError) as e:
        rfidray.simulate({"antennas": [{"name": "a", "position": [0, 0, 1]}],
                          "tags": [{"name": "t", "position": [1, 0, 1], "gain_db": 3}]})
    assert str(e.value).startswith("scenario dict: field 'tags[0].gain_db': unknown key 'gain_db' (did you mean 'gain_dbi'?)")
    with pytest.raises(ValueError, match="channel"):
        rfidray.simulate(SOURCE_DIR / "scenes" / "paper_warehouse.yaml", channel="multi-bounce")


def test_readings_errors_name_file_line_and_column(tmp_path):
    bad = tmp_path / "r.csv"
    bad.write_text("time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi\n"
                   "0,0,0,0,0,0,0,1,t,1,0.5,-50\n"
                   "0.1,0,0,0,0,0,0,1,t,1,abc,-50\n")
    with pytest.raises(ValueError) as e:
        rfidray.load_readings(bad)
    assert str(e.value).startswith(f"{bad}:3: column 'phase'")
    assert str(e.value) == cli_error("localize", bad)


def test_argument_errors():
    scene = rfidray.Scene.load(SOURCE_DIR / "scenes" / "ground_wall.obj")
    with pytest.raises(ValueError, match=r"field 'channel_options.candidates': must be exact or exhaustive \(got 'slow'\)"):
        rfidray.Channel(scene, "single-bounce", candidates="slow")
    with pytest.raises(ValueError, match="unknown key 'candidate_ray'"):
        rfidray.Channel(scene, "single-bounce", candidate_ray=10)
    with pytest.raises(ValueError, match="needs a scene"):
        rfidray.Channel(None, "los")
    with pytest.raises(ValueError, match="auto"):
        rfidray.Channel(scene, "auto")
    with pytest.raises(ValueError, match=r"Endpoint: field 'pattern.gain_dbi'"):
        rfidray.Endpoint([0, 0, 0], pattern={"kind": "patch", "gain_dbi": 500})
    with pytest.raises(ValueError, match=r"field 'position': needs 3 numbers \(got 2\)"):
        rfidray.Endpoint([0, 0])
    ch = rfidray.Channel(scene)
    with pytest.raises(ValueError, match=r"tags\[1\]: coordinates must be finite"):
        ch.one_way([0, 0, 1], np.array([[1.0, 0, 1], [np.nan, 0, 1]]))
    with pytest.raises(ValueError, match=r"\(N, 3\) array"):
        ch.one_way([0, 0, 1], np.zeros((4, 2)))
    with pytest.raises(ValueError, match="frequency_hz"):
        ch.paths([0, 0, 1], [1, 0, 1], 0.0)
    with pytest.raises(ValueError, match="at the antenna"):
        ch.paths([0, 0, 1], [0, 0, 1])
    with pytest.raises(ValueError, match="method"):
        rfidray.localize(np.zeros(0, dtype=rfidray.readings_dtype()), method="magic")
    with pytest.raises(ValueError, match="no_such_scene.obj: cannot open OBJ file"):
        rfidray.Scene.load("no_such_scene.obj")
