#!/usr/bin/env python3
"""Score a vision pipeline's road masks on the shared CamVid photos (../shared/data/real/camvid):
road IoU over the whole set, as `mapnav eval segmentation` (road = labels 3 and 4, 11 ignored),
beside the baseline "everything below the horizon is road"."""
import argparse
import sys
from pathlib import Path

import numpy as np

import mapnav

ROOT = Path(__file__).resolve().parents[2]
ROAD, IGNORE = (3, 4), (11,)

parser = argparse.ArgumentParser(description=__doc__)
parser.add_argument("--photos", default=str(ROOT.parent / "shared" / "data" / "real" / "camvid"))
parser.add_argument("--pipeline", default="sidewalk")
args = parser.parse_args()

photos = Path(args.photos)
if not (photos / "images").is_dir() or not (photos / "labels").is_dir():
    sys.exit(f"score_camvid: {photos}: the CamVid photos are missing (images/ and labels/; "
             "see ../shared/data/real/README.md)")

images = sorted((photos / "images").glob("*.png"))
pipeline = mapnav.create_pipeline(args.pipeline)
counts = {"pipeline": np.zeros(3), "horizon": np.zeros(3)}  # true positives, false positives, false negatives
for path in images:
    image = mapnav.read_image(str(path))
    label = mapnav.read_image(str(photos / "labels" / path.name))
    height, width = label.shape
    camera = mapnav.Camera.assumed_photo(width, height)
    bootstrap = mapnav.prediction_from_region(mapnav.bottom_trapezoid(width, height), camera)
    road, scored = np.isin(label, ROAD), ~np.isin(label, IGNORE)
    below = np.array([camera.backproject((width / 2, v + 0.5)) is not None for v in range(height)])
    masks = {"pipeline": pipeline.segment(image, bootstrap, masks=True).mask == 255,
             "horizon": np.repeat(below[:, None], width, axis=1)}
    for name, mask in masks.items():
        counts[name] += [(mask & road & scored).sum(), (mask & ~road & scored).sum(), (~mask & road & scored).sum()]

iou = {name: tp / (tp + fp + fn) for name, (tp, fp, fn) in counts.items()}
print(f"{args.pipeline}: {len(images)} photos, road IoU {iou['pipeline']:.4f} "
      f"(everything below the horizon: {iou['horizon']:.4f})")
