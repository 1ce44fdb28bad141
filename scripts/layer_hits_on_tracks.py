#!/usr/bin/env python3
"""Split the hits per (volume, layer) of real and simulated TrackML events
into hits on reconstructed tracks and hits on none.

`conftrack validate-trackml` compares the hits per layer of the real files
with the simulation's; where they differ, this tells whether the difference
lies in what the reconstruction turns into tracks (particles crossing the
layer that both samples reconstruct alike) or in the hits it leaves
(noise, particles it does not find). No truth is needed: the real and the
simulated events are reconstructed the same way.

Usage (docs/validation.md, "Hits per (volume, layer)"):
  conftrack simulate-trackml -i REAL -o SIM
  conftrack reconstruct --detector trackml -i REAL -o REAL_TRACKS
  conftrack reconstruct --detector trackml -i SIM -o SIM_TRACKS
  scripts/layer_hits_on_tracks.py REAL REAL_TRACKS SIM SIM_TRACKS
Prints, per layer, the median |z| and r of the real hits, the deviation of
all simulated hits from the real ones, and the real and simulated hits on
tracks and on none with their deviations. With --radii V L, the hits on no
track of layer (V, L) in bins of r.
"""

import argparse
import glob
import os
import re
import sys

import numpy as np
import pandas as pd


def event_numbers(folder):
    """Event numbers of the hits files in a folder."""
    numbers = set()
    for path in glob.glob(os.path.join(folder, "event*-hits.csv*")):
        match = re.match(r"event(\d+)-hits\.csv", os.path.basename(path))
        if match:
            numbers.add(int(match.group(1)))
    return sorted(numbers)


def read_csv(folder, number, kind):
    """One event's file of a kind (hits, track-hits), plain or gzip."""
    stem = os.path.join(folder, f"event{number:09d}-{kind}.csv")
    for path in (stem, stem + ".gz"):
        if os.path.exists(path):
            return pd.read_csv(path)
    raise FileNotFoundError(f"{stem}: no such file (nor .gz)")


def load(events, tracks, numbers):
    """All hits of the events with an `on_track` column."""
    frames = []
    for number in numbers:
        hits = read_csv(events, number, "hits")
        on = set(read_csv(tracks, number, "track-hits").hit_id)
        hits["on_track"] = hits.hit_id.isin(on)
        frames.append(hits[["x", "y", "z", "volume_id", "layer_id", "on_track"]])
    hits = pd.concat(frames, ignore_index=True)
    hits["r"] = np.hypot(hits.x, hits.y)
    return hits


def deviation(real, simulated):
    return f"{100.0 * (simulated / real - 1.0):+6.1f} %" if real else "     —"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("real", help="real events (hits files)")
    parser.add_argument("real_tracks", help="their reconstructed tracks")
    parser.add_argument("sim", help="simulated events of the same particles")
    parser.add_argument("sim_tracks", help="their reconstructed tracks")
    parser.add_argument("--radii", nargs=2, type=int, metavar=("VOLUME", "LAYER"),
                        help="also the hits on no track of this layer by r")
    parser.add_argument("--radius-step", type=float, default=60.0,
                        help="bin width in r for --radii [mm] (60)")
    args = parser.parse_args()

    numbers = sorted(set(event_numbers(args.real)) & set(event_numbers(args.sim)))
    if not numbers:
        sys.exit(f"{args.real}, {args.sim}: no event in both folders")
    try:
        real = load(args.real, args.real_tracks, numbers)
        sim = load(args.sim, args.sim_tracks, numbers)
    except (FileNotFoundError, KeyError, ValueError) as error:
        sys.exit(f"layer_hits_on_tracks.py: {error}")

    print(f"{len(numbers)} events; hits on tracks and on none, real / simulated")
    print(f"{'vol':>3} {'lay':>3} {'|z|':>6} {'r':>6} {'all':>8}"
          f" {'on tracks':>13} {'':>8} {'on none':>13} {'':>8}")
    for (volume, layer), r_layer in real.groupby(["volume_id", "layer_id"]):
        s_layer = sim[(sim.volume_id == volume) & (sim.layer_id == layer)]
        r_on, s_on = int(r_layer.on_track.sum()), int(s_layer.on_track.sum())
        r_off, s_off = len(r_layer) - r_on, len(s_layer) - s_on
        print(f"{volume:3d} {layer:3d} {r_layer.z.abs().median():6.0f}"
              f" {r_layer.r.median():6.0f} {deviation(len(r_layer), len(s_layer))}"
              f" {r_on:6d}/{s_on:6d} {deviation(r_on, s_on)}"
              f" {r_off:6d}/{s_off:6d} {deviation(r_off, s_off)}")

    if args.radii:
        volume, layer = args.radii
        pick = lambda h: h[(h.volume_id == volume) & (h.layer_id == layer)
                           & ~h.on_track].r
        r_off, s_off = pick(real), pick(sim)
        if r_off.empty:
            sys.exit(f"--radii {volume} {layer}: no such layer in {args.real}")
        edges = np.arange(np.floor(r_off.min() / args.radius_step) * args.radius_step,
                          r_off.max() + args.radius_step, args.radius_step)
        real_counts = np.histogram(r_off, edges)[0]
        sim_counts = np.histogram(s_off, edges)[0]
        print(f"\nlayer ({volume}, {layer}), hits on no track by r [mm]:"
              " real / simulated")
        for low, a, b in zip(edges[:-1], real_counts, sim_counts):
            print(f"  {low:6.0f}-{low + args.radius_step:<6.0f} {a:6d} / {b:6d}")


if __name__ == "__main__":
    main()
