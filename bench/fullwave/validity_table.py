#!/usr/bin/python3
"""Does `validity` flag the links the FDTD reference finds wrong? A confusion table from the stored observers.

  /usr/bin/python3 bench/fullwave/run.py --validity --rfidray build/rfidray -o bench/results/fullwave \
      [--before bench/results/fullwave/validity_before.csv]

For every observer of every case whose CSV is in OUT (run.py --case CASE wrote it, or plate_near.py for
plate_front_near: the FDTD reference and each
level's error |h/h_ideal − E/E_free|, a fraction of the free-space field) and every level, it calls
`rfidray link --level L --json` for the same link (rfidray_link.link_json: the case's source and polarization,
isotropic patterns) and reads its `validity` object. A link is *flagged* when `level_ok` is false; it is *wrong*
when the measured error exceeds 0.1 of the free-space field. No FDTD is run. Writes OUT/validity.csv (one row per
observer and level: error, reference spread, level_ok, estimated error, reason) and OUT/validity.md (per case and
level: flagged / wrong counts; misses; before/after totals when --before names an earlier validity.csv).
--reuse renders validity.md again from the validity.csv in OUT without calling rfidray. Exit 2 on bad input.
"""
from __future__ import annotations

import csv
import os
import sys
from concurrent.futures import ThreadPoolExecutor

import cases
import rfidray_link
from summary import read_rows

# The meep cases, then the graded-mesh openEMS case (plate_near.py writes its CSV in the same layout).
CASE_ORDER = tuple(cases.RUNS) + ("plate_front_near",)
WRONG = 0.1       # a level is wrong at an observer when its error exceeds this fraction of the free-space field
VERY_WRONG = 0.2  # the goal: no observer this far off left level_ok


def collect(binary: str, out: str, scratch: str, jobs: int = 2) -> list[dict]:
    tasks = []
    scenes = {}
    for name in CASE_ORDER:
        p = os.path.join(out, name + ".csv")
        if not os.path.exists(p):
            continue
        case = cases.CASES[name]()
        rows = {r["observer"]: r for r in read_rows(p)}
        scenes[name] = (case, rfidray_link.write_obj(case, os.path.join(scratch, name + ".obj")),
                        rfidray_link.case_thickness(case))
        for o in case.observers:
            if o.label not in rows:
                raise ValueError(f"{p}: no row for observer {o.label} (rerun run.py --case {name})")
            for lv in rfidray_link.LEVELS:
                tasks.append((name, o, lv, rows[o.label]))
    if not tasks:
        raise ValueError(f"no case CSV ({', '.join(c + '.csv' for c in CASE_ORDER)}) in {out}")

    def one(t):
        name, o, lv, row = t
        case, scene, thickness = scenes[name]
        v = rfidray_link.link_json(binary, scene, case, o.position, lv, thickness)["validity"]
        return {"case": name, "observer": o.label, "region": o.region, "krho": o.krho, "level": lv,
                "error": row[lv + "_error"], "reference_spread": row["reference_spread"],
                "level_ok": bool(v["level_ok"]), "estimated_error": v["estimated_error"], "reason": v["reason"]}

    with ThreadPoolExecutor(max_workers=jobs) as ex:
        return list(ex.map(one, tasks))


def write_csv(rows, path):
    keys = list(rows[0].keys())
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    os.replace(path + ".tmp", path)


def load_csv(path):
    rows = read_rows(path)
    for r in rows:
        r["level_ok"] = str(r["level_ok"]) == "True"
    return rows


def counts(rows):
    """(links, wrong, wrong and flagged, wrong > 0.1 missed, > 0.2 missed, false alarms)."""
    wrong = [r for r in rows if r["error"] > WRONG]
    return {"links": len(rows), "wrong": len(wrong),
            "caught": sum(1 for r in wrong if not r["level_ok"]),
            "missed": sum(1 for r in wrong if r["level_ok"]),
            "missed_02": sum(1 for r in rows if r["error"] > VERY_WRONG and r["level_ok"]),
            "false_alarms": sum(1 for r in rows if r["error"] <= WRONG and not r["level_ok"]),
            "right_ok": sum(1 for r in rows if r["error"] <= WRONG and r["level_ok"])}


