"""rfidray: a ray-traced multipath channel engine for passive UHF RFID, from Python.

The objects and runs of the ``rfidray`` command, on NumPy arrays:

- ``Scene.load(obj_or_world, ...)``, ``Channel(scene, level, **channel_options)``,
  ``channel.paths(antenna, tag, frequency_hz)`` and ``channel.one_way(antenna, tags, frequency_hz)``
  (``rfidray link``);
- ``simulate(scenario)`` (``rfidray simulate``): one structured array per antenna with the readings CSV's
  columns; ``load_readings(csv)`` reads such a file into the same array;
- ``localize(readings, method=...)`` (``rfidray localize``).

Units: metres, seconds, hertz, radians (degrees only where a name says ``_deg``). Bad input raises
``rfidray.InputError``, a ``ValueError`` whose message names the file, line and field, as the command prints it.
"""
from __future__ import annotations

import json
import os
import re
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np

from ._rfidray import Channel, Endpoint, InputError, Path, Scene
from ._rfidray import _calibrate, _load_readings, _localize, _simulate, tag_coupling

__all__ = ["Channel", "Endpoint", "InputError", "Path", "Scene", "Simulation", "READINGS_COLUMNS", "calibrate", "tag_coupling",
           "load_readings", "localize", "readings_dtype", "simulate"]

# The readings CSV's columns (io/readings_csv.h), in file order.
READINGS_COLUMNS = ("time", "posx", "posy", "posz", "q1", "q2", "q3", "q4", "name", "dist", "phase", "rssi",
                    "antenna", "frequency_hz", "channel")


def readings_dtype(name_chars: int = 1, antenna_chars: int = 1) -> np.dtype:
    """The structured dtype of a readings array: the CSV's columns, strings as fixed-width unicode."""
    fields = []
    for c in READINGS_COLUMNS:
        if c == "name":
            fields.append((c, f"U{max(1, name_chars)}"))
        elif c == "antenna":
            fields.append((c, f"U{max(1, antenna_chars)}"))
        elif c == "channel":
            fields.append((c, "i8"))
        else:
            fields.append((c, "f8"))
    return np.dtype(fields)


def _structured(columns: Mapping[str, Any], names: np.ndarray, antennas: np.ndarray) -> np.ndarray:
    n = len(names)
    out = np.empty(n, dtype=readings_dtype(max((len(s) for s in names), default=1),
                                           max((len(s) for s in antennas), default=1)))
    for c in READINGS_COLUMNS:
        if c == "name":
            out[c] = names
        elif c == "antenna":
            out[c] = antennas
        else:
            out[c] = columns[c]
    return out


_DICT_SOURCE = "<scenario dict>"


class Simulation(dict):
    """The result of :func:`simulate`: a dict antenna name → readings array (the antenna's CSV file).

    Attributes: ``tags`` (structured array name, x, y, z at t = 0: tags.csv), ``channel`` (the channel that
    ran, e.g. 'single-bounce' when ``channel: auto`` picked it), ``duration_s``, ``seed``, ``report`` (lines
    ``simulate`` prints about the channel choice), ``ticks`` and ``attempts`` per antenna.
    """

    tags: np.ndarray
    channel: str
    duration_s: float
    seed: int
    report: List[str]
    ticks: Dict[str, int]
    attempts: Dict[str, int]

    def truth(self) -> Dict[str, np.ndarray]:
        """Tag name → position at t = 0, the form ``localize(truth=...)`` takes."""
        return {str(t["name"]): np.array([t["x"], t["y"], t["z"]]) for t in self.tags}


