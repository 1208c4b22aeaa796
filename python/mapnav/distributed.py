"""mapnav.distributed: the random-campus suite, batch replays and evaluations on a Dask cluster.

Each seed, log or photo folder is one task: inputs in, JSON text out (a worker writes files only under
the output folder, in a folder named for its task). The results are gathered, in the order asked, into
exactly what the single-machine command prints: `mapnav suite random-campus --json`, one
`mapnav replay --json` line per log, each folder's `mapnav eval segmentation --json` document, one after
another.

    from mapnav.distributed import run_suite
    result = run_suite("1-30", map_error_m=0.5)       # a LocalCluster on this machine
    print(result.text, end="")                        # the bytes `mapnav suite ... --json` prints

`client=None` starts a LocalCluster (one single-threaded worker process per core) and stops it after;
give a `dask.distributed.Client` to run on a cluster. A worker that dies mid-task has its task re-run
on another (the scheduler's allowed-failures, 3 by default); a task that raises is retried `retries`
times and then reported with its seed, log or folder and the error, never dropped. With `output`, each
finished task's result is kept in OUTPUT/results/ and a run started again over the same folder, with
the same inputs, does not redo them. docs/distributed.md says how to start a cluster, by hand or under
Slurm. As a command: `python3 -m mapnav.distributed --help`.
"""
from __future__ import annotations

import argparse
import json as _json
import logging
import os
import shutil
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Sequence

from mapnav import _mapnav

try:
    from distributed import Client, LocalCluster, as_completed
except ImportError as _missing:  # pragma: no cover - the message is the point
    raise ImportError(
        "mapnav.distributed needs Dask's distributed scheduler: apt-get install python3-distributed "
        f"(scripts/setup installs it) ({_missing})"
    ) from _missing

__all__ = ["Gathered", "TaskError", "run_suite", "replay_logs", "evaluate", "main"]

# The CLI's exit codes (apps/src/cli.h).
EXIT_OK, EXIT_INVALID, EXIT_USAGE = 0, 1, 2

_CAMERA = "maps/cameras/terregator_pinhole.json"  # the suite's camera, as `mapnav suite` uses it


class TaskError(Exception):
    """A task that raised: which task (seed, log or folder), the error's kind and message, and the
    exit code the CLI gives for it (1 invalid input, 2 I/O and other errors). Plain arguments only, so
    that it travels between processes."""

    def __init__(self, task: str, kind: str, message: str, exit_code: int):
        super().__init__(task, kind, message, exit_code)
        self.task, self.kind, self.message, self.exit_code = task, kind, message, exit_code

    def __str__(self) -> str:
        return f"{self.task}: {self.kind}: {self.message}"


@dataclass
class Gathered:
    """What a batch came to. `text`: the bytes the single-machine command prints (for a suite its one
    JSON line or its table; for replays and evaluations each log's or folder's, one after another in
    the order given); `results`: each task's own text, in that order; `exit_code`: the command's (0 every
    mission reached its goal or was cut short by max_frames, 1 some did not or the input is invalid,
    2 an I/O error); `failures`: the tasks that raised, as TaskError (then `text` is empty)."""

    text: str
    results: list[str]
    exit_code: int
    failures: list[TaskError] = field(default_factory=list)
    per_task: bool = True  # text is a line per task (replays, evaluations), not one document (a suite)

    def json(self):
        """`text` read as JSON: the suite's object (from json=True), or a list of one object per log or folder."""
        if not self.per_task:
            return _json.loads(self.text)
        decoder, documents, at = _json.JSONDecoder(), [], 0
        while self.text[at:].strip():
            at += len(self.text[at:]) - len(self.text[at:].lstrip())
            document, at = decoder.raw_decode(self.text, at)
            documents.append(document)
        return documents


# ---- the tasks (run on the workers) ----------------------------------------------------------------


