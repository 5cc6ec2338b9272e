"""A tag a few millimetres in front of a metal plate (issue #33's d = λ/100), against every rfidray level: the
graded-mesh FDTD of fdtd_openems.py at two mesh scales, its λ/8 observers checked against meep's converged case
(b) (bench/results/fullwave/plate_front.csv), and the table written to OUT/plate_front_near.{md,csv}.

    python3 bench/fullwave/plate_near.py --rfidray build/rfidray -o bench/results/fullwave [--scales 2,1]

Each openEMS run is cached in OUT/fdtd/plate_front_near_openems_sSCALE.json (delete it to run again); two runs per
scale (with the plate, without it), ~1.5 min each at scale 2 and ~7 min at scale 1 on 2 cores. The reference is
the finest scale; its own error is stated as the change from the next scale (the grid's first-order convergence
near a sheet would make the finest about that far from the limit).
"""
from __future__ import annotations

import argparse
import cmath
import csv
import json
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cases  # noqa: E402
import fdtd_openems  # noqa: E402
import rfidray_link  # noqa: E402
from geometry import WAVELENGTH_M  # noqa: E402
from run import atomic_write  # noqa: E402
from validity_table import write_csv  # noqa: E402


def openems_ratio(case, scale: float, out_dir: str, log) -> dict:
    path = os.path.join(out_dir, "fdtd", f"{case.name}_openems_s{scale:g}.json")
    labels = [o.label for o in case.observers]
    if os.path.exists(path):
        with open(path) as f:
            d = json.load(f)
        if d["labels"] == labels:
            d["ratio"] = np.array(d["ratio_re"]) + 1j * np.array(d["ratio_im"])
            return d
    with tempfile.TemporaryDirectory() as scratch:
        r = fdtd_openems.ratio(case, scale, WAVELENGTH_M / 100, scratch, log=log)
    facts = {k: {kk: vv for kk, vv in r[k].items() if kk not in ("fields", "fields_by_cut")} for k in ("plate", "free")}
    d = {"labels": labels, "scale": scale, "ratio_re": r["ratio"].real.tolist(), "ratio_im": r["ratio"].imag.tolist(),
         "truncation": r["truncation"].tolist(),
         "runs": facts, "date": time.strftime("%Y-%m-%d")}
    with open(path + ".tmp", "w") as f:
        json.dump(d, f, indent=1)
    os.replace(path + ".tmp", path)
    d["ratio"] = r["ratio"]
    return d


def meep_reference(out_dir: str) -> dict:
    """case (b)'s converged meep field per observer label (|E/E0|, arg), conjugated there already (rfidray's
    convention), from plate_front.csv."""
    out = {}
    path = os.path.join(out_dir, "plate_front.csv")
    if os.path.exists(path):
        with open(path) as f:
            for row in csv.DictReader(f):
                out[row["observer"]] = cmath.rect(float(row["fdtd_abs"]), float(row["fdtd_arg_rad"]))
    return out


def fmt(z: complex) -> str:
    return f"{abs(z):.3f}∠{cmath.phase(z):+.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rfidray", required=True)
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--scales", default="2,1", help="mesh scales, coarsest first (the last is the reference)")
    a = ap.parse_args()
    log = lambda m: print(m, file=sys.stderr, flush=True)  # noqa: E731
    case = cases.CASES["plate_front_near"]()
    scales = [float(s) for s in a.scales.split(",")]
    runs = [openems_ratio(case, s, a.out, log) for s in scales]
    ref = runs[-1]["ratio"]
    spread = np.abs(runs[-1]["ratio"] - runs[-2]["ratio"]) if len(runs) > 1 else np.full(len(ref), np.nan)
    with tempfile.TemporaryDirectory() as scratch:
        levels = rfidray_link.all_levels(a.rfidray, case, scratch)
    meep = meep_reference(a.out)
    rows = []
    for i, o in enumerate(case.observers):
        # Case (b)'s observers with the same label stand 4 mm away (on x = 0 and z = 0, where meep mirrors).
        meep_value = meep.get(o.label)
        row = {"observer": o.label, "x_m": o.position[0], "y_m": o.position[1], "z_m": o.position[2],
               "d_m": -o.position[1], "rho_m": o.rho_m, "region": o.region,
               "fdtd_abs": abs(ref[i]), "fdtd_arg_rad": cmath.phase(ref[i]), "reference_spread": spread[i],
               "record_spread": runs[-1]["truncation"][i]}
        for run in runs:
            row[f"openems_s{run['scale']:g}_re"] = run["ratio"][i].real
            row[f"openems_s{run['scale']:g}_im"] = run["ratio"][i].imag
        row["meep_converged"] = fmt(meep_value) if meep_value is not None else ""
        row["meep_difference"] = abs(meep_value - ref[i]) if meep_value is not None else float("nan")
        for lv in rfidray_link.LEVELS:
            h = levels[lv][i]
            row[f"{lv}_abs"], row[f"{lv}_arg_rad"], row[f"{lv}_error"] = abs(h), cmath.phase(h), abs(h - ref[i])
        rows.append(row)
    os.makedirs(a.out, exist_ok=True)
    write_csv(rows, os.path.join(a.out, "plate_front_near.csv"))
    lines = [f"# {case.name}", "", case.description + ".", "",
             "Graded-mesh FDTD (openEMS 0.0.35, `bench/fullwave/fdtd_openems.py`), E/E_free at 866 MHz; reference = "
             f"mesh scale {scales[-1]:g}, spread = its change from scale {scales[-2]:g}"
             if len(scales) > 1 else "", ""]
    cuts = "/".join(f"{c * 1e9:g}" for c in fdtd_openems.RECORD_CUTS_S)
    for run in runs:
        p, fr = run["runs"]["plate"], run["runs"]["free"]
        lines.append(f"- scale {run['scale']:g}: {p['cells'] / 1e6:.2f} M cells, {p['steps']} probe samples; with the "
                     f"plate {p['seconds']:.0f} s, free {fr['seconds']:.0f} s; the ratio moves by ≤ "
                     f"{max(run['truncation']):.4f} between the records cut at {cuts} ns ({run['date']})")
    lines += ["", "| observer | d | region | FDTD (openEMS) | mesh spread | record spread | meep (converged, case (b)) | " +
              " | ".join(f"`{lv}`" for lv in rfidray_link.LEVELS) + " |",
              "|---|---|---|---|---|---|---|" + "---|" * len(rfidray_link.LEVELS)]
    for r in rows:
        lines.append(f"| {r['observer']} | {r['d_m'] * 1000:.1f} mm | {r['region']} | "
                     f"{fmt(cmath.rect(r['fdtd_abs'], r['fdtd_arg_rad']))} | "
                     f"{r['reference_spread']:.3f} | {r['record_spread']:.3f} | "
                     + (f"{r['meep_converged']} (differs by {r['meep_difference']:.3f})" if r["meep_converged"] else "—")
                     + " | " + " | ".join(f"{r[lv + '_error']:.3f}" for lv in rfidray_link.LEVELS) + " |")
    lines += ["", "Level columns: |h/h_ideal − E/E_free|, a fraction of the free-space field. Mesh spread: the "
              "reference's change from the next coarser mesh; record spread: how far it moves between the records cut "
              f"at {cuts} ns. The meep column is case (b)'s converged field at the observer of the same label, 4 mm "
              "away (on the planes x = 0 and z = 0)."]
    atomic_write(os.path.join(a.out, "plate_front_near.md"), "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
