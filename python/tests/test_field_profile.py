"""scripts/field_profile.py: the bending field along z from tracks alone."""

import importlib.util

import numpy as np
import pandas as pd
import pytest

from conftest import SOURCE_DIR


@pytest.fixture(scope="module")
def field_profile():
    spec = importlib.util.spec_from_file_location(
        "field_profile", SOURCE_DIR / "scripts" / "field_profile.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def forward_tracks(bending):
    """Hits of 40 tracks from the origin (tan(lambda) = 3, transverse
    radius of curvature 1 m near z = 0), integrated in 1 mm steps with the
    curvature scaled by bending(|z|), one hit each 70 mm of r."""
    hits, track_hits = [], []
    hit_id = 0
    for track_id in range(40):
        psi = 2.0 * np.pi * track_id / 40.0
        sign = 1.0 if track_id % 2 else -1.0
        x = y = z = 0.0
        next_r = 30.0
        for _ in range(1000):
            psi += sign * bending(abs(z)) / 1000.0
            x += np.cos(psi)
            y += np.sin(psi)
            z += 3.0 * sign
            if np.hypot(x, y) >= next_r:
                hit_id += 1
                hits.append((hit_id, x, y, z))
                track_hits.append((track_id, hit_id, 0))
                next_r += 70.0
    return (pd.DataFrame(hits, columns=["hit_id", "x", "y", "z"]),
            pd.DataFrame(track_hits,
                         columns=["track_id", "hit_id", "outlier"]))


def test_uniform_field_gives_one_everywhere(field_profile):
    rows = field_profile.profile(
        field_profile.measure([forward_tracks(lambda z: 1.0)]))
    assert len(rows) >= 8
    for low, high, count, median in rows:
        assert median == pytest.approx(1.0, abs=0.01), (low, high)


def test_weaker_field_beyond_a_plane_halves_the_ratio_there(field_profile):
    rows = field_profile.profile(
        field_profile.measure(
            [forward_tracks(lambda z: 1.0 if z < 1200.0 else 0.5)]))
    by_bin = {low: median for low, high, count, median in rows}
    assert by_bin[300] == pytest.approx(1.0, abs=0.01)
    assert by_bin[600] == pytest.approx(1.0, abs=0.01)
    assert by_bin[1800] == pytest.approx(0.5, abs=0.02)
    assert by_bin[2100] == pytest.approx(0.5, abs=0.02)