def _data_file(relative: str) -> str:
    """A shipped file: beside an installed module (PREFIX/lib/python3/dist-packages/mapnav ->
    PREFIX/share/mapnav), else in the source tree the module was built from."""
    installed = Path(__file__).resolve().parents[4] / "share" / "mapnav" / relative
    if installed.is_file():
        return str(installed)
    return str(Path(_mapnav._source_dir) / relative)


def _guarded(task: str, call: Callable[[], object]):
    """Runs `call`, turning the library's errors into a TaskError naming `task`."""
    try:
        return call()
    except _mapnav.InvalidInput as e:
        raise TaskError(task, type(e).__name__, str(e), EXIT_INVALID) from None
    except Exception as e:  # IoError, NotFound, OSError, anything: reported, never dropped
        raise TaskError(task, type(e).__name__, str(e), EXIT_USAGE) from None


def _suite_task(seed: int, folder: str | None, options: dict, map_options: dict | None) -> str:
    def run() -> str:
        if folder is not None:
            return _mapnav._suite_seed(seed, folder, _data_file(_CAMERA), options, map_options)
        scratch = tempfile.mkdtemp(prefix=f"mapnav-suite-seed-{seed}-")
        try:
            return _mapnav._suite_seed(seed, scratch, _data_file(_CAMERA), options, map_options)
        finally:
            shutil.rmtree(scratch, ignore_errors=True)

    return _guarded(f"seed {seed}", run)


def _replay_task(mission: str, log: str, settings: dict) -> str:
    def run() -> str:
        text, summary, ok = _mapnav._replay_task(mission, log, **settings)
        return _json.dumps({"json": text, "summary": summary, "ok": ok})

    return _guarded(f"log {log}", run)


def _evaluate_task(pipeline: str, images: str, labels: str, settings: dict) -> str:
    return _guarded(f"folder {Path(images).parent}", lambda: _mapnav._evaluate_task(pipeline, images, labels, **settings))


def _nothing(i: int) -> int:
    """A task that does nothing: the scheduler's overhead per task (bench/distributed_bench.py)."""
    return i


# ---- running a batch (on the client) ---------------------------------------------------------------


class _Progress:
    """done / running / failed, the rate and the time left, on `stream`: redrawn in place on a terminal,
    a line per finished task otherwise; nothing when not `enabled`."""

    def __init__(self, total: int, enabled: bool, stream=None):
        self.total, self.enabled = total, enabled
        self.stream = stream or sys.stderr
        self.tty = self.enabled and hasattr(self.stream, "isatty") and self.stream.isatty()
        self.start = time.monotonic()

    def show(self, done: int, running: int, failed: int, resumed: int = 0) -> None:
        if not self.enabled:
            return
        elapsed = time.monotonic() - self.start
        fresh = done - resumed
        rate = fresh / elapsed if elapsed > 0 else 0.0
        left = (self.total - done - failed) / rate if rate > 0 else float("nan")
        width = 24
        filled = int(width * (done + failed) / self.total) if self.total else width
        bar = "#" * filled + "-" * (width - filled)
        eta = f"{left:.0f} s left" if left == left else "time left unknown"
        line = (f"[{bar}] {done}/{self.total} done, {running} running, {failed} failed, "
                f"{rate:.2f} tasks/s, {eta}")
        if self.tty:
            self.stream.write("\r" + line + "\x1b[K")
        else:
            self.stream.write(line + "\n")
        self.stream.flush()

    def close(self) -> None:
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()


