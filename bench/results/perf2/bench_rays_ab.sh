#!/bin/bash
# Interleaved old / new bench_rays on paper and w1m (medians of 3 repetitions per benchmark).
#   bash bench/results/perf2/bench_rays_ab.sh OLD_BENCH_DIR NEW_BENCH_DIR > log
OLD=${1:?old bench dir} NEW=${2:?new bench dir}
for rep in 1 2; do
  for which in old new; do
    B=$([ $which = old ] && echo $OLD || echo $NEW)
    echo "=== rep $rep $which load $(cut -d' ' -f1-3 /proc/loadavg) $(date -u +%H:%M:%S)"
    $B/bench_rays --scenes paper,w1m --benchmark_filter='occluded|los_ours' --benchmark_repetitions=3 --benchmark_report_aggregates_only=true 2>&1 | grep -E "median|width|segments"
  done
done
