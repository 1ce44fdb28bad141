"""Checks of Python arguments: a bad one raises TypeError or ValueError with
a one-line message that names it."""

import math
import numbers


def whole_number(key, value, minimum=0):
    """`value` as an int >= minimum."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{key}: expected a whole number, got {value!r}")
    if value < minimum:
        raise ValueError(f"{key}: must be >= {minimum}, got {value}")
    return int(value)


def flag(key, value):
    if not isinstance(value, bool):
        raise TypeError(f"{key}: expected True or False, got {value!r}")
    return value


def beam_spot(key, value):
    """`value` as None or a pair (x, y) of finite numbers [mm] within 10 mm
    of the detector axis (FinderConfig::beamSpotX, beamSpotY)."""
    if value is None:
        return None
    if (isinstance(value, (str, bytes)) or not hasattr(value, "__len__")
            or len(value) != 2):
        raise TypeError(f"{key}: expected a pair (x, y) in mm, got {value!r}")
    pair = []
    for v in value:
        if isinstance(v, bool) or not isinstance(v, numbers.Real):
            raise TypeError(f"{key}: expected numbers, got {value!r}")
        if not (math.isfinite(v) and abs(v) <= 10.0):
            raise ValueError(f"{key}: must be finite and within 10 mm of the "
                             f"detector axis, got {value!r}")
        pair.append(float(v))
    return tuple(pair)


def text(key, value):
    if not isinstance(value, str):
        raise TypeError(f"{key}: expected a string, got {value!r}")
    return value


def toml_value(key, value):
    """A Python value as a TOML value (generator settings)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        if not math.isfinite(value):
            raise ValueError(f"{key}: must be finite, got {value!r}")
        return repr(float(value))
    if isinstance(value, str):
        escaped = value.replace("\\", "\\\\").replace('"', '\\"')
        return f'"{escaped}"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(key, v) for v in value) + "]"
    raise TypeError(
        f"{key}: expected a number, a string, a bool or a list, got {value!r}")


def toml_table(name, settings):
    """A TOML table [name] of `settings` (a dict), '' if empty."""
    if not settings:
        return ""
    if not isinstance(settings, dict):
        raise TypeError(f"{name}: expected a dict of settings, got {settings!r}")
    lines = [f"[{name}]"]
    for key, value in settings.items():
        if not isinstance(key, str) or not key.replace("_", "").isalnum():
            raise ValueError(f"{name}: bad setting name {key!r}")
        lines.append(f"{key} = {toml_value(key, value)}")
    return "\n".join(lines) + "\n"