class _Folder:
    """The output folder of a batch: OUTPUT/run.json says what was asked (a run started again over
    the folder must ask the same), OUTPUT/results/NAME.json holds each finished task's text."""

    def __init__(self, path: str | os.PathLike | None, asked: dict):
        self.path = Path(path) if path is not None else None
        if self.path is None:
            return
        results = self.path / "results"
        try:
            results.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise TaskError(str(self.path), "IoError", f"cannot create the output folder: {e.strerror}", EXIT_USAGE) from None
        run = self.path / "run.json"
        if run.exists():
            try:
                before = _json.loads(run.read_text())
            except (OSError, ValueError) as e:
                raise TaskError(str(run), "InvalidInput", f"not a run's description ({e})", EXIT_INVALID) from None
            if before != asked:
                raise TaskError(str(run), "InvalidInput",
                                "the folder holds a run that asked for other things (its run.json: "
                                f"{_json.dumps(before, sort_keys=True)}); give another output folder",
                                EXIT_INVALID)
        else:
            self._write(run, _json.dumps(asked, sort_keys=True, indent=1) + "\n")

    def done(self, name: str) -> str | None:
        """The finished task's text, or None (not run, or its file cut short: it runs again)."""
        if self.path is None:
            return None
        f = self.path / "results" / f"{name}.json"
        try:
            text = f.read_text()
        except OSError:
            return None
        return text if text.endswith("\n") else None

    def keep(self, name: str, text: str) -> None:
        if self.path is not None:
            self._write(self.path / "results" / f"{name}.json", text + "\n")

    @staticmethod
    def _write(path: Path, text: str) -> None:
        """Whole or not at all: a temporary file beside it, renamed."""
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
        tmp.write_text(text)
        os.replace(tmp, path)


def _local_client(workers: int | None) -> tuple[Client, LocalCluster]:
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                           dashboard_address=None, silence_logs=logging.ERROR)
    return Client(cluster), cluster


def _run(tasks: Sequence[tuple[str, Callable, tuple]], client: Client | None, folder: _Folder, progress: bool,
         retries: int, workers: int | None = None) -> tuple[list[str | None], list[TaskError]]:
    """Runs `tasks` (name, function, arguments): each finished one's text in the order of `tasks`
    (None where it failed), and the failures in that order."""
    texts: list[str | None] = [folder.done(name) for name, _, _ in tasks]
    todo = [i for i, t in enumerate(texts) if t is None]
    resumed = len(tasks) - len(todo)
    bar = _Progress(len(tasks), progress)
    failures: dict[int, TaskError] = {}
    if todo:
        cluster = None
        if client is None:
            client, cluster = _local_client(workers)
        try:
            futures = {}
            for i in todo:
                name, fn, args = tasks[i]
                futures[client.submit(fn, *args, key=f"mapnav-{name}-{os.getpid()}-{time.time_ns()}",
                                      retries=retries, pure=False)] = i
            done = resumed
            bar.show(done, min(len(todo), _slots(client)), 0, resumed)
            for future in as_completed(futures):
                i = futures[future]
                if future.status == "finished":
                    texts[i] = future.result()
                    folder.keep(tasks[i][0], texts[i])
                    done += 1
                else:
                    failures[i] = _failure(tasks[i][0], future)
                remaining = len(tasks) - done - len(failures)
                bar.show(done, min(remaining, _slots(client)), len(failures), resumed)
        finally:
            bar.close()
            if cluster is not None:
                client.close()
                cluster.close()
    return texts, [failures[i] for i in sorted(failures)]


def _slots(client: Client) -> int:
    """Tasks the cluster runs at once (its workers' threads)."""
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:  # a scheduler gone away: the count is only for the bar
        return 1


def _failure(name: str, future) -> TaskError:
    error = future.exception()
    if isinstance(error, TaskError):
        return error
    # A worker that died more often than the scheduler allows (KilledWorker), a lost connection.
    return TaskError(name, type(error).__name__, str(error), EXIT_USAGE)


def _seed_list(seeds: str | Iterable[int]) -> list[int]:
    if isinstance(seeds, str):
        return _mapnav.parse_seed_list(seeds)
    out: list[int] = []
    for s in seeds:
        if isinstance(s, bool) or not isinstance(s, int) or s < 0:
            raise _mapnav.InvalidInput(f"seeds: {s!r} is not a seed (a whole number >= 0)")
        if s not in out:
            out.append(s)
    if not out:
        raise _mapnav.InvalidInput("seeds: empty; give at least one seed")
    return out


