#!/usr/bin/env python3
"""Event display of conftrack (the paper's figures 2 and 4): one event's hits
in (x, y), in the conformal plane (u, v) and in (z, r), one colour per found
track, hits on no track grey.

Usage: conftrack_display.py display_hits.csv out.png [title]
The CSV (written by conftrack) has columns x,y,z,track (track -1: none).
"""
import csv
import math
import sys


def main(path, out, title):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    hits = []
    with open(path) as f:
        for row in csv.DictReader(f):
            hits.append((float(row["x"]), float(row["y"]), float(row["z"]),
                         int(row["track"])))
    free = [h for h in hits if h[3] < 0]
    tracks = sorted({h[3] for h in hits if h[3] >= 0})
    cmap = plt.get_cmap("tab20")
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.6))
    panels = [
        ("x [mm]", "y [mm]", lambda h: (h[0], h[1])),
        ("u [1/mm]", "v [1/mm]",
         lambda h: (h[0] / (h[0] ** 2 + h[1] ** 2), h[1] / (h[0] ** 2 + h[1] ** 2))),
        ("z [mm]", "r [mm]", lambda h: (h[2], math.hypot(h[0], h[1]))),
    ]
    for ax, (xl, yl, proj) in zip(axes, panels):
        if free:
            pts = [proj(h) for h in free]
            ax.scatter([p[0] for p in pts], [p[1] for p in pts], s=2,
                       c="0.7", linewidths=0, label="unassigned hits")
        for k, t in enumerate(tracks):
            pts = sorted((proj(h) for h in hits if h[3] == t),
                         key=lambda p: abs(p[0]) + abs(p[1]))
            ax.plot([p[0] for p in pts], [p[1] for p in pts], ".-",
                    ms=3, lw=0.4, color=cmap(k % 20))
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.grid(alpha=0.3)
    axes[0].set_aspect("equal", adjustable="datalim")
    axes[1].set_aspect("equal", adjustable="datalim")
    fig.suptitle(f"{title}: {len(hits)} hits, {len(tracks)} tracks "
                 f"(unassigned hits grey)")
    fig.tight_layout()
    fig.savefig(out, dpi=90)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) > 3 else "event")
