#!/usr/bin/python3
"""The paper warehouse under a Gen2 reader as the tag population grows: for the paper's ten tags, reads per tag
and the localization error of `rfidray localize` (the paper's hyperbolic method, nlls and sar), against the tick
model (15 Hz, scenes/paper_warehouse.yaml, mobile antenna).

    /usr/bin/python3 bench/gen2_paper_localization.py build/rfidray OUT_DIR > bench/results/gen2/paper_localization.md
"""
import csv
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES = [
    ("tick model, 15 Hz (paper)", ROOT / "scenes/paper_warehouse.yaml", 10),
    ("Gen2 dense_reader_m4, 10 tags", ROOT / "bench/results/gen2/paper_gen2_10.yaml", 10),
    ("Gen2 dense_reader_m4, 100 tags", ROOT / "bench/results/gen2/paper_gen2_100.yaml", 100),
    ("Gen2 dense_reader_m4, 1000 tags", ROOT / "bench/results/gen2/paper_gen2_1000.yaml", 1000),
]
PAPER_TAGS = [f"tag{i}" for i in range(1, 11)]


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    rfidray, out = argv[1], Path(argv[2])
    print("| case | tags | reads per paper tag (median, min) | method | paper tags located | error mm (median, max) |")
    print("|---|---|---|---|---|---|")
    for name, scenario, n in CASES:
        d = out / scenario.stem
        subprocess.run([rfidray, "simulate", str(scenario), "-o", str(d), "-q"], check=True)
        reads = {t: 0 for t in PAPER_TAGS}
        with open(d / "mobile.csv", newline="") as f:
            for row in csv.DictReader(f):
                if row["name"] in reads:
                    reads[row["name"]] += 1
        counts = list(reads.values())
        res = subprocess.run([rfidray, "localize", str(d / "mobile.csv"), "--truth", str(d / "tags.csv"),
                              "--height-known", "--mirror-prior", "truth", "--method", "all"],
                             capture_output=True, text=True, check=True).stdout.splitlines()
        for method in ("hyperbolic", "nlls", "sar"):
            errs = []
            for line in res[1:]:
                f = line.split()
                if len(f) >= 7 and f[0] in reads and f[1] == method and f[2] == "ok":
                    errs.append(float(f[6]))
            err = f"{statistics.median(errs):.1f}, {max(errs):.1f}" if errs else "-"
            print(f"| {name} | {n} | {statistics.median(counts):.0f}, {min(counts)} | {method} | {len(errs)} / 10 | {err} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