def _failed(results: list, failures: list[TaskError]) -> Gathered:
    return Gathered("", [r for r in results if r is not None], max(f.exit_code for f in failures), failures)


def run_suite(seeds: str | Iterable[int], client: Client | None = None, *, output: str | os.PathLike | None = None,
              map_options: dict | str | None = None, wall_time: bool = False, json: bool = True,
              progress: bool = False, retries: int = 2, workers: int | None = None, **options) -> Gathered:
    """`mapnav suite random-campus` with each seed a task. `seeds` "1-30" (as --seeds) or ints;
    `options` SuiteOptions' fields (junctions, map_error_m, max_frames, world_json, odometry_json:
    `mapnav options SuiteOptions`); `map_options` the Map module's (as --map-options). `output`: each
    seed's map.json and mission.json in OUTPUT/seed-N/ (written by the worker) and the results kept for
    a resumed run; none: each worker uses a scratch folder of its own. `wall_time` as the CLI without
    --no-wall-time (its wall times differ from run to run); `json` False prints the table instead."""
    seed_list = _seed_list(seeds)
    options.pop("threads", None)  # each task is one seed: a worker's threads are the cluster's business
    folder = _Folder(output, {"kind": "suite", "options": options, "map_options": map_options})
    seed_folder = str(Path(output).resolve()) if output is not None else None
    tasks = [(f"seed-{s}", _suite_task, (s, seed_folder, options, map_options)) for s in seed_list]
    results, failures = _run(tasks, client, folder, progress, retries, workers)
    if failures:
        return _failed(results, failures)
    text = _mapnav._suite_report(results, options, map_options, json=json, wall_time=wall_time)
    ok = all(r["reached"] or (r["stopped_early"] and not r["error"]) for r in map(_json.loads, results))
    return Gathered(text, results, EXIT_OK if ok else EXIT_INVALID, per_task=False)


def _task_names(paths: Sequence[str]) -> list[str]:
    return [f"{i:04d}-{Path(p).name or 'folder'}" for i, p in enumerate(paths)]


def replay_logs(mission: str | os.PathLike, logs: Iterable[str | os.PathLike], client: Client | None = None, *,
                output: str | os.PathLike | None = None, pipeline: str | None = None,
                options: dict | str | None = None, map_options: dict | str | None = None, use_gnss: bool = False,
                max_frames: int = 0, strict: bool = False, json: bool = True, progress: bool = False,
                retries: int = 2, workers: int | None = None) -> Gathered:
    """`mapnav replay --mission MISSION --log LOG --json` for each log, a task each; the logs are read
    by the workers where they lie (shared storage), not sent through the scheduler. `json` False: each
    log's summary as `mapnav replay` prints it, under a line naming the log."""
    logs = [str(Path(p)) for p in logs]
    mission = str(Path(mission).resolve())
    if not Path(mission).is_file():
        raise TaskError(mission, "IoError", "no such mission file", EXIT_USAGE)
    if not logs:
        raise _mapnav.InvalidInput("logs: empty; give at least one replay log folder")
    for log in logs:
        if not Path(log).is_dir():
            raise TaskError(f"log {log}", "IoError", "no such log folder", EXIT_USAGE)
    mo = dict(_json.loads(map_options) if isinstance(map_options, str) else (map_options or {}))
    if use_gnss:
        mo["use_gnss"] = True
    settings = {"pipeline": pipeline, "options": options, "max_frames": max_frames, "strict": strict,
                "map_options": mo or None}
    absolute = [str(Path(p).resolve()) for p in logs]
    folder = _Folder(output, {"kind": "replay", "mission": mission, "logs": absolute, "settings": settings})
    tasks = [(name, _replay_task, (mission, log, settings)) for name, log in zip(_task_names(logs), absolute)]
    results, failures = _run(tasks, client, folder, progress, retries, workers)
    if failures:
        return _failed(results, failures)
    runs = [_json.loads(r) for r in results]
    if json:
        text = "".join(run["json"] for run in runs)
    else:
        text = "".join(f"== {log}\n{run['summary']}" for log, run in zip(logs, runs))
    return Gathered(text, [run["json"] for run in runs], EXIT_OK if all(run["ok"] for run in runs) else EXIT_INVALID)


