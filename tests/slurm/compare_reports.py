#!/usr/bin/env python3
"""Checks that a merged report equals a single-process report of the same
events: summary.json without what depends on the processes (wall times,
memory, threads, merge bookkeeping) and every histogram CSV byte for byte
(the wall-time tables excepted). Exit 1 with the first difference."""
import json
import pathlib
import sys

PROCESS_KEYS = {"time_ms_per_event", "time_ms_total", "peak_rss_mb", "threads",
                "merged_shards", "timing_note"}


def physics(path):
    summary = json.loads(path.read_text())
    for key in PROCESS_KEYS:
        summary.pop(key, None)
    for step in summary.get("steps", []):
        step.pop("ms_per_event", None)
    return summary


def main(single, merged):
    single, merged = pathlib.Path(single), pathlib.Path(merged)
    if not (merged / "summary.json").is_file():
        sys.exit(f"compare: {merged}/summary.json missing")
    a, b = physics(single / "summary.json"), physics(merged / "summary.json")
    for key in sorted(set(a) | set(b)):
        if a.get(key) != b.get(key):
            sys.exit(f"compare: summary.json key '{key}' differs: "
                     f"{str(a.get(key))[:200]} != {str(b.get(key))[:200]}")
    csvs = [p for p in sorted(single.glob("*.csv"))
            if not p.name.startswith("time_")]
    if not csvs:
        sys.exit(f"compare: no CSV files in {single}")
    for p in csvs:
        other = merged / p.name
        if not other.is_file() or other.read_bytes() != p.read_bytes():
            sys.exit(f"compare: {other} differs from {p}")
    print(f"compare: summary.json and {len(csvs)} histograms identical")


if __name__ == "__main__":
    main(*sys.argv[1:3])
