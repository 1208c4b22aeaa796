"""mapnav: map-based navigation of small vehicles with one camera.

Maps, cameras, predicted views, routes, vision pipelines on numpy frames, replay logs and missions;
the same library functions the `mapnav` command line calls. See docs/python.md.
"""
from ._mapnav import *  # noqa: F401,F403
from ._mapnav import __version__  # noqa: F401