def _labelled(folder: str) -> tuple[str, str]:
    f = Path(folder)
    images, labels = f / "images", f / "labels"
    if not images.is_dir() or not labels.is_dir():
        raise TaskError(f"folder {folder}", "IoError",
                        "expected a folder of labelled photos holding images/ and labels/ (as ../shared/data/real/camvid)",
                        EXIT_USAGE)
    return str(images.resolve()), str(labels.resolve())


def evaluate(pipeline: str, image_dirs: Iterable[str | os.PathLike], client: Client | None = None, *,
             output: str | os.PathLike | None = None, options: dict | str | None = None,
             road_values: Sequence[int] = (3,), ignore_values: Sequence[int] = (), bootstrap: str = "trapezoid",
             resize: tuple[int, int] | None = None, progress: bool = False, retries: int = 2,
             workers: int | None = None) -> Gathered:
    """`mapnav eval segmentation --pipeline PIPELINE --images DIR/images --labels DIR/labels --json` for
    each folder of `image_dirs`, a task each (a folder's photos are read by the worker where they lie)."""
    dirs = [str(Path(d)) for d in image_dirs]
    if not dirs:
        raise _mapnav.InvalidInput("image_dirs: empty; give at least one folder of labelled photos")
    pairs = [_labelled(d) for d in dirs]
    settings = {"road_values": list(road_values), "ignore_values": list(ignore_values), "bootstrap": bootstrap,
                "options": options, "resize": list(resize) if resize else None}
    folder = _Folder(output, {"kind": "eval", "pipeline": pipeline, "folders": [p[0] for p in pairs],
                              "settings": settings})
    tasks = [(name, _evaluate_task, (pipeline, images, labels, settings))
             for name, (images, labels) in zip(_task_names(dirs), pairs)]
    results, failures = _run(tasks, client, folder, progress, retries, workers)
    if failures:
        return _failed(results, failures)
    return Gathered("".join(results), results, EXIT_OK)


# ---- the command -----------------------------------------------------------------------------------


