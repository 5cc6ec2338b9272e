#!/usr/bin/env python3
"""Signed localization errors of a row of tags, per slot in the row and per distance of the row from the stage.

Two sources, one table:
  real RUNS_DIR [--antenna-file A] [--start K --every N]
      runs converted by `bench/real_data.py --keep DIR` (RUNS_DIR = DIR/D1/train: <run>/{readings,truth}.csv);
  simulated [--wall-y Y --wall-material M] [--seeds 3]
      the same stage in rfidray (50 stops over x 0.02-0.98 m facing +y, 8 hopping carriers, a concrete floor
      0.75 m below, ideal antenna and tags), a row of 5 tags 20 cm apart at 0.50, 0.55 ... 0.90 m (--distances), and
      optionally a wall parallel to the stage at y = Y behind the row; each seed moves the row's centre
      (0.50, 0.52, 0.48 m) as the real runs do.
Every run is localized by `rfidray localize --method nlls --height-known --mirror-prior boresight --max-range 3
--json` with every gate open (`--max-residual-rad 10 --max-uncertainty-m 10`), so that biased tags are seen
instead of failed. Printed: the range error (estimated minus true y) of every run, per distance and slot, then
per slot the median error, the median spread between the runs at one distance, the spread of the
per-distance medians and the median wrapped-phase residual.

An error that is random (noise) spreads between runs at one distance. An error that is the same for every run
at one distance but swings from one distance to the next comes from the geometry that changes with the
distance: a path whose length depends on where the row is. A property of the antenna or of a tag in its row
changes smoothly with the distance instead.

Usage: row_errors_by_distance.py real RUNS_DIR [--antenna-file A] [--rfidray build/rfidray]
       row_errors_by_distance.py simulated [--wall-y 1.4 --wall-material concrete] [--rfidray build/rfidray]
"""
import argparse
import collections
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile

OPEN_GATES = ["--method", "nlls", "--height-known", "--mirror-prior", "boresight", "--max-range", "3", "--json",
              "--max-residual-rad", "10", "--max-uncertainty-m", "10"]


def die(message):
    print("row_errors_by_distance: " + message, file=sys.stderr)
    sys.exit(2)


def localize(rfidray, readings, truth, extra):
    r = subprocess.run([rfidray, "localize", readings, "--truth", truth] + OPEN_GATES + extra,
                       capture_output=True, text=True)
    if r.returncode != 0:
        die("%s: rfidray localize exit %d: %s" % (readings, r.returncode, r.stderr.strip()[-400:]))
    try:
        return json.loads(r.stdout)["results"]
    except (ValueError, KeyError) as e:
        die("%s: rfidray localize printed no results JSON (%s)" % (readings, e))


def collect(results, truth_csv, table):
    """table[(distance, slot)] += [(range error, residual)]; slots by x order in the row."""
    try:
        with open(truth_csv, encoding="utf-8") as f:
            truth = {r["name"]: (float(r["x"]), float(r["y"])) for r in csv.DictReader(f)}
    except (OSError, KeyError, TypeError, ValueError) as e:
        die("%s: not a truth CSV with name,x,y columns (%s)" % (truth_csv, e))
    slot = {name: i for i, name in enumerate(sorted(truth, key=lambda n: truth[n][0]))}
    for r in results:
        if r.get("y") is None or r["name"] not in truth:
            continue
        tx, ty = truth[r["name"]]
        table[(round(ty, 2), slot[r["name"]])].append((r["y"] - ty, r.get("residual_rad")))


def real(args, table):
    if not os.path.isdir(args.runs):
        die("%s: not a folder (give DIR/D1/train of `bench/real_data.py --keep DIR`)" % args.runs)
    runs = sorted(os.listdir(args.runs))[args.start::args.every]
    extra = ["--antenna-file", args.antenna_file] if args.antenna_file else []
    for run in runs:
        folder = os.path.join(args.runs, run)
        readings, truth = os.path.join(folder, "readings.csv"), os.path.join(folder, "truth.csv")
        if not (os.path.isfile(readings) and os.path.isfile(truth)):
            die("%s: no readings.csv and truth.csv" % folder)
        collect(localize(args.rfidray, readings, truth, extra), truth, table)
    return len(runs)


