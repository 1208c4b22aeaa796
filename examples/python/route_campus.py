#!/usr/bin/env python3
"""Plan the papers' dialogue route R1 -> R3 on the campus map, say it, and plan it again with a
road blocked."""
import argparse
from pathlib import Path

import numpy as np

import mapnav

ROOT = Path(__file__).resolve().parents[2]

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--map", default=str(ROOT / "maps" / "cmu_campus.json"))
parser.add_argument("--from", dest="start", default="R1@I1+3")
parser.add_argument("--to", default="R3@I3+2")
parser.add_argument("--block", default="R2", help="roads and intersections not to use, comma-separated")
args = parser.parse_args()

campus = mapnav.Map.load(args.map)
for block in ([], args.block.split(",")):
    route = mapnav.route(campus, args.start, args.to, block=block)
    print(f"{args.start} -> {args.to}" + (f", avoiding {', '.join(block)}" if block else "") + ":")
    print("  " + route.dialogue.replace("\n", "\n  "))
    turns = [leg for leg in route.legs if leg["action"] == "turn"]
    steps = np.linalg.norm(np.diff(route.line, axis=0), axis=1)
    print(f"  {route.length_m:.1f} m over {len(route.roads)} roads, {len(turns)} turns; "
          f"the line has {len(route.line)} points, {steps.sum():.1f} m")
