"""mapnav.distributed on a real Dask cluster on 127.0.0.1 (a `dask scheduler` and two `dask worker`
processes of one thread each), compared byte for byte with the built `mapnav`: the suite, a worker
killed while tasks run, a resumed run, replays over several logs, evaluations over several folders, and
the command's errors and exit codes."""
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import CLI, SOURCE, shared_data

from mapnav import distributed

PYTHON = sys.executable
SHORT_CROSSING = str(SOURCE / "tests" / "data" / "missions" / "short_crossing.json")
# Long enough that a worker can be killed mid-task (about 3 s a seed), short enough for CI.
SUITE_FRAMES = "100"


def _stop(process):
    """Stops a process and its group (a worker and anything it started) and waits for it."""
    if process.poll() is None:
        try:
            os.killpg(process.pid, signal.SIGTERM)
            process.wait(timeout=10)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            os.killpg(process.pid, signal.SIGKILL)
    process.wait()


class Cluster:
    """A scheduler and workers on 127.0.0.1, each its own process group; stop() stops them all."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.processes = []
        self.workers = []
        scheduler_file = folder / "scheduler.json"
        self.scheduler = self._start([PYTHON, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                      "--port", "0", "--no-dashboard", "--scheduler-file", str(scheduler_file)],
                                     "scheduler")
        deadline = time.monotonic() + 60
        while not scheduler_file.exists() or not scheduler_file.read_text().strip():
            assert self.scheduler.poll() is None, (folder / "scheduler.log").read_text()
            assert time.monotonic() < deadline, "the scheduler did not start in 60 s"
            time.sleep(0.1)
        self.address = json.loads(scheduler_file.read_text())["address"]

    def _start(self, command, name):
        log = open(self.folder / f"{name}.log", "w")
        p = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, start_new_session=True, env=os.environ)
        self.processes.append(p)
        return p

    def add_worker(self):
        n = len(self.workers)
        # No nanny: killing the worker's process is killing the worker (a nanny would start it again).
        w = self._start([PYTHON, "-m", "distributed.cli.dask_worker", self.address, "--nthreads", "1", "--no-nanny",
                         "--no-dashboard", "--name", f"w{n}", "--local-directory", str(self.folder / f"w{n}")],
                        f"worker{n}")
        self.workers.append(w)
        return w

    def wait_for_workers(self, n):
        from distributed import Client

        with Client(self.address, timeout="30s") as c:
            c.wait_for_workers(n, timeout=60)

    def stop(self):
        for p in reversed(self.processes):
            _stop(p)


@pytest.fixture
def cluster(tmp_path):
    c = Cluster(tmp_path)
    try:
        c.add_worker()
        c.add_worker()
        c.wait_for_workers(2)
        yield c
    finally:
        c.stop()
    assert all(p.poll() is not None for p in c.processes)


def _cli(*args):
    done = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    return done.returncode, done.stdout, done.stderr


def _distributed(*args, wait=True):
    command = [PYTHON, "-m", "mapnav.distributed", *map(str, args)]
    if not wait:
        return subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    done = subprocess.run(command, capture_output=True, text=True, timeout=600)
    return done.returncode, done.stdout, done.stderr


SUITE = ["--seeds", "1-6", "--max-frames", SUITE_FRAMES, "--json", "--no-wall-time"]


@pytest.fixture(scope="module")
def single_machine_suite():
    code, out, err = _cli("suite", "random-campus", *SUITE, "--threads", "2")
    assert code == 0, err
    return out


def test_the_suite_on_two_workers_prints_the_bytes_of_the_single_machine_command(cluster, single_machine_suite,
                                                                                  tmp_path):
    code, out, err = _distributed("suite", "--scheduler", cluster.address, *SUITE, "-o", tmp_path / "out")
    assert code == 0, err
    assert out == single_machine_suite
    assert "6/6 done, 0 running, 0 failed" in err
    assert sorted(os.listdir(tmp_path / "out" / "results")) == [f"seed-{s}.json" for s in range(1, 7)]
    # Each worker wrote its seed's map and mission under the output folder, in the seed's own folder.
    assert all((tmp_path / "out" / f"seed-{s}" / "mission.json").is_file() for s in range(1, 7))


def test_a_worker_killed_while_tasks_run_loses_no_seed_and_repeats_none(cluster, single_machine_suite, tmp_path):
    out_dir = tmp_path / "out"
    run = _distributed("suite", "--scheduler", cluster.address, *SUITE, "-o", out_dir, wait=False)
    try:
        deadline = time.monotonic() + 120
        results = out_dir / "results"
        while not (results.is_dir() and any(results.glob("seed-*.json"))):
            assert run.poll() is None, run.communicate()
            assert time.monotonic() < deadline, "no seed finished in 120 s"
            time.sleep(0.05)
        victim = cluster.workers[0]
        os.killpg(victim.pid, signal.SIGKILL)
        victim.wait()
        out, err = run.communicate(timeout=300)
    finally:
        if run.poll() is None:
            run.kill()
            run.communicate()
    assert run.returncode == 0, err
    assert victim.returncode == -signal.SIGKILL
    assert sorted(p.name for p in results.iterdir()) == [f"seed-{s}.json" for s in range(1, 7)]
    assert out == single_machine_suite
    assert [r["seed"] for r in json.loads(out)["runs"]] == [1, 2, 3, 4, 5, 6]


def test_a_resumed_run_takes_the_finished_seeds_from_its_folder(tmp_path):
    out_dir = tmp_path / "out"
    args = ["suite", "--seeds", "3,5", "--max-frames", "4", "--json", "--no-wall-time", "--workers", "1", "-o", out_dir]
    code, first, err = _distributed(*args)
    assert code == 0, err
    # A finished seed is read back, not run again: its kept record is what the second run prints ...
    kept = out_dir / "results" / "seed-3.json"
    record = json.loads(kept.read_text())
    record["outcome"] = "kept from the first run"
    kept.write_text(json.dumps(record) + "\n")
    # ... and a record cut short (the client stopped while writing it) is run again.
    cut = out_dir / "results" / "seed-5.json"
    cut.write_text(cut.read_text()[:40])
    code, second, err = _distributed(*args)
    assert code == 0, err
    runs = json.loads(second)["runs"]
    assert runs[0]["outcome"] == "kept from the first run"
    assert runs[1] == json.loads(first)["runs"][1]
    # The same folder for other inputs is refused, naming the folder's run.json.
    code, _, err = _distributed("suite", "--seeds", "3,5", "--max-frames", "5", "--workers", "1", "-o", out_dir)
    assert code == 1
    assert f"{out_dir / 'run.json'}: InvalidInput: the folder holds a run that asked for other things" in err


def test_replays_of_four_logs_equal_four_replay_commands(cluster, tmp_path):
    logs = []
    for seed in range(1, 5):
        log = tmp_path / f"log{seed}"
        code, _, err = _cli("simulate", "--mission", SHORT_CROSSING, "-o", log, "--seed", seed)
        assert code == 0, err
        logs.append(log)
    code, out, err = _distributed("replay", "--scheduler", cluster.address, "--mission", SHORT_CROSSING, *logs,
                                  "--json", "--no-progress")
    assert code == 0, err
    assert err == ""
    got = [json.loads(line) for line in out.splitlines()]
    assert len(got) == 4
    timing = ("latency_ms_median", "latency_ms_p99", "latency_ms_max", "vision_ms_median")  # wall-clock figures
    for log, run in zip(logs, got):
        code, single, err = _cli("replay", "--mission", SHORT_CROSSING, "--log", log, "--json")
        assert code == 0, err
        expected = json.loads(single)
        for key in timing:
            assert run.pop(key) >= 0 and expected.pop(key) >= 0
        assert run == expected
    # The logs differ (their seeds do), so the equality above is not one run's repeated.
    assert got[0]["lateral_rms_m"] != got[1]["lateral_rms_m"]
    # The API gives the same, with the text of each replay in `results`.
    from distributed import Client

    with Client(cluster.address) as client:
        gathered = distributed.replay_logs(SHORT_CROSSING, logs, client)
    assert gathered.exit_code == 0
    assert [json.loads(r)["frames"] for r in gathered.results] == [r["frames"] for r in got]


def test_evaluations_of_two_folders_equal_two_eval_commands(cluster, tmp_path):
    camvid = shared_data("camvid")
    photos = sorted((camvid / "images").iterdir())[:6]
    folders = []
    for k in range(2):
        f = tmp_path / f"part{k}"
        (f / "images").mkdir(parents=True)
        (f / "labels").mkdir()
        for photo in photos[3 * k:3 * k + 3]:
            (f / "images" / photo.name).symlink_to(photo)
            (f / "labels" / photo.name).symlink_to(camvid / "labels" / photo.name)
        folders.append(f)
    code, out, err = _distributed("eval", "--scheduler", cluster.address, "--pipeline", "color-rgb", *folders,
                                  "--json", "--no-progress")
    assert code == 0, err
    singles = []
    for f in folders:
        code, single, err = _cli("eval", "segmentation", "--pipeline", "color-rgb", "--images", f / "images",
                                 "--labels", f / "labels", "--json")
        assert code == 0, err
        singles.append(single)
    assert out == "".join(singles)  # each folder's document as the CLI prints it, in the order given
    scores = [json.loads(s) for s in singles]
    assert scores[0]["images"] == scores[1]["images"] == 3 and scores[0] != scores[1]


def test_bad_input_gets_a_clear_error_and_the_clis_exit_code(tmp_path):
    code, out, err = _distributed("suite", "--seeds", "5-2")
    assert (code, out) == (1, "")
    assert "error: '5-2' is not a seed list: the range '5-2' runs backwards" in err
    code, out, err = _distributed("suite", "--seeds", "1", "--scheduler", "tcp://127.0.0.1:9", "--timeout", "2")
    assert (code, out) == (2, "")
    assert "tcp://127.0.0.1:9: IoError: cannot reach the Dask scheduler within 2 s" in err
    missing = tmp_path / "no-such-log"
    code, out, err = _distributed("replay", "--mission", SHORT_CROSSING, missing)
    assert (code, out) == (2, "")
    assert f"log {missing}: IoError: no such log folder" in err
    code, out, err = _distributed("eval", tmp_path)
    assert (code, out) == (2, "")
    assert "expected a folder of labelled photos holding images/ and labels/" in err
    code, _, err = _distributed("suite", "--junctions", "x")
    assert code == 2 and "invalid int value: 'x'" in err
    code, _, err = _distributed("suite", "--seeds", "1", "--max-frames", "2", "--map-options", '{"nope": 1}',
                                "--workers", "1")
    assert code == 1 and "nope" in err


def test_help_explains_every_flag():
    parser = distributed._parser()
    commands = next(a for a in parser._actions if a.dest == "command").choices
    assert set(commands) == {"suite", "replay", "eval"}
    for name, sub in commands.items():
        for action in sub._actions:
            assert action.help, f"{name} {action.option_strings or action.dest}: no help"
        code, out, _ = _distributed(name, "--help")
        assert code == 0 and "--scheduler ADDRESS" in out and "--output DIR" in out
    code, out, _ = _distributed("--help")
    assert code == 0 and "Exit codes" in out
