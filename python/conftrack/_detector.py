"""conftrack.Detector: a tracker description (detectors/*.toml)."""

import pandas as pd

from . import _conftrack
from ._arguments import text


class Detector:
    """A detector by shipped name ("clicdet", "cld", "trackml") or TOML file.

    Attributes: name, model, field [T], envelope_r and envelope_z [mm], and
    `layers`, a DataFrame with one row per sensitive layer (name,
    subdetector, side, layer, shape, r, z_min, z_max, r_min, r_max [mm],
    thickness_x0, sigma_u, sigma_v [mm], n_phi_modules, n_z_modules, and the
    TrackML volume_id and layer_id).
    """

    def __init__(self, name_or_toml="clicdet"):
        self._handle = _conftrack.Detector(text("name_or_toml", name_or_toml))
        self._layers = None

    name = property(lambda self: self._handle.name)
    model = property(lambda self: self._handle.model)
    field = property(lambda self: self._handle.field)
    envelope_r = property(lambda self: self._handle.envelope_r)
    envelope_z = property(lambda self: self._handle.envelope_z)

    @property
    def layers(self):
        if self._layers is None:
            self._layers = pd.DataFrame(self._handle.layer_columns())
        return self._layers

    def __repr__(self):
        return (f"Detector({self.name!r}, model {self.model!r}, "
                f"{self.field} T, {len(self.layers)} layers)")


def as_detector(value, key="detector", optional=False):
    """A Detector from a Detector, a name or a TOML file (None if optional)."""
    if value is None and optional:
        return None
    if isinstance(value, Detector):
        return value
    if isinstance(value, str):
        return Detector(value)
    raise TypeError(f"{key}: expected a detector name, a TOML file or a "
                    f"conftrack.Detector, got {value!r}")
