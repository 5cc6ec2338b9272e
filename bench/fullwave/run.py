#!/usr/bin/python3
"""Full-wave reference harness (issue #33): FDTD (meep) against every rfidray channel level, one case per call.

  /usr/bin/python3 bench/fullwave/run.py --rfidray build/rfidray --case sheet_edge_soft \
      [--resolution 60 --resolution 90] [--pml 0.2 --pml 0.35] [--thickness 0.02] -o bench/results/fullwave
  /usr/bin/python3 bench/fullwave/run.py --halfplane-2d [--resolution 60 ...] -o bench/results/fullwave
  /usr/bin/python3 bench/fullwave/run.py --summary -o bench/results/fullwave
  /usr/bin/python3 bench/fullwave/run.py --validity --rfidray build/rfidray -o bench/results/fullwave
  /usr/bin/python3 bench/fullwave/run.py --all --rfidray build/rfidray -o bench/results/fullwave

Per case it writes CASE.md and CASE.csv: for every observer the FDTD's E/E_free at the finest resolution, the
reference's own error (resolution spread, PML and sheet-thickness changes) and for every level h/h_ideal and the
error |h/h_ideal − E/E_free| (a fraction of the free-space field). FDTD runs are cached in OUT/fdtd/*.json.
--summary builds sheet_edge.md, validity_bands.csv and error_vs_krho.png from the sheet cases' CSVs; --validity
checks `link --json`'s validity verdicts against every stored observer (validity_table.py). --all does all of it:
every case as its stored reference was made (cases.RUNS; cached FDTD runs are reused, so with the cache it takes
minutes), then --summary, the other cases' table (cases_summary.py) and --validity (against --before if given).
Exit 2 on bad input (unknown case, missing binary), with the reason.
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

import cases  # noqa: E402
from geometry import K_RAD_M  # noqa: E402


def geometry_words(case) -> str:
    """What the case's objects are in the FDTD, for the table's header: zero-thickness sheets, slabs (a sheet with
    Box.slab_m, which the FDTD builds that thick), closed boxes."""
    kinds = []
    for box in case.boxes:
        kind = ("closed boxes" if box.thin_axis is None else
                f"{box.slab_m * 100:g} cm slabs" if box.slab_m > 0.0 else "zero-thickness sheets")
        if kind not in kinds:
            kinds.append(kind)
    return " and ".join(kinds)


def log(msg):
    print(msg, flush=True)


def fail(msg):
    print(f"run.py: error: {msg}", file=sys.stderr)
    sys.exit(2)


def atomic_write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def run_case(a):
    import rfidray_link
    import store
    case = cases.CASES[a.case]()
    case.check()
    res = sorted(a.resolution or [60.0])
    pml = a.pml or [0.2]
    t0 = time.time()
    runs = {r: store.fdtd_ratio(case, a.out, r, pml[0], 0.0, rerun=a.rerun, log=log) for r in res}
    fine = runs[res[-1]]
    # The reference: first-order Richardson extrapolation of the two finest runs (a zero-thickness sheet converges
    # at first order near its edge; richardson_2d.py checks it against the exact 2-D half-plane), or the finest.
    if len(res) > 1 and not a.no_richardson:
        # Order p: 1 near a sheet's edge, 2 for a case of averaged dielectric blocks and no sheets (Case).
        coarse, r = runs[res[-2]], (res[-1] / res[-2]) ** case.convergence_order
        ref_meep = fine["ratio"] + (fine["ratio"] - coarse["ratio"]) / (r - 1.0)
        spread = np.abs(fine["ratio"] - coarse["ratio"])
        estimate = spread / (r - 1.0)  # the finer run's own error at that order
    else:
        ref_meep = fine["ratio"]
        spread = estimate = np.full(len(fine["ratio"]), np.nan)
    ref = np.conj(ref_meep)  # meep e^{-iωt} → rfidray e^{+jωt}
    # The PML and sheet-thickness checks at the coarsest resolution (their effect, not the grid's).
    pml_diff = np.full(len(ref), np.nan)
    if len(pml) > 1:
        other = store.fdtd_ratio(case, a.out, res[0], pml[1], 0.0, rerun=a.rerun, log=log)
        pml_diff = np.abs(other["ratio"] - runs[res[0]]["ratio"])
    thick_diff = np.full(len(ref), np.nan)
    if a.thickness:
        other = store.fdtd_ratio(case, a.out, res[0], pml[0], a.thickness, rerun=a.rerun, log=log)
        thick_diff = np.abs(other["ratio"] - runs[res[0]]["ratio"])
    fdtd_s = time.time() - t0
    if not os.path.exists(a.rfidray):
        fail(f"--rfidray {a.rfidray}: no such file (build the target rfidray first)")
    t1 = time.time()
    levels = rfidray_link.all_levels(a.rfidray, case, a.scratch)
    rt_s = time.time() - t1
    names = list(rfidray_link.LEVELS)
    rows = []
    for i, o in enumerate(case.observers):
        row = {"observer": o.label, "x_m": o.position[0], "y_m": o.position[1], "z_m": o.position[2],
               "rho_m": o.rho_m, "phi_deg": o.phi_deg, "krho": o.krho, "region": o.region,
               "fdtd_abs": abs(ref[i]), "fdtd_arg_rad": float(np.angle(ref[i])),
               "reference_spread": spread[i], "finest_error_estimate": estimate[i], "pml_change": pml_diff[i], "thickness_change": thick_diff[i],
               "steady_state": fine["steady"][i]}
        for r in res:
            row[f"fdtd_r{r:g}_re"] = float(np.conj(runs[r]["ratio"][i]).real)
            row[f"fdtd_r{r:g}_im"] = float(np.conj(runs[r]["ratio"][i]).imag)
        for lv in names:
            h = levels[lv][i]
            row[f"{lv}_abs"] = abs(h)
            row[f"{lv}_arg_rad"] = float(np.angle(h))
            row[f"{lv}_error"] = abs(h - ref[i])
        row["full_isotropic_error"] = abs(levels["full:isotropic"][i] - ref[i])
        rows.append(row)
    os.makedirs(a.out, exist_ok=True)
    csv_path = os.path.join(a.out, case.name + ".csv")
    with open(csv_path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    os.replace(csv_path + ".tmp", csv_path)
    md = [f"# {case.name}", "", case.description + ".", "",
          f"FDTD: meep {', '.join(f'{r:g}' for r in res)} px/m, PML {pml[0]:g} m, {geometry_words(case)}; reference = "
          f"{('order-%d Richardson extrapolation of the two finest' % case.convergence_order) if len(res) > 1 and not a.no_richardson else f'{res[-1]:g} px/m'}. Errors are |h/h_ideal − E/E_free|, a fraction of the free-space field. "
          f"Spread = |E({res[-1]:g}) − E({res[-2] if len(res) > 1 else res[-1]:g})|/E_free; PML: {pml} m; "
          f"thickness check: {f'{a.thickness:g} m' if a.thickness else 'not run'}.", "",
          "| observer | kρ | region | FDTD E/E₀ | spread | " + " | ".join(names) + " |",
          "|---|---|---|---|---|" + "---|" * len(names)]
    for r in rows:
        md.append(f"| {r['observer']} | {r['krho']:.2f} | {r['region']} | {r['fdtd_abs']:.3f}∠{r['fdtd_arg_rad']:+.2f} | "
                  f"{r['reference_spread']:.3f} | " + " | ".join(f"{r[lv + '_error']:.3f}" for lv in names) + " |")
    md += ["", "Per region: error median / max of each level over all its observers; where some are not converged "
           "(spread > 0.05 of the free-space field) a second row gives the converged ones only.", "",
           "| region | observers | n | spread median / max | " + " | ".join(names) + " |",
           "|---|---|---|---|" + "---|" * len(names)]
    for region in dict.fromkeys(r["region"] for r in rows):
        sel_all = [r for r in rows if r["region"] == region]
        conv = [r for r in sel_all if r["reference_spread"] <= 0.05]
        groups = [("all, converged" if len(conv) == len(sel_all) else "all", sel_all)]
        if len(conv) != len(sel_all):
            groups.append(("converged only", conv))
        for which, sel in groups:
            if not sel:
                md.append(f"| {region} | {which} | 0 | | " + " | ".join("" for _ in names) + " |")
                continue
            sp = np.array([r["reference_spread"] for r in sel])
            md.append(f"| {region} | {which} | {len(sel)} | {np.median(sp):.3f} / {np.max(sp):.3f} | " + " | ".join(
                f"{np.median([r[lv + '_error'] for r in sel]):.3f} / {np.max([r[lv + '_error'] for r in sel]):.3f}"
                for lv in names) + " |")
    md += ["", f"FDTD {fdtd_s:.0f} s (cached runs count 0), rfidray {rt_s:.1f} s for {len(rows) * len(names)} links."]
    atomic_write(os.path.join(a.out, case.name + ".md"), "\n".join(md) + "\n")
    log(f"wrote {csv_path} and {case.name}.md; full error median {np.median([r['full_error'] for r in rows]):.3f}")


def run_halfplane_2d(a):
    import halfplane2d
    res = sorted(a.resolution or [60.0, 120.0, 240.0])
    obs, meta = [], []
    for rho in cases.SHEET_RHOS_M:
        for ang in cases.SHEET_ANGLES_DEG:
            obs.append((rho * math.cos(math.radians(ang)), rho * math.sin(math.radians(ang))))
            meta.append((rho, ang))
    src = (cases.SOURCE_RANGE_M * math.cos(math.radians(cases.SOURCE_PHI_DEG)),
           cases.SOURCE_RANGE_M * math.sin(math.radians(cases.SOURCE_PHI_DEG)))
    rows = []
    md = ["# 2-D check: line source beside a PEC half-plane, meep vs the exact eigenfunction series", "",
          "Source 1 m from the edge at φ' = 60°; observers as in the sheet case. Error = |E/E₀(FDTD) − E/E₀(exact)|.",
          "Zero-thickness sheet (one grid row of tangential E = 0).", ""]
    for pol in ("soft", "hard"):
        hard = pol == "hard"
        exact = np.array([halfplane2d.exact_ratio(r, math.radians(p), cases.SOURCE_RANGE_M,
                                                  math.radians(cases.SOURCE_PHI_DEG), hard) for r, p in meta])
        fd = {}
        for r in res:
            t0 = time.time()
            fd[r] = np.conj(halfplane2d.fdtd_ratio(obs, src, hard, r, log=log))
            log(f"2-D {pol} {r:g} px/m: {time.time() - t0:.1f} s")
        md += [f"## {pol}", "", "| ρ (kρ) | " + " | ".join(f"{r:g} px/m median / max" for r in res) +
               f" | spread {res[-1]:g} vs {res[-2]:g}: median / max |", "|---|" + "---|" * (len(res) + 1)]
        for rho in cases.SHEET_RHOS_M:
            idx = [i for i, (rr, _) in enumerate(meta) if rr == rho]
            errs = [np.abs(fd[r][idx] - exact[idx]) for r in res]
            sp = np.abs(fd[res[-1]][idx] - fd[res[-2]][idx])
            md.append(f"| {rho * 100:g} cm ({K_RAD_M * rho:.2f}) | " +
                      " | ".join(f"{np.median(e):.3f} / {np.max(e):.3f}" for e in errs) +
                      f" | {np.median(sp):.3f} / {np.max(sp):.3f} |")
        md.append("")
        for i, (rho, ang) in enumerate(meta):
            row = {"polarization": pol, "rho_m": rho, "phi_deg": ang, "krho": K_RAD_M * rho,
                   "exact_re": exact[i].real, "exact_im": exact[i].imag}
            for r in res:
                row[f"error_r{r:g}"] = abs(fd[r][i] - exact[i])
            rows.append(row)
    os.makedirs(a.out, exist_ok=True)
    p = os.path.join(a.out, "halfplane_2d.csv")
    with open(p + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    os.replace(p + ".tmp", p)
    atomic_write(os.path.join(a.out, "halfplane_2d.md"), "\n".join(md) + "\n")
    log("wrote halfplane_2d.md / .csv")


def run_all(a):
    """Every case of cases.RUNS with its own resolutions, PML and thickness checks; then the tables."""
    import copy
    import cases_summary
    import summary
    import validity_table
    if not a.rfidray or not os.path.isfile(a.rfidray):
        fail(f"--all needs --rfidray BINARY (got {a.rfidray!r}: no such file)")
    if a.before and not os.path.isfile(a.before):
        fail(f"--before {a.before}: no such file")
    t0 = time.time()
    for name, (resolutions, pmls, thickness) in cases.RUNS.items():
        one = copy.copy(a)
        one.case, one.resolution, one.pml, one.thickness = name, [float(r) for r in resolutions], list(pmls), thickness
        log(f"case {name}: {', '.join(f'{r:g}' for r in resolutions)} px/m")
        run_case(one)
    summary.write(a.out, log)
    cases_summary.write(a.out, log)
    try:
        validity_table.write(a.rfidray, a.out, a.scratch, a.before, log=log, reuse=False)
    except ValueError as e:
        fail(str(e))
    log(f"all cases, tables and validity in {time.time() - t0:.0f} s")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rfidray", help="path of the rfidray binary")
    ap.add_argument("--case", help="one of: " + ", ".join(cases.CASES))
    ap.add_argument("--resolution", type=float, action="append", help="FDTD px/m (repeat; finest = reference)")
    ap.add_argument("--pml", type=float, action="append", help="PML thickness m (first = used; second = check)")
    ap.add_argument("--thickness", type=float, default=0.0, help="also run sheets this thick (m) at the coarsest resolution")
    ap.add_argument("--halfplane-2d", action="store_true", help="the 2-D FDTD vs exact half-plane study")
    ap.add_argument("--all", action="store_true",
                    help="every case as its reference was made (cases.RUNS), then --summary, the other cases' table "
                         "and --validity")
    ap.add_argument("--summary", action="store_true", help="bands, CSV and chart from the sheet cases' CSVs")
    ap.add_argument("--validity", action="store_true",
                    help="validity's verdicts against every stored observer (validity.md/.csv; no FDTD run)")
    ap.add_argument("--before", help="with --validity: an earlier validity.csv to compare with")
    ap.add_argument("--reuse", action="store_true", help="with --validity: re-render from OUT/validity.csv")
    ap.add_argument("--no-richardson", action="store_true", help="reference = the finest run, not the extrapolation")
    ap.add_argument("--rerun", action="store_true", help="ignore cached FDTD runs")
    ap.add_argument("--scratch", default="/tmp/rfidray_fullwave", help="scratch directory for OBJ scenes")
    ap.add_argument("-o", "--out", required=True, help="output directory")
    a = ap.parse_args()
    if a.resolution and any(not (10 <= r <= 2000) for r in a.resolution):
        fail("--resolution: px/m must be in [10, 2000]")
    if a.pml and any(not (0.05 <= p <= 2.0) for p in a.pml):
        fail("--pml: thickness must be in [0.05, 2] m")
    if a.halfplane_2d:
        return run_halfplane_2d(a)
    if a.all:
        return run_all(a)
    if a.summary:
        import summary
        return summary.write(a.out, log)
    if a.validity:
        if not a.reuse and (not a.rfidray or not os.path.isfile(a.rfidray)):
            fail(f"--validity needs --rfidray BINARY (got {a.rfidray!r}: no such file)")
        if a.reuse and not os.path.isfile(os.path.join(a.out, "validity.csv")):
            fail(f"--reuse: no validity.csv in {a.out} (run --validity --rfidray BINARY first)")
        if a.before and not os.path.isfile(a.before):
            fail(f"--before {a.before}: no such file")
        import validity_table
        try:
            return validity_table.write(a.rfidray, a.out, a.scratch, a.before, log=log, reuse=a.reuse)
        except ValueError as e:
            fail(str(e))
    if not a.case or a.case not in cases.CASES:
        fail(f"--case: expected one of {', '.join(cases.CASES)} (got {a.case!r})")
    if not a.rfidray:
        fail("--rfidray BINARY is required with --case")
    if not os.path.isfile(a.rfidray):
        fail(f"--rfidray {a.rfidray}: no such file (build the target rfidray first)")
    run_case(a)


if __name__ == "__main__":
    main()
