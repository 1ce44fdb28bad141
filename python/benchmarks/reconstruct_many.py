"""Benchmark of the Python module (docs/python.md "Performance"):

1. reconstruct_many on 1 and 2 threads for 20 CLICdet ttbar + 30 BX events:
   wall times, speedup, and that the results are identical;
2. the cost of passing a DataFrame of a real TrackML event (about 110k
   hits) to reconstruct(): conversion time against reconstruction time.

    PYTHONPATH=build/python python3 python/benchmarks/reconstruct_many.py
"""

import argparse
import pathlib
import time

import pandas as pd

import conftrack

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]


def best_of(repeats, fn):
    """Fastest wall time of `repeats` calls, the CPU time of that call
    (all threads of the process) and its value."""
    best, cpu, value = float("inf"), 0.0, None
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        value = fn()
        wall = time.perf_counter() - t0
        if wall < best:
            best, cpu = wall, time.process_time() - c0
    return best, cpu, value


def threads_benchmark(events, repeats):
    sample = conftrack.simulate("ttbar3tev", events=events, seed=1,
                                overlay_bx=30, threads=2)
    hits = [e.hits for e in sample]
    conftrack.reconstruct(hits[0])  # set up the chain once
    t1, c1, one = best_of(
        repeats, lambda: conftrack.reconstruct_many(hits, threads=1))
    t2, c2, two = best_of(
        repeats, lambda: conftrack.reconstruct_many(hits, threads=2))
    for a, b in zip(one, two):
        pd.testing.assert_frame_equal(a.tracks, b.tracks)
        pd.testing.assert_frame_equal(a.hit_tracks, b.hit_tracks)
    n_hits = sum(len(h) for h in hits)
    print(f"reconstruct_many, {events} CLICdet ttbar + 30 BX events "
          f"({n_hits / events:.0f} hits each), best of {repeats}:")
    # CPU time / wall time: the cores the process actually got. Below 2
    # with 2 threads, other processes held the cores (a shared machine).
    print(f"  1 thread  {t1:7.2f} s wall, {c1 / t1:.2f} cores busy")
    print(f"  2 threads {t2:7.2f} s wall, {c2 / t2:.2f} cores busy; "
          f"speedup {t1 / t2:.2f}x, results identical")


def conversion_benchmark(repeats):
    folder = SOURCE_DIR / "data" / "trackml" / "train_100_events_no_truth"
    hits = conftrack.read_event(folder, 1005).hits
    conftrack.reconstruct(hits.head(1000), detector="trackml")  # set up
    rows = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = conftrack.reconstruct(hits, detector="trackml")
        wall = (time.perf_counter() - t0) * 1e3
        s = r.statistics
        reco = s["finding_ms"] + s["fitting_ms"] + s["selection_ms"]
        rows.append((s["conversion_ms"], reco, wall))
    conversion, reco, wall = min(rows, key=lambda row: row[2])
    print(f"reconstruct() of a real TrackML event, {len(hits)} hits "
          f"(fastest of {repeats}):")
    print(f"  DataFrame -> hits {conversion:8.1f} ms "
          f"({100 * conversion / reco:.2f} % of the reconstruction)")
    print(f"  reconstruction    {reco:8.1f} ms; whole call {wall:.1f} ms")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=20)
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    threads_benchmark(args.events, args.repeats)
    conversion_benchmark(args.repeats)


if __name__ == "__main__":
    main()
