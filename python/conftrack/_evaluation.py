"""Evaluation: performance numbers and histograms, the TrackML score."""

import json

import pandas as pd

from . import _conftrack
from ._arguments import flag, text


def evaluate(events, results, single_particle=False, sample=""):
    """The performance of `results` (from reconstruct or reconstruct_many)
    against `events` (from simulate or read_event, with truth), in the same
    order. Returns the numbers of summary.json (`conftrack run`) as a dict
    (NaN where undefined) with one more key, "histograms": for each
    distribution of the report (efficiency_vs_pt, ..., time_per_event) a
    dict of numpy arrays: edges and, for ratios, passed, total, value and
    uncertainty per bin; for counts, counts. Units: GeV, degrees, mm, ms.
    """
    events = list(events)
    results = list(results)
    handles = []
    for i, e in enumerate(events):
        if not hasattr(e, "_handle") or not hasattr(e, "number"):
            raise TypeError(f"events[{i}]: expected a conftrack.Event, "
                            f"got {type(e).__name__}")
        handles.append(e._handle)
    result_handles = []
    for i, r in enumerate(results):
        if not hasattr(r, "_handle") or not hasattr(r, "hit_tracks"):
            raise TypeError(f"results[{i}]: expected a conftrack.Result, "
                            f"got {type(r).__name__}")
        result_handles.append(r._handle)
    summary_json, histograms = _conftrack.evaluate(
        handles, result_handles, flag("single_particle", single_particle),
        text("sample", sample))
    summary = json.loads(summary_json)
    summary = _nan_for_null(summary)
    summary["histograms"] = histograms
    return summary


def _nan_for_null(value):
    if value is None:
        return float("nan")
    if isinstance(value, dict):
        return {k: _nan_for_null(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_nan_for_null(v) for v in value]
    return value


def _columns(table, key):
    if isinstance(table, pd.DataFrame):
        return {c: table[c].to_numpy() for c in table.columns}
    if isinstance(table, dict):
        return table
    raise TypeError(f"{key}: expected a pandas DataFrame or a dict of numpy "
                    f"arrays, got {type(table).__name__}")


def trackml_score(truth, submission, particles=None):
    """The TrackML score of `submission` (hit_id, track_id; every hit of
    `truth` once) against `truth` (hit_id, particle_id, weight; without
    weights they are computed from the truth and `particles` as the
    trackml-library does). Returns a dict: score, efficiency, fake_rate and
    their counts."""
    return _conftrack.trackml_score(
        _columns(truth, "truth"), _columns(submission, "submission"),
        None if particles is None else _columns(particles, "particles"))
