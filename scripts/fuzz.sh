#!/usr/bin/env bash
# Runs every libFuzzer target in <bin dir> for FUZZ_SECONDS each (default 60) on a copy of its
# seed corpus, so tests/corpus/ only holds what is committed: out/fuzz/<target>/corpus grows with
# what the fuzzer finds, out/fuzz/<target>/ collects crash-*, leak-*, timeout-* and oom-* inputs
# and the log. Prints one summary line per target; exits 1 when any target found something.
# Usage: scripts/fuzz.sh <bin dir> [target...]   (`make fuzz` builds build-fuzz/bin and runs this)
set -uo pipefail

bin=${1:?usage: scripts/fuzz.sh <bin dir> [target...]}
shift
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds=${FUZZ_SECONDS:-60}
if [ $# -gt 0 ]; then
  targets=("$@")
else
  targets=()
  for t in "$bin"/*_fuzz; do targets+=("$(basename "$t" _fuzz)"); done
fi

failed=0
summary=()
for target in "${targets[@]}"; do
  out="$root/out/fuzz/$target"
  rm -rf "$out"
  mkdir -p "$out/corpus"
  cp "$root/tests/corpus/$target"/* "$out/corpus/"
  echo "fuzz: $target for ${seconds}s (log: out/fuzz/$target/fuzz.log)" >&2
  start=$(date +%s)
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb / -malloc_limit_mb: a reader asking
  # for 2 GB is as much a bug as a crash. -close_fd_mask=1 drops the readers' stdout, not the
  # sanitizers' reports on stderr.
  "$bin/${target}_fuzz" "$out/corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -malloc_limit_mb=2048 -close_fd_mask=1 -print_final_stats=1 -artifact_prefix="$out/" > "$out/fuzz.log" 2>&1
  status=$?
  elapsed=$(($(date +%s) - start))
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/fuzz.log" | tail -1)
  found=$(find "$out" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
  line=$(printf '%-12s %10s runs %5ss  corpus %4d  findings %d' "$target" "${runs:-?}" "$elapsed" \
    "$(find "$out/corpus" -type f | wc -l)" "$found")
  if [ "$status" -ne 0 ] || [ "$found" -ne 0 ]; then
    failed=1
    line+="  FAILED (exit $status): $(grep -m1 -E '^==[0-9]+==ERROR|^SUMMARY|runtime error|ERROR: libFuzzer' "$out/fuzz.log")"
  fi
  summary+=("$line")
done

echo "fuzz summary (${seconds}s per target):"
printf '  %s\n' "${summary[@]}"
exit $failed
