#!/usr/bin/env python3
"""bench/real_data.py end to end on a small data set that this test writes in the AdaRF layout (the real set is
never in the repository): per-stop CSV files with a BOM and the invalid y = 1.63 column, dataset/config.txt,
codes/config.py. Phases follow the geometry exactly (4πfD/c, per-tag and per-carrier offsets, a little noise),
so every method must find the tags within a few millimetres, the table must list them, and the calibration
must run on the training split. Fails on any broken step: import, truth reconstruction, calibrate, localize.
Usage: test_real_data.py RFIDRAY_BINARY SOURCE_DIR"""
import csv
import math
import os
import random
import subprocess
import sys
import tempfile

C = 299792458.0


def write_run(folder, tags, carriers, reads_per_stop, rng):
    os.makedirs(folder)
    tag_offset = {epc: rng.uniform(0, 2 * math.pi) for epc, _, _ in tags}
    for k in range(50):
        ax = 0.02 + k * 0.96 / 49
        with open(os.path.join(folder, "%d.csv" % k), "w", encoding="utf-8") as f:
            f.write("\ufeffepc,antennaIndex,frequency,time,RSSI,phase,dopplerShift,velocity,x,y,z,angle\n")
            for c, fr in enumerate(carriers):
                for epc, tx, ty in tags:
                    d = math.hypot(tx - ax, ty)
                    phase = (4 * math.pi * fr * d / C + tag_offset[epc] + 0.3 * c + rng.gauss(0, 0.05)) % (2 * math.pi)
                    for _ in range(reads_per_stop):
                        f.write("%s,1,%d,0,-50.5,%.6f,0,0,%.6f,1.63,0,-0.02\n" % (epc, fr, phase, ax))


STAND_INS = {
    # Stand-ins with the interfaces bench/real_peers.py calls (the set's own code is never in the repository).
    "config.py": "FRE_TEST = [920625000 + 500000 * k for k in range(8)]\nFRE_TRAIN = [920625000]\n",
    "extract_signal_profile.py": """
import os
import numpy as np
def read_file(path):
    return [open(os.path.join(path, "%d.csv" % i), encoding="utf-8-sig").read().split("\\n")[1:]
            for i in range(len(os.listdir(path)))]
def extract_profile(data, epcs, fres):
    out = np.full((len(epcs), 2, len(fres), len(data)), -1.0)
    for p, lines in enumerate(data):
        for line in lines:
            f = line.split(",")
            if len(f) < 6 or f[0].encode() not in epcs or int(f[2]) not in fres:
                continue
            out[epcs.index(f[0].encode()), 0, fres.index(int(f[2])), p] = float(f[5])
    xs = np.zeros((1, len(data)))
    xs[0, :] = np.linspace(0.02, 0.98, len(data))  # where this test's runs put the stops
    return out, xs
""",
    "preprocess.py": """
import numpy as np
def preprocess(phases, xs, epc=b''):
    keep = np.all(phases != -1, axis=0)
    return np.unwrap(phases[:, keep], axis=1), np.repeat(xs[:, keep], phases.shape[0], axis=0)
""",
    "hologram.py": """
import numpy as np
class Hologram:
    def __init__(self, paras, phases, xs, fres):
        self.n, self.step, self.phases, self.xs, self.fres = paras[0], paras[2], phases, xs, np.array(fres, float)
    def _map(self):
        m = np.zeros((self.n, self.n))
        k = 4 * np.pi * self.fres[:, None] / 299792458.0
        for r in range(self.n):
            for c in range(self.n):
                d = np.hypot(self.xs - (r + 1) * self.step, (c + 1) * self.step)
                m[self.n - 1 - c, r] = np.abs(np.sum(np.exp(1j * (self.phases - k * d)), axis=1)).sum()
        return m
    holo_tagoram = holo_mobitagbot = _map
""",
    "other_schemes.py": """
import numpy as np
from codes.hologram import Hologram
def rf_scanner(phases, xs, fres):
    h = Hologram([100, 100, 0.01, 0.01], phases, xs, fres)
    i, j = np.unravel_index(np.argmax(h._map()), (100, 100))
    return [(j + 1) * 0.01, (100 - i) * 0.01]
def stpp(phases, xs, fres):
    return rf_scanner(phases, xs, fres)[0]
""",
}


def write_stand_in_peers(codes):
    for name, text in STAND_INS.items():
        mode = "a" if name == "config.py" else "w"
        with open(os.path.join(codes, name), mode) as f:
            f.write(text)