def confusion_md(rows):
    md = ["| case | level | links | error > 0.1: flagged / missed | of which > 0.2 missed | error ≤ 0.1: ok / "
          "false alarm |", "|---|---|---|---|---|---|"]
    for name in CASE_ORDER:
        for lv in rfidray_link.LEVELS:
            sel = [r for r in rows if r["case"] == name and r["level"] == lv]
            if not sel:
                continue
            c = counts(sel)
            md.append(f"| {name} | `{lv}` | {c['links']} | {c['caught']} / {c['missed']} | {c['missed_02']} | "
                      f"{c['right_ok']} / {c['false_alarms']} |")
    c = counts(rows)
    md.append(f"| **all** | | {c['links']} | {c['caught']} / {c['missed']} | {c['missed_02']} | "
              f"{c['right_ok']} / {c['false_alarms']} |")
    return md


def totals_md(label, rows):
    c = counts(rows)
    return (f"| {label} | {c['links']} | {c['wrong']} | {c['caught']} | {c['missed']} | {c['missed_02']} | "
            f"{c['false_alarms']} of {c['links'] - c['wrong']} |")


def write(binary, out, scratch, before=None, jobs=2, log=print, reuse=False):
    """reuse: render validity.md from the validity.csv already in OUT (no rfidray calls)."""
    if reuse:
        rows = load_csv(os.path.join(out, "validity.csv"))
    else:
        rows = collect(binary, out, scratch, jobs)
        write_csv(rows, os.path.join(out, "validity.csv"))
    md = ["# Validity against the FDTD reference: flagged links vs measured error", "",
          "Every observer of every case (its CSV in this directory) at every level: `rfidray link --level L --json`'s "
          "`validity.level_ok` against the measured error |h/h_ideal − E/E_free| (a fraction of the free-space "
          f"field) of that level there. Wrong = error > {WRONG}. Written by `run.py --validity` "
          "(bench/fullwave/validity_table.py); one row per link in `validity.csv`.", "",
          "## Totals", "",
          "| build | links | wrong (> 0.1) | flagged | missed | missed > 0.2 | false alarms (flagged, ≤ 0.1) |",
          "|---|---|---|---|---|---|---|"]
    old_rows = load_csv(before) if before else []
    if before:
        md.append(totals_md("before (`validity_before.csv`)", old_rows))
    md.append(totals_md("this build", rows))
    if before:
        md.append(totals_md("before, `full` only", [r for r in old_rows if r["level"] == "full"]))
    md.append(totals_md("this build, `full` only", [r for r in rows if r["level"] == "full"]))
    md += ["", "## Per case and level", ""] + confusion_md(rows)
    missed = sorted((r for r in rows if r["error"] > WRONG and r["level_ok"]), key=lambda r: -r["error"])
    md += ["", f"## Missed: error > {WRONG} and `level_ok`", ""]
    if missed:
        md += ["| case | observer | kρ | level | error | spread | estimate | reason |", "|---|---|---|---|---|---|---|---|"]
        for r in missed:
            md.append(f"| {r['case']} | {r['observer']} | {r['krho']:.2f} | `{r['level']}` | {r['error']:.3f} | "
                      f"{r['reference_spread']:.3f} | {r['estimated_error']:.3f} | {r['reason'] or '—'} |")
    else:
        md.append("None.")
    if before:
        old = {(r["case"], r["observer"], r["level"]): r for r in old_rows}
        changed = [r for r in rows if (k := (r["case"], r["observer"], r["level"])) in old and
                   old[k]["level_ok"] != r["level_ok"]]
        md += ["", "## Verdicts changed since `validity_before.csv`", "",
               f"{sum(1 for r in changed if not r['level_ok'])} links newly flagged "
               f"({sum(1 for r in changed if not r['level_ok'] and r['error'] > WRONG)} of them wrong), "
               f"{sum(1 for r in changed if r['level_ok'])} no longer flagged."]
    p = os.path.join(out, "validity.md")
    with open(p + ".tmp", "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(p + ".tmp", p)
    c = counts(rows)
    log(f"wrote {p}: {c['links']} links, {c['wrong']} wrong, {c['missed']} missed ({c['missed_02']} > 0.2), "
        f"{c['false_alarms']} false alarms")


if __name__ == "__main__":
    print("run it as: run.py --validity --rfidray BIN -o OUT", file=sys.stderr)
    sys.exit(2)
