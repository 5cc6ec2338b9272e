"""The published methods that ship with the AdaRF set, run on the same runs and truth as rfidray (bench/real_data.py).

The set has no licence, so none of its code is in this repository: this module imports it at run time from the
folder given to real_data.py (--adarf), and runs it through the set's own extraction and preprocessing:

    codes/extract_signal_profile.py  read_file, extract_profile   (mean phase per stop and carrier)
    codes/preprocess.py              preprocess                   (drop stops missing a carrier, unwrap)
    codes/hologram.py                Hologram.holo_tagoram        Tagoram (differential augmented hologram)
                                     Hologram.holo_mobitagbot     MobiTagbot (entropy-weighted hologram)
    codes/other_schemes.py           rf_scanner                   RF-Scanner (per-carrier curve fit)
                                     stpp                         STPP (x along the stage only)

Holograms on the grid the set's own scripts use: 100 x 100 cells of 1 cm over x, y in (0, 1] m (the antenna
path at y = 0, stops at x = 0.02 ... 1.00 m as the set's extraction places them). Each method's CPU time is
time.process_time() around its call, per tag.

Shim, stated: other_schemes.stpp uses `np.int`, which NumPy 1.24 removed; `np.int = int` is set before it runs.
"""
import importlib
import math
import os
import statistics
import sys
import time

PEERS = ["Tagoram", "MobiTagbot", "RF-Scanner", "STPP (x only)"]
GRID_CELLS = 100
GRID_STEP_M = 0.01


class PeerCode:
    """The set's modules, imported from its folder."""

    def __init__(self, adarf):
        codes = os.path.join(adarf, "codes")
        if not os.path.isdir(codes):
            raise RuntimeError("%s: no codes/ folder (the AdaRF repository holds it)" % adarf)
        os.environ.setdefault("MPLBACKEND", "Agg")  # hologram.py imports pyplot
        import numpy as np
        if not hasattr(np, "int"):
            np.int = int  # other_schemes.stpp: np.int was removed in NumPy 1.24
        if adarf not in sys.path:
            sys.path.insert(0, os.path.abspath(adarf))
        self.np = np
        self.extract = importlib.import_module("codes.extract_signal_profile")
        self.preprocess = importlib.import_module("codes.preprocess")
        self.hologram = importlib.import_module("codes.hologram")
        self.other = importlib.import_module("codes.other_schemes")
        self.config = importlib.import_module("codes.config")


def _peak(np, holo_map):
    """Hologram map (the set's layout: map[num_x - 1 - c, r] at x = (r + 1) step, y = (c + 1) step) -> (x, y)."""
    i, j = np.unravel_index(int(np.argmax(holo_map)), holo_map.shape)
    c = GRID_CELLS - 1 - i
    return (j + 1) * GRID_STEP_M, (c + 1) * GRID_STEP_M


def run_peers_on_run(code, run_dir, epcs, truth, methods=PEERS, split="test"):
    """One run folder: [{name, method, x, y, error_m, cpu_ms}] for every tag of `epcs` (bytes) with a truth
    {epc str: (x, y)}, on the set's carriers of `split` (FRE_TEST: 8, FRE_TRAIN: 1). A tag the set's
    preprocessing leaves with fewer than 3 stops has no position."""
    np = code.np
    fres = list(code.config.FRE_TEST if split == "test" else code.config.FRE_TRAIN)
    data = code.extract.read_file(run_dir.rstrip("/"))
    profile, xs = code.extract.extract_profile(data, epcs, fres)
    out = []
    devnull = open(os.devnull, "w")
    for k, epc in enumerate(epcs):
        name = epc.decode()
        if name not in truth:
            continue
        tx, ty = truth[name]
        stdout = sys.stdout
        sys.stdout = devnull  # preprocess prints the stops it drops
        try:
            phases, pxs = code.preprocess.preprocess(profile[k, 0], xs, epc)
        finally:
            sys.stdout = stdout
        for m in methods:
            row = {"name": name, "method": m, "x": None, "y": None, "error_m": None, "cpu_ms": None}
            if phases.shape[1] >= 3:
                t0 = time.process_time()
                try:
                    if m in ("Tagoram", "MobiTagbot"):
                        h = code.hologram.Hologram([GRID_CELLS, GRID_CELLS, GRID_STEP_M, GRID_STEP_M], phases, pxs, fres)
                        x, y = _peak(np, h.holo_tagoram() if m == "Tagoram" else h.holo_mobitagbot())
                    elif m == "RF-Scanner":
                        x, y = (float(v) for v in code.other.rf_scanner(phases, pxs, fres))
                    else:
                        x, y = float(code.other.stpp(phases, pxs, fres)), None
                except Exception as e:  # a peer's own failure (e.g. curve_fit not converging) is no position
                    row["failure"] = "%s: %s" % (type(e).__name__, str(e)[:200])
                    x = y = None
                row["cpu_ms"] = 1e3 * (time.process_time() - t0)
                if x is not None:
                    row["x"], row["y"] = x, y
                    row["error_m"] = abs(x - tx) if y is None else math.hypot(x - tx, y - ty)
            out.append(row)
    devnull.close()
    return out


def peer_stats(rows):
    """Per peer: tags, with a position, mean/median/p90/max error (mm), CPU ms per tag."""
    out = {}
    for m in PEERS:
        mine = [r for r in rows if r["method"] == m]
        if not mine:
            continue
        errs = sorted(r["error_m"] for r in mine if r["error_m"] is not None)
        cpu = [r["cpu_ms"] for r in mine if r["cpu_ms"] is not None]
        out[m] = {
            "tags": len(mine), "positioned": len(errs),
            "mean_mm": 1e3 * statistics.fmean(errs) if errs else float("nan"),
            "median_mm": 1e3 * statistics.median(errs) if errs else float("nan"),
            "p90_mm": 1e3 * errs[min(len(errs) - 1, int(math.ceil(0.9 * len(errs))) - 1)] if errs else float("nan"),
            "max_mm": 1e3 * errs[-1] if errs else float("nan"),
            "cpu_ms": statistics.fmean(cpu) if cpu else float("nan"),
        }
    return out
