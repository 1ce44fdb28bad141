"""reconstruct_many: the same results on 1 and 2 threads and one by one."""

import pandas as pd

import conftrack


def test_reconstruct_many_threads_identical():
    events = conftrack.simulate("ttbar3tev", events=4, seed=21, overlay_bx=5)
    hits = [e.hits for e in events]
    one = conftrack.reconstruct_many(hits, threads=1)
    two = conftrack.reconstruct_many(hits, threads=2)
    alone = [conftrack.reconstruct(h) for h in hits]
    assert len(one) == len(two) == len(alone) == 4
    for a, b, c in zip(one, two, alone):
        assert len(a.tracks) > 10
        pd.testing.assert_frame_equal(a.tracks, b.tracks)
        pd.testing.assert_frame_equal(a.tracks, c.tracks)
        pd.testing.assert_frame_equal(a.hit_tracks, b.hit_tracks)
        pd.testing.assert_frame_equal(a.track_hits, c.track_hits)
