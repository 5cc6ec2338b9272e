#!/usr/bin/python3
"""Chart of bench_gen2's throughput.csv: reads/s of all tags and reads per tag per second against the tag
population, one line per Gen2 preset.

    /usr/bin/python3 bench/gen2_throughput_plot.py bench/results/gen2/throughput.csv bench/results/gen2/throughput.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    rows = list(csv.DictReader(open(argv[1], newline="")))
    presets = sorted({r["preset"] for r in rows})
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for p in presets:
        sel = [r for r in rows if r["preset"] == p]
        n = [int(r["tags"]) for r in sel]
        ax1.plot(n, [float(r["reads_per_s"]) for r in sel], marker="o", label=p)
        ax2.plot(n, [float(r["reads_per_tag_per_s"]) for r in sel], marker="o", label=p)
    for ax in (ax1, ax2):
        ax.set_xscale("log")
        ax.set_xlabel("tags in the field")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    ax1.set_ylabel("reads/s (all tags)")
    ax2.set_yscale("log")
    ax2.set_ylabel("reads per tag per second")
    fig.suptitle("Gen2 inventory, session 0, dual target, Q algorithm; ideal channel, every tag powered")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
