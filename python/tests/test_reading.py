"""Detectors and TrackML files into DataFrames."""

import numpy as np
import pytest

import conftrack

HIT_COLUMNS = ["hit_id", "x", "y", "z", "volume_id", "layer_id", "module_id"]


def test_detector_numbers_and_layers():
    d = conftrack.Detector("clicdet")
    assert d.name == "CLICdet"
    assert d.field == pytest.approx(4.0)
    layers = d.layers
    assert len(layers) > 20
    for c in ["name", "subdetector", "shape", "r", "z_min", "sigma_u",
              "volume_id", "layer_id"]:
        assert c in layers
    barrel = layers[layers["shape"] == "cylinder"]
    # The vertex barrel's first layer is at 31 mm (detectors.md).
    assert barrel.r.min() == pytest.approx(31.0, abs=1.0)
    assert (layers.sigma_u > 0).all()


def test_read_event_real_trackml(trackml_events):
    event = conftrack.read_event(trackml_events, 1001)
    assert event.number == 1001
    hits = event.hits
    assert list(hits.columns) == HIT_COLUMNS  # Kaggle files: no resolutions
    assert len(hits) == 93680
    assert hits.hit_id.iloc[0] == 1 and hits.hit_id.is_monotonic_increasing
    assert event.truth is None
    particles = event.particles
    assert "particle_id" in particles and "px" in particles
    assert particles.nhits.sum() <= len(hits)
    # The hits lie in the TrackML tracker: |z| < 3 m, r < 1.1 m.
    assert np.abs(hits.z).max() < 3000.0
    assert np.hypot(hits.x, hits.y).max() < 1100.0


def test_read_hits_with_and_without_detector(trackml_events):
    path = trackml_events / "event000001003-hits.csv.gz"
    raw = conftrack.read_hits(path)
    checked = conftrack.read_hits(path, detector="trackml")
    assert len(raw) == len(checked)
    np.testing.assert_array_equal(raw.x.to_numpy(), checked.x.to_numpy())
    np.testing.assert_array_equal(raw.module_id, checked.module_id)
    # With the detector the layers' resolutions come along.
    assert "sigma_u" in checked and (checked.sigma_u > 0).all()
    assert "sigma_u" not in raw


def test_simulated_event_round_trip_through_files(tmp_path, cli):
    cli("simulate", "--sample", "muons", "--gen", "pt_GeV=5", "-n", "1",
        "--seed", "11", "-o", tmp_path)
    from_files = conftrack.read_event(tmp_path, 1, detector="clicdet")
    simulated = conftrack.simulate("muons", events=1, seed=11, pt_GeV=5)[0]
    for name in ["hits", "truth", "particles"]:
        a = getattr(from_files, name)
        b = getattr(simulated, name)
        assert list(a.columns) == list(b.columns), name
        np.testing.assert_allclose(a.to_numpy(float), b.to_numpy(float),
                                   rtol=1e-12, atol=0, err_msg=name)
