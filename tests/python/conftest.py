"""Shared fixtures of the Python tests: the rfidray binary and the source tree (set by ctest; defaults for a
manual `PYTHONPATH=build/python python3 -m pytest tests/python` from the source root)."""
import json
import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("RFIDRAY_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BINARY = pathlib.Path(os.environ.get("RFIDRAY_BINARY", SOURCE_DIR / "build" / "rfidray"))


@pytest.fixture
def source_dir() -> pathlib.Path:
    return SOURCE_DIR


def run_cli(*args, check=True):
    """Runs the rfidray command; returns the completed process (text)."""
    proc = subprocess.run([str(BINARY), *map(str, args)], capture_output=True, text=True, timeout=240)
    if check and proc.returncode != 0:
        raise AssertionError(f"rfidray {' '.join(map(str, args))} exited {proc.returncode}:\n{proc.stderr}")
    return proc


def link_json(*args):
    return json.loads(run_cli("link", *args, "--json").stdout)
