#!/usr/bin/env python3
"""Phase and RSSI of one tag along the paper's robot path, free space against the warehouse's multipath.

Runs scenes/paper_warehouse.yaml twice with the physical reader model (the paper model ignores the channel):
once on the ideal (free-space) channel and once ray-traced (single-bounce), same seed, and plots the mobile
antenna's reads of one tag against time. Headless: matplotlib's Agg backend writes a PNG.

    PYTHONPATH=build/python python3 python/examples/robot_path_phase_rssi.py -o out/phase_rssi.png
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import rfidray  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default=str(ROOT / "scenes" / "paper_warehouse.yaml"))
    parser.add_argument("--antenna", default="mobile")
    parser.add_argument("--tag", default="tag8")
    parser.add_argument("--duration", type=float, default=None, help="simulated seconds (default: the whole path)")
    parser.add_argument("-o", "--output", default="phase_rssi.png")
    args = parser.parse_args()

    runs = {}
    for level in ("ideal", "single-bounce"):
        sim = rfidray.simulate(args.scenario, model="physical", channel=level, duration_s=args.duration)
        if args.antenna not in sim:
            raise SystemExit(f"no antenna '{args.antenna}' (the scenario has {', '.join(sim)})")
        reads = sim[args.antenna]
        runs[level] = reads[reads["name"] == args.tag]
    if all(len(r) == 0 for r in runs.values()):
        raise SystemExit(f"{args.antenna} never reads {args.tag} in this run")

    fig, (ax_phase, ax_rssi) = plt.subplots(2, 1, sharex=True, figsize=(9, 6), constrained_layout=True)
    style = {"ideal": dict(color="#1f77b4", label="ideal (free space)"),
             "single-bounce": dict(color="#d62728", label="single-bounce (warehouse multipath)")}
    for level, reads in runs.items():
        ax_phase.plot(reads["time"], reads["phase"], ".", ms=2.5, **style[level])
        ax_rssi.plot(reads["time"], reads["rssi"], ".", ms=2.5, **style[level])
    ax_phase.set_ylabel("phase (rad)")
    ax_phase.set_ylim(0, 2 * np.pi)
    ax_rssi.set_ylabel("RSSI (dBm)")
    ax_rssi.set_xlabel("time (s)")
    ax_phase.set_title(f"{args.tag} read by the {args.antenna} antenna along the robot path")
    ax_phase.legend(loc="upper right", markerscale=4)
    for ax in (ax_phase, ax_rssi):
        ax.grid(alpha=0.3)
    out = pathlib.Path(args.output)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    counts = ", ".join(f"{level}: {len(r)} reads" for level, r in runs.items())
    print(f"{out}: {counts}")


if __name__ == "__main__":
    main()
