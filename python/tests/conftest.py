"""Shared fixtures of the Python tests: where the CLI and the data are.

Run by ctest (`make test`), which sets PYTHONPATH to build/python and
CONFTRACK_CLI to the program; by hand:
  PYTHONPATH=build/python CONFTRACK_CLI=build/conftrack python3 -m pytest python/tests
"""

import os
import pathlib
import subprocess

import pytest

SOURCE_DIR = pathlib.Path(
    os.environ.get("CONFTRACK_SOURCE_DIR",
                   pathlib.Path(__file__).resolve().parents[2]))
TRACKML_EVENTS = SOURCE_DIR / "data" / "trackml" / "train_100_events_no_truth"


@pytest.fixture(scope="session")
def cli():
    """Runs the conftrack program; returns the CompletedProcess."""
    program = os.environ.get("CONFTRACK_CLI",
                             str(SOURCE_DIR / "build" / "conftrack"))

    def run(*args, check=True):
        done = subprocess.run([program, "-q", *map(str, args)],
                              capture_output=True, text=True)
        if check and done.returncode != 0:
            raise AssertionError(f"conftrack {' '.join(map(str, args))}: "
                                 f"exit {done.returncode}: {done.stderr}")
        return done
    return run


@pytest.fixture(scope="session")
def trackml_events():
    return TRACKML_EVENTS
