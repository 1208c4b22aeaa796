"""mapnav: map-based navigation of small vehicles with one camera.

Maps, cameras, predicted views, routes, vision pipelines on numpy frames, replay logs and missions;
the same library functions the `mapnav` command line calls. See docs/python.md.
"""
import json as _json

from ._mapnav import *  # noqa: F401,F403
from ._mapnav import __version__  # noqa: F401
from ._mapnav import _evaluate_task


def evaluate_segmentation(pipeline, images, labels, **settings):
    """A pipeline (a Pipeline, run as it is: reset() it for a fresh start; or a name, made with `options`)
    over the labelled photos of the folders `images` and `labels`, scored as `mapnav eval segmentation`
    does (docs/eval.md): the dict its --json prints.

    Settings (keywords, as the CLI's flags): road_values [3], ignore_values [], bootstrap 'trapezoid' or
    'labels-first-frame'; camera a camera file (default: the assumed level pin-hole); bev=True scores in a
    bird's-eye grid (needs camera; bev_range (x0, x1, z0, z1) and bev_cell in metres, KITTI's by default);
    overlays a folder; options the pipeline's (with a name); resize (width, height) scores the photos
    resized to that size; grey=True scores them as a grey camera gives them.
    """
    return _json.loads(_evaluate_task(pipeline, images, labels, **settings))
