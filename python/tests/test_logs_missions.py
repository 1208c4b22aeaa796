"""Replay logs (frames, truth, odometry) and missions against `mapnav replay --json` / `run --json`."""
import json

import numpy as np
import pytest

import mapnav
from conftest import DIALOGUE, cli, cli_json

FRAMES = 6


@pytest.fixture(scope="module")
def log_dir(tmp_path_factory):
    path = tmp_path_factory.mktemp("log") / "dialogue"
    cli("simulate", "--mission", DIALOGUE, "-o", path, "--max-frames", FRAMES)
    return path


def test_a_log_reads_its_frames_truth_and_odometry(log_dir):
    log = mapnav.ReplayLog.open(str(log_dir))
    lines = [json.loads(line) for line in (log_dir / "frames.jsonl").read_text().splitlines()]
    assert len(log) == len(lines) == FRAMES
    assert log.times.tolist() == [line["t"] for line in lines]
    assert log.odometry[:, 0].tolist() == [line["odometry"]["distance_m"] for line in lines]
    assert log.truth[:, :2].tolist() == [[line["truth"]["x"], line["truth"]["y"]] for line in lines]
    assert log.frames[2]["image"] == lines[2]["image"] and log.frames[2]["truth"][0] == lines[2]["truth"]["x"]
    assert (log.camera.width, log.camera.height) == (512, 480)
    image = log.image(2)
    assert image.shape == (480, 512, 3) and np.array_equal(image, mapnav.read_image(str(log_dir / lines[2]["image"])))
    assert log.mask(2).shape == (480, 512)
    with pytest.raises(mapnav.InvalidInput):
        log.image(FRAMES)


def test_a_missing_log_raises_an_io_error(tmp_path):
    with pytest.raises(mapnav.IoError, match="nowhere"):
        mapnav.ReplayLog.open(str(tmp_path / "nowhere"))


def without_timings(metrics):
    """The metrics but the run's own timings (latency_ms_*, vision_ms_*), which differ run to run."""
    return {k: v for k, v in metrics.items() if "_ms_" not in k}


def test_replay_gives_the_clis_metrics(log_dir):
    metrics = mapnav.replay(DIALOGUE, str(log_dir))
    printed = json.loads(cli("replay", "--mission", DIALOGUE, "--log", log_dir, "--json", expect=1)[0])
    assert without_timings(metrics) == without_timings(printed)
    assert metrics["frames"] == FRAMES and metrics["reached_goal"] is False


def test_replay_takes_the_map_modules_options_as_the_cli_does(log_dir):
    options = {"initial_sigma_m": 0.5, "initial_heading_sigma_deg": 5}
    metrics = mapnav.replay(DIALOGUE, str(log_dir), map_options=options)
    printed = json.loads(cli("replay", "--mission", DIALOGUE, "--log", log_dir, "--map-options", json.dumps(options),
                             "--json", expect=1)[0])
    assert without_timings(metrics) == without_timings(printed)
    # A wider start changes what the filter says of itself (its NEES), so the options were used.
    assert metrics["nees_mean"] != mapnav.replay(DIALOGUE, str(log_dir))["nees_mean"]
    with pytest.raises(mapnav.InvalidInput, match="map_options.*initial_sigma_m"):
        mapnav.replay(DIALOGUE, str(log_dir), map_options={"initial_sigma_m": -1})


def test_run_gives_the_clis_metrics():
    metrics = mapnav.run(DIALOGUE, max_frames=4, seed=3)
    printed = cli_json("run", "--mission", DIALOGUE, "--max-frames", 4, "--seed", 3, "--json")
    assert without_timings(metrics) == without_timings(printed) and metrics["frames"] == 4


def test_a_bad_mission_raises_the_clis_message(tmp_path):
    with pytest.raises(mapnav.IoError, match="nowhere.json"):
        mapnav.run(str(tmp_path / "nowhere.json"))
