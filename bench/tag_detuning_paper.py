#!/usr/bin/env python3
"""The paper warehouse with its tags as half-wave dipoles (docs/tag-antenna.md): reads and RSSI with and without the
tag antenna model, for the paper's ten tags and for a tag set 1 cm off the east racks' metal faces.

Each variant runs `rfidray simulate` on a copy of scenes/paper_warehouse.yaml with the physical reader model and a
traced channel (both overridden on the command line), once with point tags (today's default) and once with
`antenna: dipole:0.166:0.0005` on every tag (chip matched in free space, backed by the scene's metal within 15 cm).
Per tag: reads, mean RSSI, and the detuning the link command reports at the tag (nearest metal, τ, F).

Usage: python3 bench/tag_detuning_paper.py RFIDRAY_BINARY REPO_ROOT OUT_DIR [--channel single-bounce]
Writes OUT_DIR/paper_warehouse.md and OUT_DIR/paper_warehouse.csv. Exit 2 on bad arguments or a failed run.
"""
import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

DIPOLE = "dipole:0.166:0.0005"
RACK_FACE_SET = """
tag_sets:
  - name: face_{i}
    surface: {material: metal, mesh: rack_east_*, facing: [-1, 0, 0], offset_m: 0.01, step_m: 0.6,
              within: {min: [2.0, -9.5, 0.5], max: [3.0, 1.0, 2.6]}}
  - name: shelf_{i}
    surface: {material: metal, mesh: rack_east_*, facing: [0, 0, 1], offset_m: 0.01, step_m: 0.5,
              within: {min: [3.1, -9.5, 1.0], max: [3.8, 1.0, 1.1]}}
"""


def fail(msg):
    print(f"tag_detuning_paper.py: {msg}", file=sys.stderr)
    sys.exit(2)


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"{' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()[-2000:]}")
    return r


def variant(base_text, with_antenna, with_face_set):
    text = base_text
    if with_face_set:
        text = text.rstrip() + "\n" + RACK_FACE_SET
        if with_antenna:
            for name in ("face_{i}", "shelf_{i}"):
                text = text.replace(f"  - name: {name}\n", f"  - name: {name}\n    antenna: " + DIPOLE + "\n")
    if with_antenna:
        # every listed tag: {name: tagN, position: [...]} → with the antenna key
        text = re.sub(r"\{name: (tag\d+), position: (\[[^\]]*\])\}", r"{name: \1, position: \2, antenna: '" + DIPOLE + "'}", text)
    return text


def simulate(binary, scenario, out_dir, channel):
    r = run([binary, "simulate", scenario, "--model", "physical", "--channel", channel, "-o", out_dir, "--threads", "2"])
    stats = {}
    for name in ("mobile", "fixed"):
        path = os.path.join(out_dir, name + ".csv")
        with open(path) as f:
            for row in csv.DictReader(f):
                s = stats.setdefault(row["name"], {"reads": 0, "rssi_sum": 0.0})
                s["reads"] += 1
                s["rssi_sum"] += float(row["rssi"])
    tags = {}
    with open(os.path.join(out_dir, "tags.csv")) as f:
        for row in csv.DictReader(f):
            tags[row["name"]] = (float(row["x"]), float(row["y"]), float(row["z"]))
    return stats, tags, r.stderr


