#!/bin/bash
# Interleaved old / new bench_sweep runs (links/s at 100 and 100 000 tags per pose, los and single-bounce,
# w1m and paper, 2 threads); take the median of the 3 invocations per cell.
#   bash bench/results/perf2/pose_tax_ab.sh OLD_BENCH_DIR NEW_BENCH_DIR > log
# (each dir holds a bench_sweep binary, e.g. a build of main's commit and build/bench)
OLD=${1:?old bench dir} NEW=${2:?new bench dir}
for rep in 1 2 3; do
  for scene in w1m paper; do
    for tags in 100 100000; do
      for which in old new; do
        B=$([ $which = old ] && echo $OLD || echo $NEW)
        echo "=== rep $rep $which $scene tags $tags load $(cut -d' ' -f1-3 /proc/loadavg) $(date -u +%H:%M:%S)"
        $B/bench_sweep --scenes $scene --settings los,single-bounce --threads 2 --tags $tags --poses 4 --runs 5 --no-tags-sweep --out ${TMPDIR:-/tmp}/pose_tax_$which 2>&1 | grep -v -E "^Warning|gnuplot|charts not|\.gp"
      done
    done
  done
done
