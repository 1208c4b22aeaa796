"""Shared by the Python module's tests: where the built CLI and the source tree are (ctest sets
MAPNAV_CLI and MAPNAV_SOURCE_DIR), running the CLI, and the campus map and camera."""
import json
import os
import subprocess
from pathlib import Path

import pytest

import mapnav

SOURCE = Path(os.environ["MAPNAV_SOURCE_DIR"])
CLI = os.environ["MAPNAV_CLI"]
CAMPUS = str(SOURCE / "maps" / "cmu_campus.json")
PINHOLE = str(SOURCE / "maps" / "cameras" / "terregator_pinhole.json")
DIALOGUE = str(SOURCE / "maps" / "missions" / "campus_dialogue.json")


def cli(*args, expect=0):
    """Runs the built `mapnav` with `args`; returns (stdout, stderr) and checks the exit code."""
    done = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert done.returncode == expect, f"mapnav {' '.join(map(str, args))}: exit {done.returncode}\n{done.stderr}"
    return done.stdout, done.stderr


def cli_json(*args):
    return json.loads(cli(*args)[0])


def cli_error(*args, expect=1):
    """The message the CLI prints for a failing command, without its "mapnav: error: " prefix."""
    err = cli(*args, expect=expect)[1].strip().splitlines()[-1]
    assert err.startswith("mapnav: error: "), err
    return err[len("mapnav: error: "):]


def shared_data(name):
    """A folder of ../shared/data/real; fails (never skips) naming it when it is missing."""
    path = SOURCE.parent / "shared" / "data" / "real" / name
    assert path.is_dir(), f"{path}: the shared real data is missing (see ../shared/data/real/README.md)"
    return path


@pytest.fixture(scope="session")
def campus():
    return mapnav.Map.load(CAMPUS)


@pytest.fixture(scope="session")
def pinhole():
    return mapnav.Camera.load(PINHOLE)


@pytest.fixture(scope="session")
def frame():
    """A 512 x 480 frame of the benchmark's sidewalk scene (R1 of the campus) and its file."""
    camera, frames, predictions = mapnav.sidewalk_scene(str(SOURCE / "maps"), 1)
    return frames[0]
