"""Reconstruction of hits given as a DataFrame or a dict of arrays."""

import numpy as np
import pandas as pd

from . import _conftrack
from ._arguments import beam_spot as check_beam_spot
from ._arguments import flag, whole_number
from ._detector import Detector, as_detector

#: The hit columns the reconstruction reads (others are ignored).
HIT_COLUMNS = ("hit_id", "x", "y", "z", "volume_id", "layer_id", "module_id",
               "sigma_u", "sigma_v")

#: The track parameters, in the order of the covariance matrices.
PARAMETERS = ("d0", "phi0", "omega", "z0", "tan_lambda")


class Result:
    """The reconstruction of one event.

    tracks: one row per track: track_id (1, 2, ...; the ids of hit_tracks),
      the perigee parameters d0 [mm], phi0 [rad], omega [1/mm], z0 [mm],
      tan_lambda, pt [GeV], chi2, ndf, n_hits, n_outliers, fitted, step
      (the finding step), pt_estimate [GeV], the perigee's reference
      ref_x, ref_y [mm] (the beam line d0 and z0 are measured from) and
      the 15 covariance elements cov_<row>_<column> of the track files;
    covariance: the covariance matrices, shape (n_tracks, 5, 5);
    hit_tracks: hit_id, track_id for every hit (0: on no track), a TrackML
      submission;
    track_hits: track_id, hit_id, outlier for every hit of every track
      (outlier as in the track files: 0 fitted, 1 rejected by the fit, 2
      a looper's further-turn hit, joined but not fitted);
    steps: the finder's statistics per step; statistics: a dict of counts
      and times [ms] (conversion_ms: turning the hits into C++ hits).
    """

    def __init__(self, handle):
        self._handle = handle
        self._cache = {}

    def _cached(self, name, make):
        if name not in self._cache:
            self._cache[name] = make()
        return self._cache[name]

    @property
    def covariance(self):
        return self._cached("covariance", self._handle.covariances)

    @property
    def tracks(self):
        def make():
            table = pd.DataFrame(self._handle.track_columns())
            cov = self.covariance
            for row in range(5):
                for col in range(row + 1):
                    name = f"cov_{PARAMETERS[row]}_{PARAMETERS[col]}"
                    table[name] = cov[:, row, col]
            return table
        return self._cached("tracks", make)

    @property
    def hit_tracks(self):
        return self._cached(
            "hit_tracks",
            lambda: pd.DataFrame(self._handle.hit_track_columns()))

    @property
    def track_hits(self):
        return self._cached(
            "track_hits",
            lambda: pd.DataFrame(self._handle.track_hit_columns()))

    @property
    def steps(self):
        return self._cached("steps",
                            lambda: pd.DataFrame(self._handle.step_rows()))

    @property
    def statistics(self):
        return self._handle.statistics()

    def submission(self, event_id=0):
        """hit_tracks with an event_id column first (TrackML's format)."""
        table = self.hit_tracks.copy()
        table.insert(0, "event_id", whole_number("event_id", event_id))
        return table

    def __repr__(self):
        s = self.statistics
        return f"Result({s['tracks']} tracks from {s['hits']} hits)"


def hit_columns(hits, key="hits"):
    """The hit columns of a DataFrame, a dict of arrays or an Event."""
    if hasattr(hits, "hits") and hasattr(hits, "number"):
        hits = hits.hits
    if isinstance(hits, pd.DataFrame):
        return {c: hits[c].to_numpy() for c in HIT_COLUMNS if c in hits}
    if isinstance(hits, dict):
        return {c: np.asarray(hits[c]) for c in HIT_COLUMNS if c in hits}
    raise TypeError(f"{key}: expected a pandas DataFrame or a dict of numpy "
                    f"arrays with the TrackML hit columns, got "
                    f"{type(hits).__name__}")


# Reconstructions set up so far (chain files read, sensor layouts built),
# by their settings: repeated calls do not set them up again.
_reconstructors = {}


def _reconstructor(detector, chain, fit, fit_pdg, module_level,
                   beam_spot=None):
    det = as_detector(detector)
    if chain is not None and not isinstance(chain, str):
        raise TypeError(f"chain: expected a chain name or TOML file, "
                        f"got {chain!r}")
    key = (det if isinstance(detector, Detector) else detector, chain,
           flag("fit", fit), whole_number("fit_pdg", fit_pdg, minimum=-10**9),
           flag("module_level", module_level),
           check_beam_spot("beam_spot", beam_spot))
    if key not in _reconstructors:
        if len(_reconstructors) >= 8:
            _reconstructors.clear()
        _reconstructors[key] = _conftrack.Reconstructor(
            det._handle, chain or "", fit, fit_pdg, module_level, key[-1])
    return _reconstructors[key]


def reconstruct(hits, detector="clicdet", chain=None, fit=True, fit_pdg=211,
                module_level=False, beam_spot=None):
    """Finds, fits and selects the tracks of one event, as `conftrack
    reconstruct` does for a hits file. `hits`: a DataFrame or a dict of
    numpy arrays with the TrackML hit columns (hit_id, x, y, z, volume_id,
    layer_id, module_id; sigma_u, sigma_v optional), or an Event. `chain`:
    a chain name or TOML file (default: the detector's). `beam_spot`: the
    transverse position (x, y) of the beam line in mm, as --beam-spot
    (default: the chain's). Returns a Result.
    """
    reco = _reconstructor(detector, chain, fit, fit_pdg, module_level,
                          beam_spot)
    return Result(reco.run(hit_columns(hits)))


def reconstruct_many(events, detector="clicdet", chain=None, fit=True,
                     fit_pdg=211, module_level=False, threads=0,
                     beam_spot=None):
    """reconstruct() of each element of `events` (hits as for reconstruct),
    `threads` events at a time (0: all cores) with the GIL released. The
    results are those of reconstruct() one by one, in the same order."""
    reco = _reconstructor(detector, chain, fit, fit_pdg, module_level,
                          beam_spot)
    columns = [hit_columns(h, key=f"events[{i}]") for i, h in enumerate(events)]
    return [Result(r) for r in
            reco.run_many(columns, whole_number("threads", threads))]
