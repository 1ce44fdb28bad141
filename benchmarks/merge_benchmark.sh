#!/usr/bin/env bash
# Times `conftrack merge` of the 100 shards of a 10,000-event muon study
# (the issue's target: under 10 s). The shards are made here with
# `conftrack run --shard K/100`; the merge is timed three times with the
# plots (what a user gets) and three times without, and the medians are
# printed with the machine.
#
# Usage: benchmarks/merge_benchmark.sh path/to/conftrack [shards] [events]
set -euo pipefail
conftrack=$(readlink -f "${1:?usage: $0 path/to/conftrack [shards] [events]}")
shards=${2:-100}
events=${3:-10000}
work=$(mktemp -d /tmp/conftrack-merge-bench.XXXXXX)
trap 'rm -rf "$work"' EXIT

start=$SECONDS
for ((k = 0; k < shards; ++k)); do
  "$conftrack" -q run --sample muons --overlay-bx 0 -n "$events" --seed 1 \
    --no-plots -j 1 --shard "$k/$shards" -o "$work/shard-$k" >/dev/null
done
echo "made $shards shards of a $events-event muon study in $((SECONDS - start)) s"
du -sh "$work" | awk '{print "shard folders: " $1}'

median_of_3() {  # prints the median wall time [s] of three runs of "$@"
  local times=()
  for _ in 1 2 3; do
    rm -rf "$work/merged"
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>&1
    t1=$(date +%s.%N)
    times+=("$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }')")
  done
  printf '%s\n' "${times[@]}" | sort -g | sed -n 2p
}
inputs=("$work"/shard-*)
with_plots=$(median_of_3 "$conftrack" -q merge -i "${inputs[@]}" -o "$work/merged")
without=$(median_of_3 "$conftrack" -q merge --no-plots -i "${inputs[@]}" -o "$work/merged")
"$conftrack" -q merge --no-plots -i "${inputs[@]}" -o "$work/merged" |
  grep -E "events|efficiency" | head -3
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "merge of $shards shards: median of 3: ${with_plots} s with plots, ${without} s without"