def _parser() -> argparse.ArgumentParser:
    common = argparse.ArgumentParser(add_help=False)
    where = common.add_argument_group("where it runs")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="a running Dask scheduler, e.g. tcp://HOST:8786 (default: a LocalCluster on this machine)")
    where.add_argument("--workers", type=int, metavar="N",
                       help="the LocalCluster's workers, one thread each (default: one per core; not with --scheduler)")
    where.add_argument("--timeout", type=float, default=10.0, metavar="S",
                       help="seconds to wait for the scheduler to answer (default 10)")
    where.add_argument("-o", "--output", metavar="DIR",
                       help="keep each task's result in DIR/results/ (and the suite's maps and missions in DIR/seed-N/); "
                            "run again over DIR with the same inputs to resume without redoing finished tasks")
    where.add_argument("--retries", type=int, default=2, metavar="N",
                       help="times a task that raised is run again before it is reported (default 2; a worker that "
                            "dies has its tasks re-run anyway)")
    where.add_argument("--no-progress", action="store_true", help="no progress on stderr")
    where.add_argument("--json", action="store_true",
                       help="print what the single-machine command prints with --json")

    p = argparse.ArgumentParser(
        prog="python3 -m mapnav.distributed",
        description="Run mapnav's suite, replays or evaluations as tasks on a Dask cluster (docs/distributed.md). "
                    "The output is what the single-machine command prints; progress (done / running / failed, "
                    "rate, time left) goes to stderr.",
        epilog="Exit codes, as the mapnav command's: 0 every mission reached its goal (or --max-frames cut it) or "
               "every folder was scored, 1 some did not or the input is invalid (a seed list that runs backwards), "
               "2 usage or I/O error (an unreachable scheduler, a missing log or folder).")
    sub = p.add_subparsers(dest="command", required=True, metavar="{suite,replay,eval}")

    s = sub.add_parser("suite", parents=[common], help="mapnav suite random-campus, a seed a task",
                       description="`mapnav suite random-campus` with each seed a task; --json prints the bytes "
                                   "`mapnav suite random-campus --json` prints for the same seeds and options.")
    s.add_argument("--seeds", default="1-30", help="seeds, one map and mission each: ranges and lists, e.g. 1-1000 "
                                                   "or 1,4,9-12 (default 1-30)")
    s.add_argument("--junctions", type=int, help="junctions along each campus' spine (default: the suite's, 3)")
    s.add_argument("--map-error-m", type=float, help="how wrong each map is, m (as mapnav suite --map-error-m)")
    s.add_argument("--max-frames", type=int, help="stop each run after this many frames (default: to the goal)")
    s.add_argument("--map-options", metavar="JSON", help="the Map module's options as a JSON object")
    s.add_argument("--no-wall-time", action="store_true", help="leave out wall times: the same bytes for the same seeds")

    r = sub.add_parser("replay", parents=[common], help="mapnav replay over many logs, a log a task",
                       description="`mapnav replay --mission MISSION --log LOG` for each LOG, a task each; --json "
                                   "prints one `mapnav replay --json` line per log, in the order given. The logs "
                                   "are read by the workers where they lie (shared storage).")
    r.add_argument("--mission", required=True, help="the mission file")
    r.add_argument("logs", nargs="+", metavar="LOG", help="replay log folders (mapnav simulate, mapnav log import-*)")
    r.add_argument("--pipeline", help="vision pipeline (default: the mission's)")
    r.add_argument("--options", metavar="JSON", help="the pipeline's options as a JSON object")
    r.add_argument("--map-options", metavar="JSON", help="the Map module's options as a JSON object")
    r.add_argument("--use-gnss", action="store_true", help="fuse each log's GNSS fixes (as mapnav replay --use-gnss)")
    r.add_argument("--max-frames", type=int, default=0, help="stop each replay after this many frames")
    r.add_argument("--strict", action="store_true", help="stop a replay at its log's first fault")

    e = sub.add_parser("eval", parents=[common], help="mapnav eval segmentation over many folders, a folder a task",
                       description="`mapnav eval segmentation --json` for each FOLDER (holding images/ and labels/), "
                                   "a task each; prints each folder's JSON document as that command does, one after "
                                   "another in the order given (with or without --json).")
    e.add_argument("folders", nargs="+", metavar="FOLDER", help="folders of labelled photos, each with images/ and labels/")
    e.add_argument("--pipeline", default="sidewalk", help="vision pipeline (default sidewalk; mapnav pipelines lists them)")
    e.add_argument("--options", metavar="JSON", help="the pipeline's options as a JSON object")
    e.add_argument("--road-values", default="3", help="label values that are road, comma-separated (default 3)")
    e.add_argument("--ignore-values", default="", help="label values left out of the scores, comma-separated")
    e.add_argument("--bootstrap", default="trapezoid", choices=["trapezoid", "labels-first-frame"],
                   help="the road region the pipeline trains on (default trapezoid)")
    e.add_argument("--resize", metavar="WxH", help="score the photos resized to WxH pixels, e.g. 320x240")
    return p


