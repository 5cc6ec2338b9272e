"""FDTD results on disk: one JSON per (case, resolution, PML, sheet thickness), so a table can be rebuilt, or a
level re-checked, without re-running the FDTD. Each file records the run's grid, time and steady-state residual."""
from __future__ import annotations

import json
import os

import numpy as np

import fdtd
from geometry import Case


def key(case: Case, resolution: float, dpml_m: float, sheet_thickness_m: float) -> str:
    return f"{case.name}_r{resolution:g}_pml{dpml_m:g}_t{sheet_thickness_m:g}"


def fdtd_ratio(case: Case, directory: str, resolution: float, dpml_m: float = 0.2, sheet_thickness_m: float = 0.0,
               settle_periods: float = 12.0, rerun: bool = False, log=print) -> dict:
    """E/E_free per observer (meep convention), cached in DIRECTORY/fdtd/KEY.json."""
    path = os.path.join(directory, "fdtd", key(case, resolution, dpml_m, sheet_thickness_m) + ".json")
    labels = [o.label for o in case.observers]
    if os.path.exists(path) and not rerun:
        with open(path) as f:
            d = json.load(f)
        if d["labels"] == labels and d["settle_periods"] == settle_periods:
            d["ratio"] = np.array(d["ratio_re"]) + 1j * np.array(d["ratio_im"])
            d["steady"] = np.array(d["steady"])
            return d
    # The free-space run of a grid serves every geometry variant on it (sheet thickness): cached on its own.
    free_path = os.path.join(directory, "fdtd", f"{case.name}_r{resolution:g}_pml{dpml_m:g}_free.npz")
    free = None
    if os.path.exists(free_path) and not rerun:
        z = np.load(free_path)
        if z["fields"].shape == (len(labels),) and float(z["settle_periods"]) == settle_periods:
            free = {"fields": z["fields"], "steady": z["steady"], "seconds": 0.0}
    if free is None:
        free = fdtd.run(case, resolution, dpml_m, False, 0.0, settle_periods, log)
        os.makedirs(os.path.dirname(free_path), exist_ok=True)
        np.savez(free_path + ".tmp.npz", fields=free["fields"], steady=free["steady"], settle_periods=settle_periods)
        os.replace(free_path + ".tmp.npz", free_path)
    r = fdtd.ratio(case, resolution, dpml_m, sheet_thickness_m, settle_periods, log, free=free)
    d = {"case": case.name, "labels": labels, "resolution": resolution, "dpml_m": dpml_m,
         "sheet_thickness_m": sheet_thickness_m, "settle_periods": settle_periods,
         "ratio_re": r["ratio"].real.tolist(), "ratio_im": r["ratio"].imag.tolist(),
         "steady": r["steady"].tolist(), "seconds": r["seconds"], "cells": r["cells"]}
    os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(d, f, indent=1)
    os.replace(tmp, path)  # never a half-written file
    d["ratio"], d["steady"] = r["ratio"], r["steady"]
    return d
