#!/usr/bin/env python3
"""bench/row_errors_by_distance.py (README "Real readers": which effect the simulated rows miss).

Simulated rows of 5 tags at three distances, two runs each (row centre moved by 2 cm):
- without a wall the range errors hardly change with the distance (their per-distance medians within 2 cm of
  each other in every slot);
- with a concrete wall 0.5-0.6 m behind the row they swing with the distance by several times more, while the
  two runs at one distance still agree: the signature the real held-out runs show.
Also: the real mode on a folder the test writes in real_data.py's --keep layout, and exit 2 on bad input.
Usage: test_row_errors_by_distance.py RFIDRAY_BINARY SOURCE_DIR"""
import json
import os
import subprocess
import sys
import tempfile


def run(script, rfidray, args):
    return subprocess.run([sys.executable, script, "--rfidray", rfidray] + args, capture_output=True, text=True,
                          timeout=600)


def summary(stdout):
    """slot -> (median error, median spread, sd of per-distance medians), cm."""
    rows = {}
    for line in stdout.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and cells[0].isdigit():
            rows[int(cells[0])] = tuple(float(c) for c in cells[1:4])
    return rows


def main():
    rfidray, src = sys.argv[1], sys.argv[2]
    script = os.path.join(src, "bench", "row_errors_by_distance.py")
    failures = []

    def check(cond, what):
        if not cond:
            failures.append(what)

    base = ["simulated", "--distances", "0.60,0.65,0.70", "--seeds", "2"]
    plain = run(script, rfidray, base)
    wall = run(script, rfidray, base + ["--wall-y", "1.25", "--wall-material", "concrete"])
    check(plain.returncode == 0 and wall.returncode == 0, "simulated runs: %s %s" % (plain.stderr, wall.stderr))
    p, w = summary(plain.stdout), summary(wall.stdout)
    check(sorted(p) == [1, 2, 3, 4, 5] and sorted(w) == [1, 2, 3, 4, 5], "five slots:\n%s\n%s" % (plain.stdout, wall.stdout))
    if len(p) == 5 and len(w) == 5:
        check(max(v[2] for v in p.values()) < 2.0, "no wall: per-distance medians within 2 cm: %s" % p)
        swing = sorted(v[2] for v in w.values())
        check(swing[2] > 3 * max(v[2] for v in p.values()) and swing[2] > 3.0,
              "wall: the median slot's swing is > 3 cm and 3x the plain one: %s vs %s" % (w, p))
        check(all(v[1] < v[2] for v in w.values()), "wall: runs at one distance agree better than distances: %s" % w)

    # real mode: two runs in real_data.py's --keep layout, written from one simulation
    with tempfile.TemporaryDirectory() as tmp:
        sim = os.path.join(tmp, "sim")
        os.makedirs(sim)
        scenario = os.path.join(src, "scenes", "stage_1m.yaml")
        r = subprocess.run([rfidray, "simulate", scenario, "-o", sim, "-q", "--channel", "ideal"], capture_output=True,
                           text=True)
        check(r.returncode == 0, "simulate stage_1m: %s" % r.stderr)
        for run_name in ("run-a", "run-b"):
            folder = os.path.join(tmp, "train", run_name)
            os.makedirs(folder)
            with open(os.path.join(sim, "stage.csv")) as f, open(os.path.join(folder, "readings.csv"), "w") as g:
                g.write(f.read())
            with open(os.path.join(folder, "truth.csv"), "w") as g:
                g.write("name,x,y,z\ntag1,0.3,0.88,0\ntag2,0.5,0.88,0\ntag3,0.7,0.88,0\n")
        r = run(script, rfidray, ["real", os.path.join(tmp, "train")])
        check(r.returncode == 0, "real mode: exit %d %s" % (r.returncode, r.stderr))
        rows = summary(r.stdout)
        check(sorted(rows) == [1, 2, 3], "real mode: three slots: %s" % r.stdout)
        # the script's bookkeeping (slots by x, sign of the error) against localize's own estimates
        run_a = os.path.join(tmp, "train", "run-a")
        out = subprocess.run([rfidray, "localize", os.path.join(run_a, "readings.csv"), "--truth",
                              os.path.join(run_a, "truth.csv"), "--method",
                              "nlls", "--height-known", "--mirror-prior", "boresight", "--max-range", "3", "--json",
                              "--max-residual-rad", "10", "--max-uncertainty-m", "10"], capture_output=True, text=True)
        estimate = {e["name"]: e["y"] for e in json.loads(out.stdout)["results"]}
        for slot, name in ((1, "tag1"), (2, "tag2"), (3, "tag3")):
            if slot in rows and estimate.get(name) is not None:
                check(abs(rows[slot][0] - 100 * (estimate[name] - 0.88)) < 0.06,
                      "real mode: slot %d error %.2f cm, localize says %.2f cm" % (slot, rows[slot][0],
                                                                                  100 * (estimate[name] - 0.88)))
        check("| 0.88 |" in r.stdout, "real mode: the distance row: %s" % r.stdout)
        bad = run(script, rfidray, ["real", os.path.join(tmp, "absent")])
        check(bad.returncode == 2 and "absent" in bad.stderr, "bad folder: %d %s" % (bad.returncode, bad.stderr))

    for f in failures:
        print("FAIL:", f)
    print("row_errors_by_distance: %d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
