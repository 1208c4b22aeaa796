#!/usr/bin/env python3
"""Predict what the camera sees from a road position and show it: the view footprint, the interest
segments and the predicted road mask, plotted with matplotlib when it is installed, else written as
the mask's PNG and listed."""
import argparse
import os
import sys
from pathlib import Path

import numpy as np

import mapnav

ROOT = Path(__file__).resolve().parents[2]

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--map", default=str(ROOT / "maps" / "cmu_campus.json"))
parser.add_argument("--camera", default=str(ROOT / "maps" / "cameras" / "terregator_pinhole.json"))
parser.add_argument("--at", default="R1@I1+3", help="road position, e.g. R1@I1+3")
parser.add_argument("-o", "--output", default="view", help="folder for the pictures")
args = parser.parse_args()

view = mapnav.predict(mapnav.Map.load(args.map), mapnav.Camera.load(args.camera), args.at)
print(f"Vision will see {', '.join(o.kind + ' ' + o.id for o in view.objects)}.")
for s in view.segments:
    length = np.linalg.norm(s.vehicle[1] - s.vehicle[0])
    print(f"  {s.id:14} {length:5.1f} m  left {s.left_surface}, right {s.right_surface}")
mask = view.road_mask
print(f"road mask {mask.shape[1]}x{mask.shape[0]}: {100 * (mask == 255).mean():.1f}% road")

os.makedirs(args.output, exist_ok=True)
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    mapnav.write_png(os.path.join(args.output, "road_mask.png"), mask)
    print(f"wrote {args.output}/road_mask.png (matplotlib is not installed: no plot)")
    sys.exit(0)

figure, (ground, image) = plt.subplots(1, 2, figsize=(11, 5))
ground.fill(view.footprint[:, 1], view.footprint[:, 0], color="0.9", label="footprint")
for s in view.segments:
    ground.plot(s.vehicle[:, 1], s.vehicle[:, 0], lw=2)
    ground.annotate(s.id, s.vehicle.mean(axis=0)[::-1], fontsize=7)
ground.set(xlabel="left, m", ylabel="forward, m", aspect="equal", title=args.at)
ground.invert_xaxis()
image.imshow(mask, cmap="gray")
for s in view.segments:
    image.plot(s.image[:, 0], s.image[:, 1], lw=2)
image.set(title="predicted road and interest segments")
figure.savefig(os.path.join(args.output, "view.png"), dpi=80)
print(f"wrote {args.output}/view.png")
