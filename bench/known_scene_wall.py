#!/usr/bin/env python3
"""A metal wall behind a tag, localized from the phase alone and with the scene known (`localize --scenario`).

The setup of the issue's silent SAR failure, ray-traced: one antenna on a 1 m stage facing +y (8 hopping carriers
920.625-924.125 MHz, 100 reads/s at 4 cm/s), one tag 0.7 m in front of it facing the stage, a metal wall (5 m x 3 m)
0.1 ... 1 m behind the tag, channel single-bounce, physical reader model, phase noise 0.05 rad. For each gap it runs
`rfidray simulate`, then `rfidray localize ... --method all --height-known --mirror-prior boresight --max-range 3
--json`, without and with `--scenario` (the scenario it simulated), and prints a markdown table: status (reason),
error and 95 % radius in mm, and the scene's multipath allowance (rad). Deterministic (seed 1).

Usage: python3 bench/known_scene_wall.py [--rfidray build/rfidray] [-o bench/results/known_scene]
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

SCENARIO = """name: wall_{gap}
seed: 1
channel: single-bounce
model: physical
scene:
  meshes: [{{file: wall.obj, material: metal}}]
antennas:
  - name: stage
    frequencies_hz: [920.625e6, 921.125e6, 921.625e6, 922.125e6, 922.625e6, 923.125e6, 923.625e6, 924.125e6]
    hop_dwell_s: 0.125
    update_rate: 100
    tx_power_dbm: 30
    noisephi: 0.05
    pattern: {{kind: patch, gain_dbi: 8, beamwidth_deg: 70}}
    yaw_deg: 90
    waypoints: [[0.0, 0, 0], [1.0, 0, 0]]
    speed_m_s: 0.04
tags:
  - {{name: tag, position: [0.5, 0.7, 0], yaw_deg: -90}}
"""


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(cmd), p.stderr))
    return p.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rfidray", default=os.path.join("build", "rfidray"))
    ap.add_argument("-o", "--output", default=os.path.join("bench", "results", "known_scene"))
    args = ap.parse_args()
    rows = []
    work = tempfile.mkdtemp(prefix="rfidray_known_scene_")  # scenarios and readings; only the table is kept
    for gap in (0.1, 0.25, 0.5, 0.75, 1.0):
        folder = os.path.join(work, "gap_%g" % gap)
        os.makedirs(folder, exist_ok=True)
        wall_y = 0.7 + gap
        with open(os.path.join(folder, "wall.obj"), "w") as f:
            f.write("v -2 {0} -1.5\nv 3 {0} -1.5\nv 3 {0} 1.5\nv -2 {0} 1.5\nf 1 2 3\nf 1 3 4\n".format(wall_y))
        scenario = os.path.join(folder, "wall.yaml")
        with open(scenario, "w") as f:
            f.write(SCENARIO.format(gap=gap))
        run([args.rfidray, "simulate", scenario, "-o", os.path.join(folder, "out"), "-q"])
        base = [args.rfidray, "localize", os.path.join(folder, "out", "stage.csv"), "--truth",
                os.path.join(folder, "out", "tags.csv"), "--method", "all", "--height-known", "--mirror-prior",
                "boresight", "--max-range", "3", "--json"]
        for label, extra in (("phase only", []), ("--scenario", ["--scenario", scenario])):
            for r in json.loads(run(base + extra))["results"]:
                status = r["status"] if r["status"] == "ok" else "%s (%s)" % (r["status"], r["reason"])
                error = "%.0f" % (1e3 * r["error_m"]) if r.get("error_m") is not None else "-"
                radius = "%.0f" % (1e3 * r["uncertainty_m"]) if r.get("uncertainty_m") is not None else "-"
                allowance = "%.2f" % r["multipath_phase_rad"] if r.get("multipath_phase_rad") is not None else "-"
                silent = r["status"] == "ok" and r["error_m"] > r["uncertainty_m"]
                rows.append("| %g | %s | %s | %s%s | %s | %s | %s |" % (gap, label, r["method"], status,
                            " **outside**" if silent else "", error, radius, allowance))
    table = ["| wall gap m | localize | method | status | error mm | radius mm | multipath rad |",
             "|---|---|---|---|---|---|---|"] + rows
    shutil.rmtree(work)
    os.makedirs(args.output, exist_ok=True)
    with open(os.path.join(args.output, "known_scene_wall.md"), "w") as f:
        f.write("\n".join(table) + "\n")
    print("\n".join(table))


if __name__ == "__main__":
    main()
