#!/bin/bash
# bash exact_blocks_ab.sh OLD/bench_sweep NEW/bench_sweep > exact_blocks_ab.log
# old = 8abc1c0 (before the per-block group search), new = its successor (the per-block search); interleaved rounds.
declare -A BIN=([old]="$1" [new]="$2")
for r in 1 2 3; do
  for cfg in "2 10000 4" "1 10000 4" "1 100000 1" "2 100000 1" "1 1000 16"; do
    set -- $cfg
    for b in old new; do
      echo "round $r threads $1 tags $2 poses $3 $b $("${BIN[$b]}" --scenes w1m --settings single-bounce --threads $1 --tags $2 --poses $3 --runs 5 --no-tags-sweep --out "/tmp/bs_$b.out" 2>&1 | grep links/s | awk '{print $4, "links/s", $11, "rays/link"}')"
    done
  done
done
