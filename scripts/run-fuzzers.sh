#!/usr/bin/env bash
# Runs every libFuzzer target of a `make sanitize` build for a bounded time, starting from
# the seeds the project makes (bivo_fuzz_seeds) and the stored regressions. Fails on any
# crash, sanitizer report, uncaught exception, leak, OOM or timeout; the input that caused
# it is kept under BUILD/fuzz/findings/<target>/ -- copy it to tests/fuzz/regressions/<target>/
# and it is replayed by every ctest run from then on.
#
# usage: scripts/run-fuzzers.sh BUILD_DIR SECONDS_PER_TARGET [TARGET...]
#   (or with FUZZ_RUNS=N instead of a time bound: that many executions per target;
#    FUZZ_SEEDS_BIN=path: the seed writer of another build, e.g. the default one, when BUILD_DIR
#    holds only the fuzz targets -- `make fuzz-ci`)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:?build folder of make sanitize}
seconds=${2:-30}
shift $(( $# >= 2 ? 2 : $# ))
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then targets=(tum_list trajectory png conic_json cbf); fi

work="$build/fuzz"
rm -rf "$work/seeds"
"${FUZZ_SEEDS_BIN:-$build/tests/fuzz/bivo_fuzz_seeds}" "$work/seeds"
bound=(-max_total_time="$seconds")
if [ -n "${FUZZ_RUNS:-}" ]; then bound=(-runs="$FUZZ_RUNS"); fi

# Targets run side by side, FUZZ_JOBS at a time (default: the processors here); each is one
# process on one core, so the time bound is each target's, and the reports come in order.
jobs=${FUZZ_JOBS:-$(nproc)}
fuzz_one() {
  local t=$1 corpus="$work/corpus/$1" findings="$work/findings/$1" log="$work/fuzz_$1.log"
  mkdir -p "$corpus" "$findings"
  # -timeout: seconds per input; -rss_limit_mb: an OOM is a finding; the first folder receives
  # new coverage, the others (seeds, regressions) are read only.
  if "$build/tests/fuzz/fuzz_$t" "${bound[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
      -print_final_stats=1 -artifact_prefix="$findings/" \
      "$corpus" "$work/seeds/$t" "tests/fuzz/regressions/$t" >"$log" 2>&1; then
    echo ok >"$work/status_$t"
  else
    echo FAILED >"$work/status_$t"
  fi
}
for t in "${targets[@]}"; do
  rm -f "$work/status_$t"
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  fuzz_one "$t" &
done
wait

failed=0
for t in "${targets[@]}"; do
  corpus="$work/corpus/$t" findings="$work/findings/$t" log="$work/fuzz_$t.log"
  status=$(cat "$work/status_$t" 2>/dev/null || echo FAILED)
  [ "$status" = ok ] || failed=1
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  speed=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -1 | grep -o '[0-9]*' || echo "?")
  echo "fuzz_$t: $status, $runs executions ($speed/s), coverage $cov edges, corpus $(ls "$corpus" | wc -l) inputs"
  if [ "$status" = FAILED ]; then
    tail -n 40 "$log"
    ls -l "$findings"
  fi
done
exit $failed