def simulate(scenario: Union[str, os.PathLike, Mapping[str, Any]], *, seed: Optional[int] = None,
             channel: Optional[str] = None, model: Optional[str] = None, duration_s: Optional[float] = None,
             threads: int = 0) -> Simulation:
    """Runs a scenario as ``rfidray simulate`` does and returns the readings it would write.

    ``scenario`` is a scenario file (YAML) or the same content as a dict (relative mesh paths then resolve
    against the current directory). ``seed``, ``channel``, ``model`` ('paper' | 'physical', every antenna) and
    ``duration_s`` override the scenario as the command's flags do. The readings are identical to the CSV
    files for the same seed, at any thread count. Raises InputError (a ValueError) naming file, line, field.
    """
    if isinstance(scenario, Mapping):
        # JSON is YAML: the scenario reader checks every key of the dict as it checks a file.
        text = json.dumps(scenario, indent=1, default=_jsonable)
        try:
            raw = _simulate(None, text, _DICT_SOURCE, seed, channel, model, duration_s, threads)
        except InputError as e:  # a line of the JSON text means nothing to the caller: the field says where
            raise InputError(re.sub(r"^" + re.escape(_DICT_SOURCE) + r":\d+: ", "scenario dict: ", str(e))) from None
    else:
        raw = _simulate(os.fspath(scenario), None, "", seed, channel, model, duration_s, threads)
    tag_names = np.array([t[0] for t in raw["tags"]] or [""])
    result = Simulation()
    result.ticks, result.attempts = {}, {}
    for name, columns, ticks, attempts in raw["antennas"]:
        names = tag_names[np.asarray(columns["tag_index"], dtype=np.intp)]
        result[name] = _structured(columns, names, np.full(len(names), name))
        result.ticks[name] = ticks
        result.attempts[name] = attempts
    tags = np.empty(len(raw["tags"]), dtype=[("name", f"U{max((len(t[0]) for t in raw['tags']), default=1)}"),
                                             ("x", "f8"), ("y", "f8"), ("z", "f8")])
    for i, t in enumerate(raw["tags"]):
        tags[i] = t
    result.tags = tags
    result.channel = raw["channel"]
    result.duration_s = raw["duration_s"]
    result.seed = raw["seed"]
    result.report = list(raw["report"])
    return result


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise InputError(f"scenario dict: cannot use a value of type {type(value).__name__}")


def load_readings(csv: Union[str, os.PathLike]) -> np.ndarray:
    """Reads a readings CSV (``rfidray simulate`` or ``rfidray import``) into a structured array with the
    file's columns (``readings_dtype``); a missing ``antenna`` column reads as '', ``frequency_hz`` as 0 and
    ``channel`` as -1. Errors name ``FILE:LINE: column 'NAME'``."""
    columns = _load_readings(os.fspath(csv))
    return _structured(columns, np.array(columns["name"], dtype=str), np.array(columns["antenna"], dtype=str))


ReadingsLike = Union[str, os.PathLike, np.ndarray, Mapping[str, np.ndarray], Sequence[Any]]


def _reading_files(readings: ReadingsLike) -> List[Dict[str, Any]]:
    if isinstance(readings, (str, os.PathLike)):
        return [_load_readings(os.fspath(readings))]
    if isinstance(readings, np.ndarray):
        if readings.dtype.names is None:
            raise InputError("readings: a structured array with the readings CSV's columns is needed "
                             "(load_readings, simulate)")
        return [{c: (readings[c].tolist() if c in ("name", "antenna") else readings[c])
                 for c in readings.dtype.names}]
    if isinstance(readings, Mapping):  # simulate(): one file per antenna, in the scenario's order
        readings = list(readings.values())
    files: List[Dict[str, Any]] = []
    for item in readings:
        files.extend(_reading_files(item))
    return files


