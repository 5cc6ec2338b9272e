#!/usr/bin/env python3
"""Phase residual against the TRUE tag position, as a function of the direction at the antenna, per tag of a row.

Reads runs converted by `bench/real_data.py --keep DIR` (DIR/D1/train/<run>/{readings,truth}.csv) and an antenna
file of `rfidray calibrate` (phase centre along boresight, carrier offsets; the pattern is left OUT, so what is
printed is what a pattern would have to explain). For each (tag, stop, carrier): the circular mean phase minus
4πfR/c minus the carrier offset, minus the tag's own mean; averaged per tag index in the row and 10° bin of the
azimuth at the antenna. An antenna effect is the same curve for every tag; a tag-in-row effect is not.
Usage: real_residual_vs_angle.py RUNS_DIR ANTENNA_YAML [--every K]
"""
import argparse
import cmath
import collections
import csv
import math
import os
import re

C = 299792458.0


def read_antenna(path):
    text = open(path, encoding="utf-8").read()

    def numbers(key):
        m = re.search(r"^%s:\s*\[([^\]]*)\]" % key, text, re.M)
        if not m:
            raise SystemExit("%s: no '%s' list" % (path, key))
        return [float(x) for x in m.group(1).split(",")]
    return numbers("phase_centre_offset_m")[0], dict(zip(numbers("frequencies_hz"), numbers("carrier_offsets_rad")))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs")
    ap.add_argument("antenna")
    ap.add_argument("--every", type=int, default=1, help="use every K-th run")
    args = ap.parse_args()
    centre_m, offsets = read_antenna(args.antenna)
    runs = sorted(os.listdir(args.runs))[::max(1, args.every)]
    bins = collections.defaultdict(list)
    for run in runs:
        folder = os.path.join(args.runs, run)
        truth = {r["name"]: (float(r["x"]), float(r["y"])) for r in csv.DictReader(open(os.path.join(folder, "truth.csv")))}
        order = {name: i for i, name in enumerate(sorted(truth))}
        acc = collections.defaultdict(complex)
        for r in csv.DictReader(open(os.path.join(folder, "readings.csv"))):
            acc[(r["name"], round(float(r["posx"]), 4), float(r["frequency_hz"]))] += cmath.exp(1j * float(r["phase"]))
        for name, (tx, ty) in truth.items():
            points = []
            for (n, ax, f), z in acc.items():
                if n != name:
                    continue
                off = next((v for k, v in offsets.items() if abs(k - f) < 1e3), None)
                if off is None:
                    continue
                r_m = math.hypot(tx - ax, ty - centre_m)  # stage along x, boresight +y
                residual = cmath.phase(z * cmath.exp(-1j * (4 * math.pi * f / C * r_m + off)))
                points.append((math.degrees(math.atan2(tx - ax, ty - centre_m)), residual))
            if not points:
                continue
            mean = cmath.phase(sum(cmath.exp(1j * p) for _, p in points))
            for az, p in points:
                bins[(order[name], 10 * round(az / 10))].append(cmath.phase(cmath.exp(1j * (p - mean))))
    print("tag in row | mean residual (rad) per 10-degree bin of the azimuth at the antenna")
    for idx in sorted({k[0] for k in bins}):
        cells = ["%+d:%+.2f" % (a, sum(bins[(idx, a)]) / len(bins[(idx, a)])) for a in range(-90, 91, 10) if bins[(idx, a)]]
        print("%d | %s" % (idx, " ".join(cells)))


if __name__ == "__main__":
    main()
