#!/usr/bin/env python3
"""bench/sweep_medians.py: the medians the README's speed tables are made of.

1. Three logs this test writes in bench_sweep's format, with known figures: the printed table must hold the
   median of each point (not the mean, not the first log), its range, and the tag sweep's per-run ratio.
2. When a bench_sweep binary is given, two tiny real runs of it: the script must read what bench_sweep prints
   today (a change of bench_sweep's output format breaks this test, not the README's next update).
3. Bad input: a file with no figures, a missing file, no arguments — exit 2 with the file named.
Usage: test_sweep_medians.py SOURCE_DIR [BENCH_SWEEP_BINARY]"""
import os
import subprocess
import sys
import tempfile

SCENE = ("w1m: 1080090 triangles, 60005 facets, 496 planes; scene + BVH build {build} s; Embree 70 B/triangle, "
         "resident {res} B/triangle; 10000 tags x 4 poses\n")
LEVEL = ("  single-bounce            {t} thread{s}  {rate:12d} links/s median (min 1, max 2)   20.57 rays/link    "
         "0.00 culled/link, single rays\n")
SWEEP = "  los                      2 threads {n:7d} tags {rate:12d} links/s    1.00 rays/link, single rays\n"


def run(script, args):
    return subprocess.run([sys.executable, script] + args, capture_output=True, text=True, timeout=120)


def main():
    src = sys.argv[1]
    bench_sweep = sys.argv[2] if len(sys.argv) > 2 else None
    script = os.path.join(src, "bench", "sweep_medians.py")
    failures = []

    def check(cond, what):
        if not cond:
            failures.append(what)

    with tempfile.TemporaryDirectory() as tmp:
        # 1. Known figures: 2-thread rates 100 k, 300 k, 110 k -> median 110 k (the mean would be 170 k).
        logs = []
        for i, (one, two, build, res, s100, s100k) in enumerate(
                [(50000, 100000, 0.5, 110, 4000000, 5000000), (60000, 300000, 0.9, 130, 1000000, 5000000),
                 (55000, 110000, 0.7, 112, 4500000, 5000000)]):
            p = os.path.join(tmp, "run%d.log" % i)
            with open(p, "w", encoding="utf-8") as f:
                f.write(SCENE.format(build=build, res=res))
                f.write(LEVEL.format(t=1, s=" ", rate=one))
                f.write(LEVEL.format(t=2, s="s", rate=two))
                f.write(SWEEP.format(n=100, rate=s100))
                f.write(SWEEP.format(n=100000, rate=s100k))
            logs.append(p)
        r = run(script, logs)
        check(r.returncode == 0, "known logs: exit %d, stderr %s" % (r.returncode, r.stderr))
        row = next((l for l in r.stdout.splitlines() if l.startswith("| w1m |")), "")
        check("55 k [50 k–60 k] / 110 k [100 k–300 k]" in row, "known logs: medians and ranges, got: " + row)
        check("single-bounce: 20.57" in row, "known logs: rays per link, got: " + row)
        check("| 0.700 s | 70 / 112 |" in row, "known logs: build time and bytes per triangle, got: " + row)
        sweep = next((l for l in r.stdout.splitlines() if l.startswith("| los |")), "")
        # per-run ratios 0.8, 0.2, 0.9 -> median 0.80, range 0.20-0.90
        check("| 0.80 (0.20–0.90) |" in sweep, "known logs: the sweep's per-run ratio, got: " + sweep)
        check(sweep.startswith("| los | 4.00 M | 5.00 M |"), "known logs: the sweep's medians, got: " + sweep)

        # 2. What bench_sweep prints today.
        if bench_sweep:
            real = []
            for i in range(2):
                out = os.path.join(tmp, "real%d" % i)
                r = subprocess.run([bench_sweep, "--out", out, "--scenes", "paper", "--tags", "50", "--poses", "2",
                                    "--runs", "1", "--settings", "los,single-bounce", "--threads", "1",
                                    "--no-tags-sweep"], capture_output=True, text=True, timeout=300)
                check(r.returncode == 0, "bench_sweep run: exit %d: %s" % (r.returncode, r.stderr[-500:]))
                p = os.path.join(tmp, "real%d.log" % i)
                with open(p, "w", encoding="utf-8") as f:
                    f.write(r.stdout)
                real.append(p)
            r = run(script, real)
            check(r.returncode == 0, "bench_sweep logs: exit %d, stderr %s" % (r.returncode, r.stderr))
            row = next((l for l in r.stdout.splitlines() if l.startswith("| paper | 1154 |")), "")
            check(row != "", "bench_sweep logs: no paper row in:\n" + r.stdout)
            check("los (1 / 2 threads)" in r.stdout and "single-bounce (1 / 2 threads)" in r.stdout,
                  "bench_sweep logs: both settings are columns:\n" + r.stdout)
            # rays per link as bench_sweep printed them (machine-independent, the same in both runs)
            with open(real[0], encoding="utf-8") as f:
                line = next((l for l in f if l.lstrip().startswith("single-bounce ") and "rays/link" in l), "")
            rays = line.split("rays/link")[0].split()[-1] if line else "?"
            check("single-bounce: " + rays in row,
                  "bench_sweep logs: rays per link %s (from %r), got: %s" % (rays, line.strip(), row))

        # 3. Bad input.
        empty = os.path.join(tmp, "empty.log")
        with open(empty, "w", encoding="utf-8") as f:
            f.write("not a bench_sweep log\n")
        for args, needle in [([empty], "empty.log"), ([os.path.join(tmp, "absent.log")], "absent.log"),
                             ([], "usage")]:
            r = run(script, args)
            check(r.returncode == 2 and needle in r.stderr,
                  "bad input %s: exit %d, stderr %r" % (args, r.returncode, r.stderr))

    for f in failures:
        print("FAIL:", f)
    print("sweep_medians: %d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