def localize(readings: ReadingsLike, *, method: str = "all",
             truth: Union[None, str, os.PathLike, Mapping[str, Iterable[float]], np.ndarray] = None,
             height_known: bool = False, mirror_prior: str = "none", frequency_hz: float = 865.7e6,
             max_range_m: float = 10.0, stride_m: float = 0.10,
             antenna_file: Union[None, str, os.PathLike] = None, fold_pi: bool = False,
             max_residual_rad: float = 0.25, max_uncertainty_m: float = 0.15,
             systematic_phase_rad: Optional[float] = None,
             scenario: Union[None, str, os.PathLike] = None, channel: Optional[str] = None,
             tag_spacing_m: Optional[float] = None) -> List[Dict[str, Any]]:
    """Locates every tag as ``rfidray localize`` does.

    ``readings``: a CSV path, a readings array, a :class:`Simulation`, or a list of these (one phase history
    per file, antenna and carrier). ``method``: 'hyperbolic' | 'nlls' | 'sar' | 'all'. ``truth``: a tags CSV,
    a dict name → (x, y, z) or a tags array (``Simulation.tags``); it adds ``error_m`` and is needed by
    ``height_known`` and ``mirror_prior='truth'``. ``systematic_phase_rad``: None takes the command's default
    (0.1 rad with ``antenna_file``, 0.2 without; with an ``antenna_file`` that measured its allowance, that one,
    of the band of ``tag_spacing_m`` — the tags' spacing as laid out, ``--tag-spacing-m`` — when given and
    measured), reported per result as ``systematic_rad``. ``max_residual_rad`` and ``max_uncertainty_m``: the gates of
    status 'ok' (``--max-residual-rad``, ``--max-uncertainty-m``). ``scenario`` (a scenario file) and ``channel`` (a level): the
    known scene whose extra paths bound the bias (``localize --scenario --channel``; README "Known scene"),
    reported as ``multipath_phase_rad``. Returns one dict per (tag, method) with the keys of
    ``localize --json``: name, method, status ('ok' | 'uncertain' | 'failed'), reason, detail, x, y, z, error_m,
    uncertainty_m (95 % radius), residual_rad, systematic_rad, multipath_phase_rad, mirror_resolved_by, reads; None where the JSON
    has null. 'uncertain': a position and its radius that do not meet the gates (the reason says which);
    'failed': no position.
    """
    return _localize(_reading_files(readings), _truth_arg(truth), method, height_known, mirror_prior, frequency_hz,
                     max_range_m, stride_m, None if antenna_file is None else os.fspath(antenna_file), fold_pi,
                     max_residual_rad, max_uncertainty_m, systematic_phase_rad, None if scenario is None else os.fspath(scenario), channel,
                     tag_spacing_m)


TruthLike = Union[str, os.PathLike, Mapping[str, Iterable[float]], np.ndarray]


def _truth_arg(truth: Optional[TruthLike]) -> Any:
    if isinstance(truth, np.ndarray):
        return {str(t["name"]): (float(t["x"]), float(t["y"]), float(t["z"])) for t in truth}
    if isinstance(truth, os.PathLike):
        return os.fspath(truth)
    if truth is not None and not isinstance(truth, str):
        return {str(k): [float(x) for x in v] for k, v in truth.items()}
    return truth


def calibrate(references: Sequence[Any], *, antenna: Optional[str] = None, height_known: bool = False,
              fold_pi: bool = False, output: Union[None, str, os.PathLike] = None) -> Dict[str, Any]:
    """Fits an antenna calibration from reference tags at known positions, as ``rfidray calibrate``.

    ``references``: (readings, truth) pairs, one per run — readings as ``localize`` takes them (a CSV path, a
    readings array, a :class:`Simulation`, or a list of these), truth a tags CSV, a dict name → (x, y, z) or a
    tags array (``Simulation.tags``); tags the truth does not know are skipped. ``antenna``: the one to
    calibrate (default: the only one that read a reference). ``height_known`` and ``fold_pi`` as the command's
    options. ``output``: also write the antenna file there (``localize(antenna_file=…)``, ``simulate``'s
    ``antenna_file:``). Returns the keys of ``calibrate --json`` (without ``output``) with NumPy arrays;
    ``geometry_covariance`` is 8 × 8 over dx, dy, dz (m), az, el, az2, az_el, el2 (rad).
    """
    pairs = []
    for item in references:
        if not isinstance(item, (tuple, list)) or len(item) != 2:
            raise InputError("references: each item must be a (readings, truth) pair")
        pairs.append((_reading_files(item[0]), _truth_arg(item[1])))
    return _calibrate(pairs, antenna or "", height_known, fold_pi, None if output is None else os.fspath(output))

