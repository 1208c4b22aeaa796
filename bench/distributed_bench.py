#!/usr/bin/env python3
"""mapnav.distributed's figures, measured in one run on this machine (docs/distributed.md):

- the random-campus suite for --seeds on a LocalCluster of 1 worker and of 2 workers (one thread each):
  wall times and their ratio (the results are the same bytes; checked);
- beside them, the single-machine `mapnav suite random-campus --threads 2` on the same seeds (MAPNAV_CLI,
  default build/bin/mapnav): what the cluster costs over threads in one process;
- the scheduler's overhead per task: --noop tasks that do nothing, submitted and gathered, wall time per
  task on the 2-worker cluster.

    PYTHONPATH=build/python python3 bench/distributed_bench.py [--seeds 1-8] [--max-frames 0] [--noop 2000]

Prints one JSON object. Speed is measured here, never asserted in a test.
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import time

from mapnav import distributed


def cluster(workers):
    client, c = distributed._local_client(workers)  # the LocalCluster the module starts itself
    return c, client


def suite_wall(workers, seeds, max_frames):
    c, client = cluster(workers)
    try:
        client.wait_for_workers(workers)
        start = time.perf_counter()
        result = distributed.run_suite(seeds, client, max_frames=max_frames)
        return time.perf_counter() - start, result
    finally:
        client.close()
        c.close()


def cli_wall(seeds, max_frames):
    cli = os.environ.get("MAPNAV_CLI", "build/bin/mapnav")
    start = time.perf_counter()
    done = subprocess.run([cli, "suite", "random-campus", "--seeds", seeds, "--max-frames", str(max_frames),
                           "--threads", "2", "--json"], capture_output=True, text=True)
    if done.returncode not in (0, 1):
        raise SystemExit(f"{cli} suite: exit {done.returncode}: {done.stderr}")
    return time.perf_counter() - start


def noop_per_task_ms(n):
    c, client = cluster(2)
    try:
        client.wait_for_workers(2)
        client.gather(client.map(distributed._nothing, range(50), pure=False))  # warm the workers
        start = time.perf_counter()
        futures = client.map(distributed._nothing, range(n), pure=False)
        assert client.gather(futures) == list(range(n))
        return 1e3 * (time.perf_counter() - start) / n
    finally:
        client.close()
        c.close()


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seeds", default="1-8", help="the suite's seeds (default 1-8)")
    p.add_argument("--max-frames", type=int, default=0, help="per run (default 0: to the goal)")
    p.add_argument("--noop", type=int, default=2000, help="tasks that do nothing, for the overhead (default 2000)")
    args = p.parse_args()
    one, r1 = suite_wall(1, args.seeds, args.max_frames)
    two, r2 = suite_wall(2, args.seeds, args.max_frames)
    assert r1.text == r2.text, "1 and 2 workers gave different results"
    threads = cli_wall(args.seeds, args.max_frames)
    print(json.dumps({
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(), "platform": platform.platform()},
        "suite": {"seeds": args.seeds, "max_frames": args.max_frames, "wall_s_1_worker": round(one, 2),
                  "wall_s_2_workers": round(two, 2), "speedup_2_vs_1": round(one / two, 3),
                  "same_results": True, "cli_threads_2_wall_s": round(threads, 2),
                  "cluster_2_workers_vs_cli_threads_2": round(two / threads, 3)},
        "noop_tasks": args.noop,
        "scheduler_overhead_ms_per_task": round(noop_per_task_ms(args.noop), 3),
    }, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
