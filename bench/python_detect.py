#!/usr/bin/env python3
"""What calling `detect` from Python costs against the C++ call: the sidewalk pipeline on the 512 x 480
frames of the sidewalk scene (mapnav/scenes/sidewalk_scene.h), timed in C++ by bench/'s
BM_SidewalkFrame (Google Benchmark, run here as a subprocess) and in Python by the same loop over the
same frames and predictions, in one run. Prints both times per frame and their ratio (docs/python.md).

Usage: PYTHONPATH=build/python python3 bench/python_detect.py [--bench build/bin/mapnav_bench]"""
import argparse
import json
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import mapnav

ROOT = Path(__file__).resolve().parents[1]

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--bench", default=str(ROOT / "build" / "bin" / "mapnav_bench"))
parser.add_argument("--seconds", type=float, default=2.0, help="time per Python repetition")
parser.add_argument("--repetitions", type=int, default=5)
args = parser.parse_args()


def cpp_ms():
    """BM_SidewalkFrame's median real time per frame over the repetitions, ms."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        subprocess.run([args.bench, "--benchmark_filter=^BM_SidewalkFrame$", f"--benchmark_out={out.name}",
                        "--benchmark_out_format=json", f"--benchmark_repetitions={args.repetitions}",
                        f"--benchmark_min_time={args.seconds}", "--benchmark_report_aggregates_only=true"],
                       capture_output=True, check=True)
        runs = json.load(open(out.name))["benchmarks"]
    return next(r["real_time"] for r in runs if r.get("aggregate_name") == "median")


def python_ms():
    """The same loop from Python: median over the repetitions of the mean time per frame, ms."""
    camera, frames, predictions = mapnav.sidewalk_scene(str(ROOT / "maps"))
    pipeline = mapnav.create_pipeline("sidewalk")
    k, times = 0, []
    for _ in range(args.repetitions):
        start, calls = time.perf_counter(), 0
        while time.perf_counter() - start < args.seconds:
            i = k % len(frames)
            k += 1
            pipeline.detect(frames[i], predictions[i], timestamp=float(k))
            calls += 1
        times.append((time.perf_counter() - start) / calls * 1e3)
    return statistics.median(times)


cpp = cpp_ms()
py = python_ms()
print(f"detect, sidewalk pipeline, 512x480: C++ {cpp:.3f} ms, Python {py:.3f} ms per frame; ratio {py / cpp:.3f}")