def simulated(args, table):
    # The stage exactly as bench/real_data.py simulates the set's runs, plus the optional wall.
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from real_data import simulated_scenario, write_floor
    work = tempfile.mkdtemp(prefix="rfidray-row-")
    write_floor(os.path.join(work, "floor.obj"))
    walls = []
    if args.wall_y is not None:
        with open(os.path.join(work, "wall.obj"), "w") as f:  # 4 m x 3 m in the plane y = 0
            f.write("v -2 0 -1\nv 2 0 -1\nv 2 0 2\nv -2 0 2\nf 1 3 2\nf 1 4 3\n")
        walls.append("{file: %s, material: %s, position: [0.5, %.4f, 0]}"
                     % (os.path.join(work, "wall.obj"), args.wall_material, args.wall_y))
    count = 0
    for distance in args.distances:
        for seed, centre in list(zip([1, 2, 3], [0.50, 0.52, 0.48]))[:args.seeds]:
            tags = [("slot%d" % i, centre + 0.2 * (i - 2), distance, 0.0) for i in range(5)]
            folder = os.path.join(work, "%.2f_%d" % (distance, seed))
            scenario = folder + ".yaml"
            simulated_scenario(scenario, tags, None, "single-bounce", seed=seed, extra_meshes=walls)
            r = subprocess.run([args.rfidray, "simulate", scenario, "-o", folder, "-q"], capture_output=True, text=True)
            if r.returncode != 0:
                die("rfidray simulate exit %d: %s" % (r.returncode, r.stderr.strip()[-400:]))
            truth = os.path.join(folder, "truth.csv")
            with open(truth, "w") as f:
                f.write("name,x,y,z\n" + "".join("%s,%.4f,%.4f,%.4f\n" % t for t in tags))
            collect(localize(args.rfidray, os.path.join(folder, "stage.csv"), truth, []), truth, table)
            count += 1
    return count


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rfidray", default=os.path.join("build", "rfidray"))
    sub = ap.add_subparsers(dest="source", required=True)
    r = sub.add_parser("real")
    r.add_argument("runs")
    r.add_argument("--antenna-file")
    r.add_argument("--start", type=int, default=0)
    r.add_argument("--every", type=int, default=1)
    s = sub.add_parser("simulated")
    s.add_argument("--wall-y", type=float, help="a wall at this y (m), parallel to the stage; none when absent")
    s.add_argument("--wall-material", default="concrete")
    s.add_argument("--seeds", type=int, default=3, choices=[1, 2, 3])
    s.add_argument("--distances", default="0.50,0.55,0.60,0.65,0.70,0.75,0.80,0.85,0.90",
                   help="row distances from the stage (m), comma-separated")
    args = ap.parse_args()
    if args.source == "simulated":
        try:
            args.distances = [float(x) for x in args.distances.split(",")]
        except ValueError:
            die("--distances: not a comma-separated list of numbers: %r" % args.distances)
        if not all(0.05 <= d <= 5.0 for d in args.distances):
            die("--distances: each must be within 0.05 ... 5 m")
        if args.wall_y is not None and not all(args.wall_y > d + 0.05 for d in args.distances):
            die("--wall-y: the wall must be behind the row (beyond every distance + 5 cm)")
    if not os.access(args.rfidray, os.X_OK):
        die("%s: no rfidray binary (build first, or give --rfidray)" % args.rfidray)
    table = collections.defaultdict(list)
    runs = real(args, table) if args.source == "real" else simulated(args, table)
    if not table:
        die("no estimates in %d runs" % runs)
    distances = sorted({d for d, _ in table})
    slots = sorted({s for _, s in table})
    print("range error (estimated − true distance, cm) of each run, by row distance and slot; %d runs\n" % runs)
    print("| distance m | " + " | ".join("slot %d" % (s + 1) for s in slots) + " |")
    print("|---" * (len(slots) + 1) + "|")
    for d in distances:
        print("| %.2f | " % d + " | ".join(" ".join("%+.0f" % (100 * e) for e, _ in table[(d, s)]) or "–"
                                           for s in slots) + " |")
    print("\n| slot | median error cm | median spread between runs at one distance cm | sd of the per-distance "
          "medians cm | median residual rad |")
    print("|---|---|---|---|---|")
    for s in slots:
        cells = [table[(d, s)] for d in distances if table[(d, s)]]
        errors = [e for c in cells for e, _ in c]
        spreads = [max(e for e, _ in c) - min(e for e, _ in c) for c in cells if len(c) > 1]
        medians = [statistics.median(e for e, _ in c) for c in cells]
        residuals = [x for c in cells for _, x in c if x is not None]
        print("| %d | %+.1f | %.1f | %.1f | %s |" % (
            s + 1, 100 * statistics.median(errors), 100 * statistics.median(spreads) if spreads else float("nan"),
            100 * statistics.pstdev(medians) if len(medians) > 1 else 0.0,
            "%.2f" % statistics.median(residuals) if residuals else "–"))


if __name__ == "__main__":
    main()
