#!/usr/bin/env bash
# Runs every libFuzzer harness of a RFIDRAY_FUZZ build for a bounded time, two at a time, each from a copy of
# its seed corpus (tests/fuzz/corpus/<name>/). Fails when any harness finds a crash, a sanitizer report, an
# invariant violation (tests/fuzz/fuzz_support.h), a timeout or a memory blow-up; the input is left in
# <build>/fuzz/findings/<name>/ and its path printed. Prints executions and corpus size per harness.
# Usage: tests/fuzz/run.sh BUILD_DIR [SECONDS_PER_HARNESS=60] [--merge]
#   --merge: afterwards, merge what each run found into tests/fuzz/corpus/<name>/ (libFuzzer -merge=1 keeps only
#   inputs that add coverage), so the corpus grows in the repository.
set -uo pipefail
build=${1:?usage: run.sh BUILD_DIR [SECONDS] [--merge]}
seconds=${2:-60}
merge=${3:-}
here=$(cd "$(dirname "$0")" && pwd)
work="$build/fuzz"
mkdir -p "$work"
harnesses=()
for exe in "$build"/tests/fuzz/fuzz_*; do
  name=$(basename "$exe"); name=${name#fuzz_}
  case "$name" in replay_*) continue ;; esac
  [ -x "$exe" ] && harnesses+=("$name")
done
if [ ${#harnesses[@]} -eq 0 ]; then
  echo "fuzz: no harnesses in $build/tests/fuzz (configure with -DRFIDRAY_FUZZ=ON and clang)" >&2
  exit 2
fi

run_one() {
  local name=$1
  local corpus="$work/corpus/$name" findings="$work/findings/$name"
  rm -rf "$corpus" "$findings"; mkdir -p "$corpus" "$findings"
  cp "$here/corpus/$name"/* "$corpus"/
  # Inputs up to 64 kB; an input taking > 10 s or > 2 GB is a finding (the limits README promises).
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$build/tests/fuzz/fuzz_$name" -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" > "$work/$name.log" 2>&1
  local rc=$?
  local execs; execs=$(grep -m1 'stat::number_of_executed_units' "$work/$name.log" | awk '{print $2}')
  local size; size=$(ls "$corpus" | wc -l)
  if [ $rc -ne 0 ]; then
    echo "fuzz: $name FAILED (exit $rc) after ${execs:-?} executions; input(s): $(ls "$findings"/* 2>/dev/null | tr '\n' ' ')"
    grep -m5 -E 'ERROR|invariant|runtime error|SUMMARY' "$work/$name.log"
    return 1
  fi
  echo "fuzz: $name ok: ${execs} executions in ${seconds} s, corpus ${size} inputs (seeds $(ls "$here/corpus/$name" | wc -l))"
  if [ "$merge" = "--merge" ]; then
    "$build/tests/fuzz/fuzz_$name" -merge=1 -max_len=65536 "$here/corpus/$name" "$corpus" > "$work/$name.merge.log" 2>&1
  fi
}

failed=0
pids=()
names=()
for name in "${harnesses[@]}"; do
  run_one "$name" > "$work/$name.summary" 2>&1 &
  pids+=($!); names+=("$name")
  # Two at a time: the machines this runs on have two cores.
  if [ ${#pids[@]} -ge 2 ]; then
    wait "${pids[0]}" || failed=1; cat "$work/${names[0]}.summary"; pids=("${pids[@]:1}"); names=("${names[@]:1}")
  fi
done
for i in "${!pids[@]}"; do wait "${pids[$i]}" || failed=1; cat "$work/${names[$i]}.summary"; done
exit $failed
