#!/usr/bin/env bash
# Builds conftrack's libFuzzer targets (fuzz/, docs/fuzzing.md) with clang-14
# in a separate build folder and runs each for FUZZ_SECONDS seconds on a
# scratch copy of its seed corpus (the repository's corpus stays as it is).
# Prints the executions of each target; exits non-zero if a target found a
# crash (a sanitizer report, an exception other than InputError, a timeout
# or running out of memory): its input is kept in
# $FUZZ_BUILD_DIR/artifacts/<target>/.
#
# Environment:
#   FUZZ_SECONDS    seconds per target (default 60)
#   FUZZ_TARGETS    space-separated subset of the targets (default: all)
#   FUZZ_BUILD_DIR  build folder (default build-fuzz)
#   FUZZ_MAX_LEN    largest input in bytes (default 16384)
#   FUZZ_RSS_MB     memory limit per target in MB (default 2048)
#   FUZZ_TIMEOUT    seconds one input may take (default 10)
#   JOBS            parallel compile jobs and fuzzers run side by side
#                   (default: nproc)
#   CC, CXX         compilers (default clang-14, clang++-14)
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
seconds="${FUZZ_SECONDS:-60}"
build="${FUZZ_BUILD_DIR:-build-fuzz}"
max_len="${FUZZ_MAX_LEN:-16384}"
rss_mb="${FUZZ_RSS_MB:-2048}"
timeout="${FUZZ_TIMEOUT:-10}"
jobs="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
all_targets="trackml_hits trackml_hits_gz trackml_truth trackml_particles
  submission track_files detector_toml chain_toml generator_toml hepmc_text
  performance_data"
targets="${FUZZ_TARGETS:-$all_targets}"

launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
# -O2 with assertions (no NDEBUG): an assertion failure is a finding too.
CC="${CC:-clang-14}" CXX="${CXX:-clang++-14}" cmake -S . -B "$build" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1" \
  -DCONFTRACK_BUILD_FUZZERS=ON -DCONFTRACK_BUILD_TESTS=OFF \
  -DCONFTRACK_BUILD_BENCHMARKS=OFF "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$jobs" --target conftrack_fuzzers

dict_of() {
  case "$1" in
    *_toml) echo fuzz/dict/toml.dict ;;
    hepmc_text) echo fuzz/dict/hepmc.dict ;;
    performance_data) echo fuzz/dict/json.dict ;;
    trackml_hits_gz) echo "" ;;
    *) echo fuzz/dict/csv.dict ;;
  esac
}

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
failed=()
printf '%-18s %14s %10s  %s\n' target executions exec/s result >"$scratch/summary"
# One target: its run on a scratch copy of its corpus, the exit status in
# $scratch/<target>.status.
run_target() {
  local t="$1"
  local exe="$build/fuzz/fuzz_$t"
  mkdir -p "$scratch/$t" "$build/artifacts/$t"
  cp -r "fuzz/corpus/$t/." "$scratch/$t/"
  local dict
  dict="$(dict_of "$t")"
  # A report's performance data is about 20 kB even for one event.
  local len="$max_len"
  [ "$t" = performance_data ] && len=$((max_len > 65536 ? max_len : 65536))
  local args=(-max_total_time="$seconds" -max_len="$len"
              -rss_limit_mb="$rss_mb" -timeout="$timeout"
              -print_final_stats=1 -artifact_prefix="$build/artifacts/$t/")
  [ -n "$dict" ] && args+=(-dict="$dict")
  local status=0
  "$exe" "${args[@]}" "$scratch/$t" >"$scratch/$t.log" 2>&1 || status=$?
  echo "$status" >"$scratch/$t.status"
}

for t in $targets; do
  [ -x "$build/fuzz/fuzz_$t" ] ||
    { echo "fuzz.sh: no target $t ($build/fuzz/fuzz_$t)" >&2; exit 2; }
done
# Each fuzzer is one process: JOBS of them run side by side, each for its
# full FUZZ_SECONDS (on the 2-core CI machine this halves the wall time
# with the same fuzzing per target).
running=0
for t in $targets; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true  # a failed run is reported below, from its status
    running=$((running - 1))
  fi
  echo "== fuzz_$t for ${seconds}s"
  run_target "$t" &
  running=$((running + 1))
done
wait || true

for t in $targets; do
  status="$(cat "$scratch/$t.status" 2>/dev/null || echo 125)"
  execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$scratch/$t.log" | tail -1)"
  rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$scratch/$t.log" | tail -1)"
  if [ "$status" -ne 0 ]; then
    result="FAILED (exit $status, input in $build/artifacts/$t/)"
    failed+=("$t")
    # The report: the sanitizer or libFuzzer lines of the log.
    grep -E "ERROR|SUMMARY|==[0-9]+==|terminate|what\(\)|Test unit written" \
      "$scratch/$t.log" | head -40 >&2 || tail -40 "$scratch/$t.log" >&2
  else
    result=ok
  fi
  printf '%-18s %14s %10s  %s\n' "$t" "${execs:-?}" "${rate:-?}" "$result" \
    | tee -a "$scratch/summary"
done
echo
cat "$scratch/summary"
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz.sh: crashes in: ${failed[*]}" >&2
  exit 1
fi
