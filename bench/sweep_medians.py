#!/usr/bin/env python3
"""Medians over several bench_sweep logs, as the README's speed tables give them.

bench_sweep prints, per scene and setting, the median of its own --runs; one invocation still swings with
what else the machine does. Run it N times and give the logs here:

    for i in 1 2 3 4 5; do ./build/bench/bench_sweep --out /tmp/sweep$i > /tmp/sweep$i.log; done
    python3 bench/sweep_medians.py /tmp/sweep?.log

Prints two Markdown tables: links/s per scene and level (median over the logs, with the range), and the
tag sweep on w1m (links/s at 100 ... 100 000 tags per pose, and the 100-tag figure over the 100 000-tag one).
Exits 2 naming the file and line when a log has no figures or a line it cannot read.
"""
import re
import statistics
import sys
from collections import OrderedDict, defaultdict

SCENE = re.compile(r"^(\w+): (\d+) triangles, .*scene \+ BVH build ([\d.]+) s; Embree (\d+) B/triangle, "
                   r"resident (\d+) B/triangle")
LEVEL = re.compile(r"^  (.+?)\s+(\d) threads?\s+(\d+) links/s median .*?\s([\d.]+) rays/link")
SWEEP = re.compile(r"^  (.+?)\s+(\d) threads?\s+(\d+) tags\s+(\d+) links/s\s+([\d.]+) rays/link")


def die(message):
    print(f"sweep_medians: {message}", file=sys.stderr)
    sys.exit(2)


def parse(path):
    scenes, levels, sweep = OrderedDict(), OrderedDict(), OrderedDict()
    scene = None
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            m = SCENE.match(line)
            if m:
                scene = m.group(1)
                scenes[scene] = dict(triangles=int(m.group(2)), build_s=float(m.group(3)),
                                     embree_b=int(m.group(4)), resident_b=int(m.group(5)))
                continue
            m = SWEEP.match(line)
            if m:
                sweep[(m.group(1), int(m.group(3)))] = int(m.group(4))
                continue
            m = LEVEL.match(line)
            if m:
                if scene is None:
                    die(f"{path}:{n}: a figure before any scene line")
                levels[(scene, m.group(1), int(m.group(2)))] = (int(m.group(3)), float(m.group(4)))
    if not levels:
        die(f"{path}: no links/s figures (is it a bench_sweep log?)")
    return scenes, levels, sweep


def k(x):
    return f"{x / 1e6:.2f} M" if x >= 1e6 else f"{x / 1e3:.0f} k"


def main():
    if len(sys.argv) < 2:
        die("usage: sweep_medians.py BENCH_SWEEP.log [...]")
    logs = []
    for p in sys.argv[1:]:
        try:
            logs.append(parse(p))
        except (OSError, UnicodeDecodeError) as e:
            die(f"{p}: {e}")
    scenes, levels, sweep = OrderedDict(), OrderedDict(), OrderedDict()
    for s, lv, sw in logs:
        for key, v in s.items():
            scenes.setdefault(key, []).append(v)
        for key, v in lv.items():
            levels.setdefault(key, []).append(v)
        for key, v in sw.items():
            sweep.setdefault(key, []).append(v)

    def med(values):
        return statistics.median(values)

    settings = list(OrderedDict.fromkeys(key[1] for key in levels))
    print(f"links/s, median of {len(logs)} bench_sweep runs (range in brackets)\n")
    print("| scene | triangles | " + " | ".join(f"{s} (1 / 2 threads)" for s in settings) +
          " | rays/link | scene + BVH build | Embree / resident B per triangle |")
    print("|---" * (len(settings) + 5) + "|")
    for scene, infos in scenes.items():
        cells = []
        rays = []
        for s in settings:
            parts = []
            for t in (1, 2):
                v = levels.get((scene, s, t))
                if v:
                    rates = [x[0] for x in v]
                    parts.append(f"{k(med(rates))} [{k(min(rates))}–{k(max(rates))}]")
            cells.append(" / ".join(parts) if parts else "–")
            v = levels.get((scene, s, 1)) or levels.get((scene, s, 2))
            if v and v[0][1] != 1.0:
                rays.append(f"{s}: {v[0][1]:.2f}")
        print(f"| {scene} | {infos[0]['triangles']} | " + " | ".join(cells) +
              f" | {'; '.join(rays)} | {med([i['build_s'] for i in infos]):.3f} s | "
              f"{med([i['embree_b'] for i in infos]):.0f} / {med([i['resident_b'] for i in infos]):.0f} |")
    if sweep:
        counts = sorted(OrderedDict.fromkeys(key[1] for key in sweep))
        sweep_settings = list(OrderedDict.fromkeys(key[0] for key in sweep))
        print(f"\nw1m, 2 threads, links/s vs tags per pose (median of {len(logs)})\n")
        print("| setting | " + " | ".join(f"{c} tags" for c in counts) +
              f" | {counts[0]} / {counts[-1]} per run (median) |")
        print("|---" * (len(counts) + 2) + "|")
        for s in sweep_settings:
            row = [med(sweep[(s, c)]) if (s, c) in sweep else None for c in counts]
            ratios = [a / b for a, b in zip(sweep.get((s, counts[0]), []), sweep.get((s, counts[-1]), []))]
            print(f"| {s} | " + " | ".join(k(x) if x else "–" for x in row) +
                  (f" | {med(ratios):.2f} ({min(ratios):.2f}–{max(ratios):.2f}) |" if ratios else " | – |"))


if __name__ == "__main__":
    main()