def _numbers(flag: str, text: str) -> list[int]:
    try:
        return [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise _mapnav.InvalidInput(f"{flag} '{text}': expected whole numbers separated by commas") from None


def _size(text: str) -> tuple[int, int]:
    w, x, h = text.partition("x")
    if not (x and w.isdigit() and h.isdigit()):
        raise _mapnav.InvalidInput(f"--resize '{text}': expected WIDTHxHEIGHT in pixels (e.g. 320x240)")
    return int(w), int(h)


def _json_flag(flag: str, text: str | None):
    if text is None:
        return None
    try:
        value = _json.loads(text)
    except ValueError as e:
        raise _mapnav.InvalidInput(f"{flag}: not JSON ({e})") from None
    if not isinstance(value, dict):
        raise _mapnav.InvalidInput(f"{flag}: expected a JSON object")
    return value


def _connect(args) -> Client | None:
    if args.scheduler is None:
        return None
    if args.workers is not None:
        raise _mapnav.InvalidInput("--workers: only for the LocalCluster (the scheduler's workers are its own)")
    try:
        return Client(args.scheduler, timeout=f"{args.timeout}s")
    except (OSError, TimeoutError, ValueError) as e:
        raise TaskError(args.scheduler, "IoError",
                        f"cannot reach the Dask scheduler within {args.timeout:g} s ({e})", EXIT_USAGE) from None


def _dispatch(args) -> Gathered:
    common = {"output": args.output, "progress": not args.no_progress, "retries": args.retries,
              "workers": args.workers}
    if args.retries < 0:
        raise _mapnav.InvalidInput(f"--retries {args.retries}: expected 0 or more")
    if args.workers is not None and args.workers < 1:
        raise _mapnav.InvalidInput(f"--workers {args.workers}: expected 1 or more")
    # Each command's flags are read first (bad input is told before any connection), then it runs on
    # the scheduler's client, which is closed after, or on a LocalCluster of its own (client None).
    if args.command == "suite":
        seeds = _seed_list(args.seeds)
        options = {k: v for k, v in (("junctions", args.junctions), ("map_error_m", args.map_error_m),
                                     ("max_frames", args.max_frames)) if v is not None}
        map_options = _json_flag("--map-options", args.map_options)

        def run(client):
            return run_suite(seeds, client, map_options=map_options, wall_time=not args.no_wall_time,
                             json=args.json, **common, **options)
    elif args.command == "replay":
        options, map_options = _json_flag("--options", args.options), _json_flag("--map-options", args.map_options)

        def run(client):
            return replay_logs(args.mission, args.logs, client, pipeline=args.pipeline, options=options,
                               map_options=map_options, use_gnss=args.use_gnss, max_frames=args.max_frames,
                               strict=args.strict, json=args.json, **common)
    else:
        options = _json_flag("--options", args.options)
        settings = {"road_values": _numbers("--road-values", args.road_values),
                    "ignore_values": _numbers("--ignore-values", args.ignore_values), "bootstrap": args.bootstrap,
                    "resize": _size(args.resize) if args.resize else None}

        def run(client):
            return evaluate(args.pipeline, args.folders, client, options=options, **settings, **common)
    client = _connect(args)
    try:
        return run(client)
    finally:
        if client is not None:
            client.close()


def main(argv: Sequence[str] | None = None) -> int:
    """The command: `python3 -m mapnav.distributed {suite,replay,eval} ...`; returns its exit code."""
    args = _parser().parse_args(argv)
    try:
        result = _dispatch(args)
    except TaskError as e:
        print(f"mapnav.distributed: error: {e}", file=sys.stderr)
        return e.exit_code
    except _mapnav.InvalidInput as e:
        print(f"mapnav.distributed: error: {e}", file=sys.stderr)
        return EXIT_INVALID
    except _mapnav.Error as e:
        print(f"mapnav.distributed: error: {e}", file=sys.stderr)
        return EXIT_USAGE
    for failure in result.failures:
        print(f"mapnav.distributed: error: {failure}", file=sys.stderr)
    sys.stdout.write(result.text)
    sys.stdout.flush()
    return result.exit_code


if __name__ == "__main__":
    sys.exit(main())
