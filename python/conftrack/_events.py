"""Events: TrackML files read into DataFrames, samples simulated."""

import os

import pandas as pd

from . import _conftrack
from ._arguments import flag, text, toml_table, whole_number
from ._detector import as_detector


class Event:
    """One event: `hits`, `truth` and `particles` DataFrames with the
    TrackML column names (truth and particles None when the event has
    none), and its `number`."""

    def __init__(self, handle, detector):
        self._handle = handle
        self.detector = detector
        self._hits = None
        self._truth = None
        self._particles = None

    number = property(lambda self: self._handle.number)

    @property
    def hits(self):
        if self._hits is None:
            self._hits = pd.DataFrame(self._handle.hit_columns())
        return self._hits

    @property
    def truth(self):
        if self._truth is None and self._handle.has_truth:
            self._truth = pd.DataFrame(self._handle.truth_columns())
        return self._truth

    @property
    def particles(self):
        if self._particles is None and self._handle.has_particles:
            self._particles = pd.DataFrame(self._handle.particle_columns())
        return self._particles

    def __repr__(self):
        return f"Event({self.number}, {len(self.hits)} hits)"


def read_hits(path, detector=None):
    """The hits file `path` (plain or .gz) as a DataFrame: hit_id, x, y, z,
    volume_id, layer_id, module_id, and sigma_u, sigma_v where known. With
    a detector the hits are checked against its layers and the resolutions
    come from them; without one the ids are taken raw."""
    det = as_detector(detector, optional=True)
    columns = _conftrack.read_hits(os.fspath(path),
                                   det._handle if det else None)
    return pd.DataFrame(columns)


def read_event(folder, event_number, detector=None):
    """Event `event_number` of `folder` (eventNNNNNNNNN-hits.csv and, if
    present, -truth.csv and -particles.csv, each plain or .gz)."""
    det = as_detector(detector, optional=True)
    handle = _conftrack.read_event(
        os.fspath(folder), whole_number("event_number", event_number),
        det._handle if det else None)
    return Event(handle, det)


def simulate(sample="ttbar3tev", detector="clicdet", events=1, seed=1,
             overlay_bx=0, first_event=1, threads=0, multiple_scattering=True,
             energy_loss=True, time_window=True, module_level=False,
             overlay=None, luminous_region=None, **generator_settings):
    """Simulates `events` events of `sample` ("ttbar3tev", "bb500", "muons"
    or "gun", "hepmc:<file>") as `conftrack simulate` does: event numbers
    first_event, first_event + 1, ..., each a function of (seed, number)
    only. Keyword arguments not named here are generator settings (as
    --gen: p_GeV=10, theta_deg=89, particle="mu-"); `overlay` and
    `luminous_region` are dicts of the [overlay] and [luminous_region]
    settings. Returns a list of Event."""
    det = as_detector(detector)
    toml = (toml_table("generator", generator_settings) +
            toml_table("overlay", overlay) +
            toml_table("luminous_region", luminous_region))
    handles = _conftrack.simulate(
        det._handle, text("sample", sample), whole_number("events", events),
        whole_number("first_event", first_event), whole_number("seed", seed),
        whole_number("overlay_bx", overlay_bx), toml,
        flag("multiple_scattering", multiple_scattering),
        flag("energy_loss", energy_loss), flag("time_window", time_window),
        flag("module_level", module_level), whole_number("threads", threads))
    return [Event(h, det) for h in handles]
