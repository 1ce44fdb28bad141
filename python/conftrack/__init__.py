"""conftrack from Python: conformal tracking on numpy arrays and pandas
DataFrames with the TrackML column names (docs/python.md).

    import conftrack
    events = conftrack.simulate("ttbar3tev", detector="clicdet", events=2,
                                overlay_bx=30)
    results = conftrack.reconstruct_many([e.hits for e in events])
    summary = conftrack.evaluate(events, results)

Units are the TrackML ones throughout: mm, GeV, ns, rad, T. Bad input
raises ValueError (FileNotFoundError for a missing file) with the one-line
message the command-line program prints.
"""

from ._detector import Detector
from ._events import Event, read_event, read_hits, simulate
from ._evaluation import evaluate, trackml_score
from ._reconstruction import Result, reconstruct, reconstruct_many

__all__ = [
    "Detector",
    "Event",
    "Result",
    "evaluate",
    "read_event",
    "read_hits",
    "reconstruct",
    "reconstruct_many",
    "simulate",
    "trackml_score",
]
