#!/usr/bin/env python3
"""Counts particles with two or more hits on one layer in simulated events.

A layer is (volume_id, layer_id) of the hits file: subdetector, side and
layer number (docs/formats.md, detector ids). Prints, over all events of the
folder, the fraction of particles with hits that have at least two hits on
one layer, and the fraction of hits that are such extra hits (every hit of a
particle on a layer beyond its first). With `conftrack simulate
--module-level` these come mostly from overlapping sensors; with ideal
layers only from loopers that cross a layer again.

Usage: scripts/layer_double_hits.py EVENT_FOLDER
"""
import collections
import csv
import glob
import gzip
import os
import sys


def rows(path):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt", newline="") as f:
        yield from csv.DictReader(f)


def main(folder):
    hit_files = sorted(glob.glob(os.path.join(folder, "event*-hits.csv*")))
    if not hit_files:
        sys.exit(f"{folder}: no event*-hits.csv files")
    particles = 0
    doubled = 0
    hits = 0
    extra = 0
    for hit_file in hit_files:
        truth_file = hit_file.replace("-hits.csv", "-truth.csv")
        layer = {r["hit_id"]: (r["volume_id"], r["layer_id"])
                 for r in rows(hit_file)}
        per = collections.Counter()
        for r in rows(truth_file):
            if r["particle_id"] != "0":
                per[(r["particle_id"],) + layer[r["hit_id"]]] += 1
        by_particle = collections.defaultdict(int)
        for (pid, _, _), n in per.items():
            hits += n
            extra += n - 1
            by_particle[pid] = max(by_particle[pid], n)
        particles += len(by_particle)
        doubled += sum(1 for n in by_particle.values() if n >= 2)
    print(f"events {len(hit_files)}  particles with hits {particles}  "
          f"hits {hits}")
    print(f"particles with >= 2 hits on one layer: {doubled} "
          f"({100.0 * doubled / particles:.2f} %)")
    print(f"extra hits (beyond the first per particle and layer): {extra} "
          f"({100.0 * extra / hits:.2f} % of hits)")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
