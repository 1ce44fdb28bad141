#!/usr/bin/env python3
"""Measure the magnetic field's fall-off along z from reconstructed tracks.

No truth is needed, so it works on the real TrackML events: the transverse
curvature of a track through three of its hits is proportional to the
field's bending there (for a track from the beam line, B_z + (z/2) dB_z/dz:
the radial field at a solenoid's end bends against B_z), and a particle's
transverse momentum does not change along the track. The ratio of the
curvature of each later triplet of hits to that of the track's innermost
triplet therefore measures the bending field at the later triplet's z
relative to the one near z = 0; in a uniform field it is 1 everywhere.

Usage (docs/validation.md):
  conftrack reconstruct -i EVENTS --detector trackml -o TRACKS
  scripts/field_profile.py EVENTS TRACKS
Prints the median ratio in bins of |z| of the middle hit, for tracks whose
innermost curvature corresponds to pT of about 0.1-1.8 GeV at 2 T; with
--by-radius, in bins of |z| and of r of the middle hit (the field's radial
dependence; docs/validation.md item 9).
"""

import argparse
import glob
import os
import sys

import numpy as np
import pandas as pd

# Hits closer than this in r to the previous hit kept are skipped, so that
# the overlap hits of one layer do not form a triplet with a tiny chord.
MIN_RADIAL_GAP_MM = 60.0
# Innermost curvature range [1/mm]: radii of 200-3000 mm (pT ~0.1-1.8 GeV
# at 2 T); straighter tracks are dominated by the hit resolution.
MIN_CURVATURE = 1.0 / 3000.0
MAX_CURVATURE = 1.0 / 200.0
Z_EDGES_MM = [0, 300, 600, 900, 1200, 1500, 1800, 2100, 2400, 2700, 3000]
R_EDGES_MM = [0, 300, 500, 700, 1100]


def triplet_curvature(a, b, c):
    """Signed curvature of the circle through three (x, y) points [1/mm]."""
    cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    ab = np.hypot(b[0] - a[0], b[1] - a[1])
    bc = np.hypot(c[0] - b[0], c[1] - b[1])
    ca = np.hypot(a[0] - c[0], a[1] - c[1])
    return 2.0 * cross / (ab * bc * ca)


def track_ratios(hits):
    """(|z|, r, ratio) of each later triplet of one track's hits, at its
    middle hit."""
    hits = hits.sort_values("r")
    kept = []
    last_r = -np.inf
    for x, y, z, r in zip(hits.x, hits.y, hits.z, hits.r):
        if r - last_r >= MIN_RADIAL_GAP_MM:
            kept.append((x, y, z, r))
            last_r = r
    if len(kept) < 5:
        return []
    inner = triplet_curvature(kept[0], kept[1], kept[2])
    if not MIN_CURVATURE <= abs(inner) <= MAX_CURVATURE:
        return []
    return [(abs(kept[i + 1][2]), kept[i + 1][3],
             triplet_curvature(kept[i], kept[i + 1], kept[i + 2]) / inner)
            for i in range(1, len(kept) - 2)]


def event_files(folder, suffix):
    found = {}
    for path in glob.glob(os.path.join(folder, "event*-" + suffix + ".csv*")):
        found[os.path.basename(path).split("-")[0]] = path
    return found


def measure(events):
    """(|z|, r, ratio) of every later triplet of the tracks of `events`, pairs
    of (hits, track_hits) DataFrames with the columns of the hits and
    track-hits files."""
    rows = []
    for hits, on_tracks in events:
        on_tracks = on_tracks[on_tracks.outlier == 0].merge(
            hits[["hit_id", "x", "y", "z"]], on="hit_id")
        on_tracks = on_tracks.assign(r=np.hypot(on_tracks.x, on_tracks.y))
        for _, track in on_tracks.groupby("track_id"):
            if len(track) >= 8:
                rows.extend(track_ratios(track))
    return pd.DataFrame(rows, columns=["abs_z", "r", "ratio"])


def profile(table):
    """[(z_low, z_high, triplets, median ratio)] in the bins Z_EDGES_MM."""
    bins = pd.cut(table.abs_z, Z_EDGES_MM)
    return [(int(interval.left), int(interval.right), len(group),
             float(group.ratio.median()))
            for interval, group in table.groupby(bins, observed=True)]


def print_by_radius(table):
    """Median ratio (triplets) in bins of |z| (rows) and r (columns)."""
    z_bins = pd.cut(table.abs_z, Z_EDGES_MM)
    r_bins = pd.cut(table.r, R_EDGES_MM)
    print("\nby |z| and r of the middle hit: median ratio (triplets)")
    print("   |z| [mm]" + "".join(
        f"{f'r {R_EDGES_MM[i]}-{R_EDGES_MM[i + 1]}':>18}"
        for i in range(len(R_EDGES_MM) - 1)))
    cells = table.groupby([z_bins, r_bins], observed=True).ratio
    medians, counts = cells.median(), cells.size()
    for interval in z_bins.cat.categories:
        row = f"{int(interval.left):5d}-{int(interval.right):<5d}"
        for r_interval in r_bins.cat.categories:
            key = (interval, r_interval)
            row += (f"{medians[key]:10.3f} ({counts[key]:5d})"
                    if key in counts.index else f"{'—':>18}")
        print(row)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("events", help="folder with eventNNNNNNNNN-hits.csv")
    parser.add_argument("tracks",
                        help="folder with eventNNNNNNNNN-track-hits.csv")
    parser.add_argument("--by-radius", action="store_true",
                        help="median ratio (triplets) in bins of |z| and r")
    args = parser.parse_args()
    hit_files = event_files(args.events, "hits")
    track_files = event_files(args.tracks, "track-hits")
    common = sorted(set(hit_files) & set(track_files))
    if not common:
        sys.exit(f"field_profile.py: error: no event has both hits in "
                 f"{args.events} and track hits in {args.tracks}")
    table = measure((pd.read_csv(hit_files[event]),
                     pd.read_csv(track_files[event])) for event in common)
    print(f"{len(common)} events; curvature of later hit triplets over the "
          f"innermost one, by |z| of the middle hit:")
    print("   |z| [mm]   triplets  median ratio")
    for low, high, count, median in profile(table):
        print(f"{low:5d}-{high:<5d}{count:10d}  {median:12.3f}")
    if args.by_radius:
        print_by_radius(table)


if __name__ == "__main__":
    main()
