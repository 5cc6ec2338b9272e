"""The validity summary of the sheet-edge cases: per band of kρ (distance to the edge × k) the median and max error
of `full` and of `single-bounce` and the reference's own spread; sheet_edge.md, validity_bands.csv (both
polarizations pooled) and error_vs_krho.png."""
from __future__ import annotations

import csv
import os

import numpy as np

BANDS = (1.1, 2.2, 4.4, 9.0)
CASES = ("sheet_edge_soft", "sheet_edge_hard", "sheet_edge_soft_tall", "sheet_edge_hard_tall", "wedge_edge_soft",
         "wedge_edge_hard")
LEVELS = ("los", "single-bounce", "double-bounce", "full-selective", "full")


def read_rows(path):
    """The rows of a results CSV, numbers as floats (the harness's case tables)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k, v in r.items():
            try:
                r[k] = float(v)
            except ValueError:
                pass
    return rows


def _band_rows(rows):
    out = []
    lo = 0.0
    for hi in BANDS:
        sel = [r for r in rows if lo < r["krho"] <= hi]
        lo = hi
        if not sel:
            continue
        f = np.array([r["full_error"] for r in sel])
        s = np.array([r["single-bounce_error"] for r in sel])
        sp = np.array([r["reference_spread"] for r in sel])
        worst = sel[int(np.argmax(f))]
        out.append({"krho_max": hi, "full_median": np.median(f), "full_max": np.max(f),
                    "single_bounce_median": np.median(s), "single_bounce_max": np.max(s),
                    "reference_spread_median": np.median(sp), "n_observers": len(sel),
                    "_spread_max": np.max(sp), "_worst": f"{worst['phi_deg']:.0f}° ({worst['region']})",
                    "_sb_over_spread": int(np.sum(s > 2 * sp)), "_full_within_01": int(np.sum(f <= 0.1))})
    return out


def write(out_dir, log=print):
    data = {c: read_rows(os.path.join(out_dir, c + ".csv")) for c in CASES if os.path.exists(os.path.join(out_dir, c + ".csv"))}
    if not data:
        raise SystemExit(f"summary: no sheet_edge_*.csv in {out_dir} (run --case sheet_edge_soft first)")
    md = ["# Sheet edge: error of each level against the FDTD reference, by kρ", "",
          "Finite PEC sheet 0.9 × 0.8 m (`_tall`: 0.9 × 1.6 m, the same edge; `wedge_`: a PEC box 0.9 × 0.5 × 0.8 m "
          "whose top face is the sheet, a right-angled edge), dipole 1 m from the edge at 60°, observers at ρ = 4, 8, "
          "16, 32 cm (kρ = 0.73, 1.45, 2.90, 5.81), 11 angles each (9 round the wedge). Error = |h/h_ideal − E/E_free|, a fraction of the "
          "free-space field. Spread: |E(finest) − E(next resolution)|/E_free (the reference's own uncertainty).", ""]
    pooled = []
    for c, rows in data.items():
        pooled += rows
        md += [f"## {c}", "", "| kρ ≤ | n | `full` median / max (worst at) | `single-bounce` median / max | "
               "reference spread median / max | `full` ≤ 0.1 |", "|---|---|---|---|---|---|"]
        for b in _band_rows(rows):
            md.append(f"| {b['krho_max']:g} | {b['n_observers']} | {b['full_median']:.3f} / {b['full_max']:.3f} "
                      f"({b['_worst']}) | {b['single_bounce_median']:.3f} / {b['single_bounce_max']:.3f} | "
                      f"{b['reference_spread_median']:.3f} / {b['_spread_max']:.3f} | {b['_full_within_01']}/{b['n_observers']} |")
        md.append("")
    bands = _band_rows(pooled)
    md += ["## Both polarizations, both sheets and the wedge pooled (validity_bands.csv)", "",
           "| kρ ≤ | n | full median | full max | single-bounce median | single-bounce max | spread median |",
           "|---|---|---|---|---|---|---|"]
    for b in bands:
        md.append(f"| {b['krho_max']:g} | {b['n_observers']} | {b['full_median']:.3f} | {b['full_max']:.3f} | "
                  f"{b['single_bounce_median']:.3f} | {b['single_bounce_max']:.3f} | {b['reference_spread_median']:.3f} |")
    cols = ["krho_max", "full_median", "full_max", "single_bounce_median", "single_bounce_max",
            "reference_spread_median", "n_observers"]
    p = os.path.join(out_dir, "validity_bands.csv")
    with open(p + ".tmp", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for b in bands:
            w.writerow([f"{b[c]:.4g}" if isinstance(b[c], float) else b[c] for c in cols])
    os.replace(p + ".tmp", p)
    with open(os.path.join(out_dir, "sheet_edge.md.tmp"), "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(os.path.join(out_dir, "sheet_edge.md.tmp"), os.path.join(out_dir, "sheet_edge.md"))
    _chart(data, os.path.join(out_dir, "error_vs_krho.png"))
    log(f"wrote sheet_edge.md, validity_bands.csv, error_vs_krho.png in {out_dir}")


def _chart(data, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ncol = min(len(data), 2)
    nrow = (len(data) + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(6 * ncol, 4.2 * nrow), sharey=True, squeeze=False)
    for ax, (c, rows) in zip(axes.flat, data.items()):
        krs = sorted({r["krho"] for r in rows})
        sp_med = [np.median([r["reference_spread"] for r in rows if r["krho"] == k]) for k in krs]
        sp_max = [np.max([r["reference_spread"] for r in rows if r["krho"] == k]) for k in krs]
        ax.fill_between(krs, 0, sp_max, color="0.85", label="reference spread (max)")
        ax.fill_between(krs, 0, sp_med, color="0.65", label="reference spread (median)")
        for lv, mk in zip(LEVELS, "os^vD"):
            med = [np.median([r[lv + "_error"] for r in rows if r["krho"] == k]) for k in krs]
            mx = [np.max([r[lv + "_error"] for r in rows if r["krho"] == k]) for k in krs]
            line, = ax.plot(krs, med, marker=mk, label=f"{lv} median")
            ax.plot(krs, mx, marker=mk, ls=":", color=line.get_color(), alpha=0.6)
        ax.set_xscale("log")
        ax.minorticks_off()  # the log axis's minor labels (2×10⁰ …) overlap the kρ ticks
        ax.set_xticks(krs)
        ax.set_xticklabels([f"{k:.2f}" for k in krs])
        ax.set_xlabel("kρ (distance to the edge × k)")
        ax.set_title(c.replace("_", " ") + " (dotted: max over the angles)")
        ax.grid(alpha=0.3)
    for row in axes:
        row[0].set_ylabel("|h/h_ideal − E/E_free|")
    axes[0][0].legend(fontsize=7, loc="upper right")
    fig.suptitle("rfidray levels vs FDTD (meep): PEC sheets 0.9 × 0.8 m and (tall) 0.9 × 1.6 m, a PEC box's edge (wedge), 866 MHz", fontsize=10)
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)
