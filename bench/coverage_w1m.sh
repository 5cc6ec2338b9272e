#!/usr/bin/env bash
# Coverage benchmark (README, "Planning a deployment"): a read-coverage map of the 1 M-triangle parametric warehouse
# (`rfidray gen-warehouse --rows 20 --racks 60 --shelves 5 --tessellation 3`, 1.08 M triangles) at 5 cm over a
# 50 m × 50 m part of its floor at one height (1000 × 1000 = 10^6 cells), one fixed antenna, exact single-bounce:
#   (a) one process, 2 OpenMP threads;  (b) 2 MPI ranks × 1 thread (mpirun), whose CSV must equal (a)'s.
# Prints the "coverage" time rfidray reports (the map itself: scene loading / BVH build and file output are
# reported apart) for each of N runs and their median. Not run by ctest (minutes). Usage:
#   bench/coverage_w1m.sh [BUILD_DIR (build)] [N (3)] [OUT_LOG (bench/results/coverage_w1m.log)]
set -euo pipefail
build=${1:-build}
runs=${2:-3}
log=${3:-bench/results/coverage_w1m.log}
rfidray=$(realpath "$build/rfidray")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$rfidray" gen-warehouse --preset parametric --rows 20 --racks 60 --shelves 5 --tessellation 3 -o "$work/w1m.obj" >/dev/null
cat > "$work/w1m.yaml" <<'YAML'
name: w1m coverage benchmark
channel: single-bounce
model: physical
scene:
  meshes:
    - {file: w1m.obj}
antennas:
  # In the aisle between the rack rows at x = 24…25 and 28…29, 2 m high, facing +X.
  - {name: fixed, position: [26.5, 85.0, 2.0], yaw_deg: 0, pattern: {kind: patch, gain_dbi: 6, beamwidth_deg: 70}}
YAML
args=("$work/w1m.yaml" --plane z=1.2 --extent 0,60,50,110 --step 0.05 --no-png)
median() { sort -g | awk '{a[NR]=$1} END{print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
coverage_s() { sed -n 's/.*coverage \([0-9.]*\) s.*/\1/p'; }
{
  echo "# bench/coverage_w1m.sh on $(hostname), $(date -u +%FT%TZ), $(nproc) cores, load average: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# $(head -1 "$work/w1m.obj" 2>/dev/null || true)"
  one=(); two=()
  for i in $(seq "$runs"); do
    out=$("$rfidray" coverage "${args[@]}" --threads 2 -o "$work/one" 2>/dev/null)
    echo "1 rank x 2 threads, run $i: $(echo "$out" | grep 'wall time')"
    one+=("$(echo "$out" | coverage_s)")
    if command -v mpirun >/dev/null; then
      out=$(mpirun -n 2 --oversubscribe --allow-run-as-root "$rfidray" coverage "${args[@]}" --threads 1 -o "$work/two" 2>/dev/null)
      echo "2 ranks x 1 thread, run $i: $(echo "$out" | grep 'wall time')"
      two+=("$(echo "$out" | coverage_s)")
      cmp -s "$work/one/coverage.csv" "$work/two/coverage.csv" && echo "  coverage.csv identical (1 rank vs 2 ranks)" \
        || echo "  coverage.csv DIFFERS between 1 and 2 ranks"
    fi
  done
  echo "cells: $(($(wc -l < "$work/one/coverage.csv") - 1))"
  echo "median coverage time, 1 rank x 2 threads: $(printf '%s\n' "${one[@]}" | median) s (of $runs)"
  [ ${#two[@]} -gt 0 ] && echo "median coverage time, 2 ranks x 1 thread: $(printf '%s\n' "${two[@]}" | median) s (of $runs)"
  echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
} | tee "$log"