def detuning(binary, scene, position):
    j = json.loads(run([binary, "link", "--scene", scene, "--antenna", "0,0,1", "--tag", ",".join(map(str, position)),
                        "--tag-antenna", DIPOLE, "--json"]).stdout)
    t = j["tag_antenna"]
    b = t["backing"]
    return (b["distance_m"] if b["kind"] != "none" else None, t["power_transfer_db"], t["chip_power_factor_db"],
            b["plane_model_ok"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("binary")
    ap.add_argument("root")
    ap.add_argument("out_dir")
    ap.add_argument("--channel", default="single-bounce")
    a = ap.parse_args()
    src = os.path.join(a.root, "scenes", "paper_warehouse.yaml")
    if not os.path.isfile(src):
        fail(f"{src}: not found (give the repository root)")
    base = open(src).read()
    os.makedirs(a.out_dir, exist_ok=True)
    work = tempfile.mkdtemp(prefix="tag_detuning_")
    rows = []
    notes = []
    try:
        shutil.copy(os.path.join(a.root, "scenes", "paper_warehouse.obj"), work)
        shutil.copy(os.path.join(a.root, "scenes", "paper_warehouse.mtl"), work)
        results = {}
        for face in (False, True):
            for antenna in (False, True):
                scen = os.path.join(work, f"v_{int(face)}_{int(antenna)}.yaml")
                with open(scen, "w") as f:
                    f.write(variant(base, antenna, face))
                out = os.path.join(work, f"out_{int(face)}_{int(antenna)}")
                results[(face, antenna)] = simulate(a.binary, scen, out, a.channel)
                if antenna:
                    notes += [l for l in results[(face, antenna)][2].splitlines()
                              if "detuned" in l or "upper bound" in l]
        scene = os.path.join(work, "paper_warehouse.obj")
        for face in (False, True):
            point_stats, tags, _ = results[(face, False)]
            dip_stats, _, _ = results[(face, True)]
            for name, pos in tags.items():
                if face != (name.startswith("face_") or name.startswith("shelf_")):
                    continue
                p = point_stats.get(name, {"reads": 0, "rssi_sum": 0.0})
                d = dip_stats.get(name, {"reads": 0, "rssi_sum": 0.0})
                dist, tau, factor, plane_ok = detuning(a.binary, scene, pos)
                group = ("rack face (1 cm)" if name.startswith("face_") else "on a shelf plate (1 cm)") if face else "paper tags"
                rows.append({"set": group, "tag": name,
                             "x": pos[0], "y": pos[1], "z": pos[2],
                             "metal_m": dist, "tau_db": tau, "F_db": factor, "plane_model_ok": plane_ok,
                             "reads_point": p["reads"], "rssi_point_dbm": p["rssi_sum"] / p["reads"] if p["reads"] else None,
                             "reads_dipole": d["reads"], "rssi_dipole_dbm": d["rssi_sum"] / d["reads"] if d["reads"] else None})
    finally:
        shutil.rmtree(work, ignore_errors=True)

    def f(v, fmt):
        return "—" if v is None else fmt.format(v)

    with open(os.path.join(a.out_dir, "paper_warehouse.csv"), "w", newline="") as fo:
        w = csv.DictWriter(fo, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out_dir, "paper_warehouse.md"), "w") as fo:
        fo.write(f"Command: `python3 bench/tag_detuning_paper.py build/rfidray . bench/results/tag_antenna --channel {a.channel}`"
                 f" (physical reader model, channel {a.channel}, both antennas, the paper's trajectory and seed).\n\n")
        for n in notes:
            fo.write(f"- simulate: {n.replace('rfidray: note: ', '')}\n")
        fo.write("\n| set | tag | nearest metal (m) | plane model | τ (dB) | F (dB) | reads, point tag | RSSI (dBm), point tag | reads, dipole | RSSI (dBm), dipole |\n")
        fo.write("|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            fo.write(f"| {r['set']} | {r['tag']} | {f(r['metal_m'], '{:.3f}')} | "
                     f"{'ok' if r['plane_model_ok'] else 'upper bound'} | {r['tau_db']:.1f} | {r['F_db']:+.1f} | "
                     f"{r['reads_point']} | {f(r['rssi_point_dbm'], '{:.1f}')} | {r['reads_dipole']} | {f(r['rssi_dipole_dbm'], '{:.1f}')} |\n")
        for s in ("paper tags", "rack face (1 cm)", "on a shelf plate (1 cm)"):
            sel = [r for r in rows if r["set"] == s]
            tp, td = sum(r["reads_point"] for r in sel), sum(r["reads_dipole"] for r in sel)
            ok = sum(1 for r in sel if r["plane_model_ok"])
            fo.write(f"| **{s}: {len(sel)} tags** | | | {ok} ok | | | **{tp}** | | **{td}** | |\n")
    print(f"wrote {os.path.join(a.out_dir, 'paper_warehouse.md')} ({len(rows)} tags)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