def main():
    rfidray, source = sys.argv[1], sys.argv[2]
    rng = random.Random(7)
    root = tempfile.mkdtemp(prefix="adarf-layout-")
    epcs_train = ["10%022d" % i for i in range(5)]
    epcs_test = ["10%022d" % i for i in range(1, 4)]
    os.makedirs(os.path.join(root, "codes"))
    with open(os.path.join(root, "codes", "config.py"), "w") as f:
        f.write("EPC_C1 = [%s]\n" % ",".join("b'%s'" % e for e in epcs_train))
        f.write("EPC_T1 = [%s]\n" % ",".join("b'%s'" % e for e in epcs_test))
        f.write("CONFIG_D1_TRAIN = {'EPC': EPC_C1, 'separation': 20, 'frequency': [920625000]}\n")
        f.write("CONFIG_D1_TEST = {'EPC': EPC_T1, 'separation': 20, 'frequency': []}\n")
    ds = os.path.join(root, "dataset")
    os.makedirs(ds)
    with open(os.path.join(ds, "config.txt"), "w") as f:
        f.write("number,x_center,y,num_location,num_fre\n1118 1-2:50 70 50 1\n1218 1-1:50 80 50 8\n1218 2-2:48 65 50 8\n")
    carriers = [920.625e6 + 0.5e6 * k for k in range(8)]
    for i, (x_cm, y_cm) in enumerate([(50, 70), (50, 70)], 1):
        tags = [(e, (x_cm + 20 * (j - 2)) / 100, y_cm / 100) for j, e in enumerate(epcs_train)]
        write_run(os.path.join(ds, "1", "train", "181118-%02d-50-1" % i), tags, carriers[:1], 3, rng)
    for i, (x_cm, y_cm) in enumerate([(50, 80), (48, 65)], 1):
        tags = [(e, (x_cm + 20 * (j - 1)) / 100, y_cm / 100) for j, e in enumerate(epcs_test)]
        write_run(os.path.join(ds, "1", "test", "181218-%02d-50-8" % i), tags, carriers, 2, rng)
    write_stand_in_peers(os.path.join(root, "codes"))
    out = os.path.join(root, "out")
    keep = os.path.join(root, "keep")
    r = subprocess.run([sys.executable, os.path.join(source, "bench", "real_data.py"), "--adarf", root, "--rfidray",
                        rfidray, "-o", out, "--datasets", "1", "--no-sim", "--peers", "--jobs", "1", "--keep", keep],
                       capture_output=True, text=True)
    print(r.stdout[-3000:], r.stderr[-3000:])
    if r.returncode != 0:
        print("FAIL: real_data.py exited %d" % r.returncode)
        return 1
    rows = list(csv.DictReader(open(os.path.join(out, "real_vs_sim.csv"))))
    failures = []
    # Uncalibrated, the geometry is exact up to 0.05 rad of noise: millimetres. Calibrated from two single-
    # carrier training runs, the phase centre along boresight is poorly determined (sd of several cm, printed
    # in antenna.yaml) and shifts the estimates by up to a few cm: the bound is looser there.
    for label, max_mm in (("real, uncalibrated", 30.0), ("real, calibrated", 60.0)):
        real = [row for row in rows if row["data"] == label]
        if len(real) != 3:
            failures.append("%s: expected 3 method rows, got %d" % (label, len(real)))
        for row in real:
            if int(row["tags"]) != 6:
                failures.append("%s %s: %s tags localized, expected 6 (2 runs x 3 tags)" % (label, row["method"], row["tags"]))
            if int(row["ok"]) < 5:
                failures.append("%s %s: only %s of 6 ok on near-exact geometry" % (label, row["method"], row["ok"]))
            if not float(row["max_mm"]) < max_mm:
                failures.append("%s %s: max error %s mm on near-exact data" % (label, row["method"], row["max_mm"]))
    if not os.path.isfile(os.path.join(out, "antenna.yaml")):
        failures.append("no antenna.yaml from calibrate")
    # The peers' harness (bench/real_peers.py) on the stand-ins: the set's extraction layout, the hologram's map
    # layout and the truth all line up, so the stand-in matched filter finds the tags to its 1 cm grid.
    peers = {row["method"]: row for row in csv.DictReader(open(os.path.join(out, "real_vs_peers.csv")))}
    for m in ("Tagoram", "MobiTagbot", "RF-Scanner", "STPP (x only)"):
        if m not in peers:
            failures.append("real_vs_peers.csv: no row for %s" % m)
        elif int(peers[m]["positioned"]) != 6 or not float(peers[m]["max_mm"]) < 25.0:
            failures.append("peer %s: %s of 6 positioned, max error %s mm" % (m, peers[m]["positioned"], peers[m]["max_mm"]))
    for m in ("rfidray nlls, calibrated", "rfidray nlls, uncalibrated"):
        if m not in peers or int(peers[m]["positioned"]) != 6:
            failures.append("real_vs_peers.csv: no full row for %s" % m)
    # Paired by (run, tag): both runs carry the same three EPCs, so pairing by name alone would find 3 tags, not 6;
    # with every tag placed by both, each side's paired mean is its own mean over all six.
    paired = list(csv.DictReader(open(os.path.join(out, "real_vs_peers_paired.csv"))))
    for m in ("rfidray nlls, calibrated", "rfidray nlls, uncalibrated"):
        for peer in ("Tagoram", "MobiTagbot", "RF-Scanner", "STPP (x only)"):
            row = [x for x in paired if x["method"] == m and x["peer"] == peer]
            if len(row) != 1 or int(row[0]["tags"]) != 6:
                failures.append("real_vs_peers_paired.csv: %s against %s: %s" % (m, peer, row))
            elif m in peers and peer in peers and not (
                    abs(float(row[0]["mean_mm"]) - float(peers[m]["mean_mm"])) < 1e-3 and
                    abs(float(row[0]["peer_mean_mm"]) - float(peers[peer]["mean_mm"])) < 1e-3):
                failures.append("paired means %s / %s, unpaired %s / %s" % (row[0]["mean_mm"], row[0]["peer_mean_mm"],
                                                                             peers[m]["mean_mm"], peers[peer]["mean_mm"]))
            if len(row) == 1:
                d, lo, hi = (float(row[0][k]) for k in ("difference_mm", "difference_low_mm", "difference_high_mm"))
                if not (abs(d - (float(row[0]["mean_mm"]) - float(row[0]["peer_mean_mm"]))) < 1e-3 and lo <= d <= hi):
                    failures.append("paired difference %s not the difference of the means or outside (%s, %s)" % (d, lo, hi))
    # The interval resamples whole runs: two runs whose tags differ by +10 and -10 mm give -10 ... +10 (run means
    # picked twice), where resampling the six tags one by one would rarely reach the ends; equal differences give
    # a point; one run, no interval.
    sys.path.insert(0, os.path.join(source, "bench"))
    import real_data
    lo, hi = real_data.paired_difference_interval({("a", t): 10.0 for t in "xyz"} | {("b", t): -10.0 for t in "xyz"})
    if (lo, hi) != (-10.0, 10.0):
        failures.append("interval over runs: (%s, %s), expected (-10, 10)" % (lo, hi))
    lo, hi = real_data.paired_difference_interval({("a", "x"): 3.0, ("b", "x"): 3.0, ("c", "y"): 3.0})
    if (lo, hi) != (3.0, 3.0):
        failures.append("interval of equal differences: (%s, %s)" % (lo, hi))
    if not all(math.isnan(v) for v in real_data.paired_difference_interval({("a", "x"): 1.0, ("a", "y"): 2.0})):
        failures.append("one run gave an interval")
    # --peer-results: the peers' rows from the kept results of the run above, not run again: the same rows.
    again = os.path.join(root, "again")
    base = [sys.executable, os.path.join(source, "bench", "real_data.py"), "--adarf", root, "--rfidray", rfidray,
            "--datasets", "1", "--no-sim", "--calibration", os.path.join(out, "antenna.yaml")]
    r = subprocess.run(base + ["-o", again, "--keep", keep, "--peer-results", keep], capture_output=True, text=True)
    if r.returncode != 0:
        failures.append("--peer-results: exited %d: %s" % (r.returncode, r.stderr[-500:]))
    else:
        reread = {row["method"]: row for row in csv.DictReader(open(os.path.join(again, "real_vs_peers.csv")))}
        for m in ("Tagoram", "MobiTagbot", "RF-Scanner", "STPP (x only)"):
            if m in peers and reread.get(m) != peers[m]:
                failures.append("--peer-results: %s row %s, was %s" % (m, reread.get(m), peers[m]))
    missing = os.path.join(root, "no-such-keep")
    r = subprocess.run(base + ["-o", again, "--peer-results", missing], capture_output=True, text=True)
    if r.returncode != 2 or "D1_peers.json" not in r.stderr:
        failures.append("--peer-results without the file: exit %d, %r (expected 2 naming the file)" % (r.returncode, r.stderr[-300:]))
    for f in failures:
        print("FAIL: " + f)
    print("real_data pipeline: " + ("FAILED" if failures else "ok"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
