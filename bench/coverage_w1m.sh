#!/usr/bin/env bash
# Coverage benchmark (README, "Planning a deployment"): a read-coverage map of the 1 M-triangle parametric warehouse
# (`rfidray gen-warehouse --rows 20 --racks 60 --shelves 5 --tessellation 3`, 1.08 M triangles) at 5 cm over a
# 50 m × 50 m part of its floor at one height (1000 × 1000 = 10^6 cells), one fixed antenna, exact single-bounce:
#   (a) one process, 2 OpenMP threads;  (b) 2 MPI ranks × 1 thread (mpirun), whose CSV must equal (a)'s.
# Prints the "coverage" time rfidray reports (the map itself: scene loading / BVH build and file output are
# reported apart) for each of N runs and their median. With BASELINE (another rfidray binary, e.g. of an older
# commit), every run also runs it, interleaved (baseline then this build, same configuration), checks that both
# write the same CSV, and prints the ratio of the medians, which a shared machine's load affects less than the
# times themselves. Not run by ctest (minutes). Usage:
#   bench/coverage_w1m.sh [BUILD_DIR (build)] [N (3)] [OUT_LOG (bench/results/coverage_w1m.log)] [BASELINE]
set -euo pipefail
build=${1:-build}
runs=${2:-3}
log=${3:-bench/results/coverage_w1m.log}
baseline=${4:-}
rfidray=$(realpath "$build/rfidray")
[ -n "$baseline" ] && baseline=$(realpath "$baseline")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$rfidray" gen-warehouse --preset parametric --rows 20 --racks 60 --shelves 5 --tessellation 3 -o "$work/w1m.obj" >/dev/null
# W1M_CHANNEL: the channel level (the benchmark: single-bounce; `full` on a small W1M_EXTENT measures that level's
# time per cell and the 2-rank identity there).
cat > "$work/w1m.yaml" <<YAML
name: w1m coverage benchmark
channel: ${W1M_CHANNEL:-single-bounce}
model: physical
scene:
  meshes:
    - {file: w1m.obj}
antennas:
  # In the aisle between the rack rows at x = 24…25 and 28…29, 2 m high, facing +X.
  - {name: fixed, position: [26.5, 85.0, 2.0], yaw_deg: 0, pattern: {kind: patch, gain_dbi: 6, beamwidth_deg: 70}}
YAML
# W1M_EXTENT shrinks the map, W1M_STEP coarsens it (a sample of the same extent): quick checks and other levels.
args=("$work/w1m.yaml" --plane z=1.2 --extent "${W1M_EXTENT:-0,60,50,110}" --step "${W1M_STEP:-0.05}" --no-png)
median() { sort -g | awk '{a[NR]=$1} END{print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
coverage_s() { sed -n 's/.*coverage \([0-9.]*\) s.*/\1/p'; }
have_mpi=0
command -v mpirun >/dev/null && have_mpi=1
# run BINARY LABEL I: both configurations; appends the times to LABEL_one / LABEL_two.
declare -A times
run() {
  local bin=$1 label=$2 i=$3 out
  out=$("$bin" coverage "${args[@]}" --threads 2 -o "$work/$label.one" 2>/dev/null)
  echo "$label: 1 rank x 2 threads, run $i: $(echo "$out" | grep 'wall time'); load $(cut -d' ' -f1 /proc/loadavg)"
  times[${label}_one]+="$(echo "$out" | coverage_s) "
  if [ $have_mpi = 1 ]; then
    out=$(mpirun -n 2 --oversubscribe --allow-run-as-root "$bin" coverage "${args[@]}" --threads 1 -o "$work/$label.two" 2>/dev/null)
    echo "$label: 2 ranks x 1 thread, run $i: $(echo "$out" | grep 'wall time'); load $(cut -d' ' -f1 /proc/loadavg)"
    times[${label}_two]+="$(echo "$out" | coverage_s) "
    cmp -s "$work/$label.one/coverage.csv" "$work/$label.two/coverage.csv" && echo "  coverage.csv identical (1 rank vs 2 ranks)" \
      || echo "  coverage.csv DIFFERS between 1 and 2 ranks"
  fi
}
med() { printf '%s\n' ${times[$1]} | median; }
{
  echo "# bench/coverage_w1m.sh on $(hostname), $(date -u +%FT%TZ), $(nproc) cores, load average: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# $(head -1 "$work/w1m.obj" 2>/dev/null || true)"
  echo "# this build: $rfidray${baseline:+; baseline: $baseline}"
  for i in $(seq "$runs"); do
    if [ -n "$baseline" ]; then
      run "$baseline" baseline "$i"
    fi
    run "$rfidray" build "$i"
    if [ -n "$baseline" ]; then
      cmp -s "$work/baseline.one/coverage.csv" "$work/build.one/coverage.csv" \
        && echo "  coverage.csv identical (baseline vs this build)" || echo "  coverage.csv DIFFERS from the baseline's"
    fi
  done
  echo "cells: $(($(wc -l < "$work/build.one/coverage.csv") - 1))"
  for label in ${baseline:+baseline} build; do
    echo "median coverage time, $label, 1 rank x 2 threads: $(med ${label}_one) s (of $runs)"
    [ $have_mpi = 1 ] && echo "median coverage time, $label, 2 ranks x 1 thread: $(med ${label}_two) s (of $runs)"
  done
  if [ -n "$baseline" ]; then
    echo "ratio of medians, this build / baseline: 1 rank x 2 threads $(awk -v a="$(med build_one)" -v b="$(med baseline_one)" 'BEGIN{printf "%.3f", a/b}')"
    [ $have_mpi = 1 ] && echo "ratio of medians, this build / baseline: 2 ranks x 1 thread $(awk -v a="$(med build_two)" -v b="$(med baseline_two)" 'BEGIN{printf "%.3f", a/b}')"
  fi
  echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
} | tee "$log"
