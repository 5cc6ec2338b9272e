#!/bin/bash
# The runs of this folder: bench_levels of two builds, alternated, three times (README: "Thin posts' legs").
# Usage, from the repository's root: bash run.sh BASE_BENCH_LEVELS NEW_BENCH_LEVELS OUT_DIR
set -euo pipefail
base=$1 new=$2 out=$3
mkdir -p "$out"
for i in 1 2 3; do
  for v in base new; do
    bin=$base; [ $v = new ] && bin=$new
    "$bin" --scenes paper --tags 250 --poses 8 --runs 1 --out "$out/paper_${v}_$i" > "$out/paper_${v}_$i.log" 2>&1
    "$bin" --scenes w1m --tags 25 --poses 4 --runs 1 --reference-candidates exact --out "$out/w1m_${v}_$i" > "$out/w1m_${v}_$i.log" 2>&1
  done
done
