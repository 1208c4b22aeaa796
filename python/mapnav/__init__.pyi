"""Type stubs of the mapnav module (docs/python.md). Arrays are numpy arrays: images uint8
H x W x 3 (RGB) or H x W (masks: 255 = road), points float64 N x 2. Poses are a road position
"R1@I1+3" or (x, y, heading_rad) in the map's frame."""
from typing import Any, Callable, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

Image = npt.NDArray[np.uint8]
Points = npt.NDArray[np.float64]
Pose = Union[str, tuple[float, float, float]]
Options = Union[None, str, dict[str, Any]]

class Error(Exception): ...
class InvalidInput(Error, ValueError): ...
class ValidationError(InvalidInput):
    file: str
    issues: list[Issue]
class IoError(Error, OSError): ...
class NotFound(Error, LookupError): ...

class Issue:
    """One problem found in a file."""
    @property
    def severity(self) -> str: ...
    @property
    def check(self) -> str: ...
    @property
    def pointer(self) -> str: ...
    @property
    def message(self) -> str: ...
    @property
    def line(self) -> int: ...
    def format(self, file: str) -> str: ...

class Map:
    """A validated map (docs/map-format.md)."""
    @staticmethod
    def load(path: str) -> Map: ...
    @staticmethod
    def import_geojson(path: str, origin: Optional[Sequence[float]] = None, snap_tolerance_m: float = 1.0) -> Map: ...
    @property
    def name(self) -> str: ...
    @property
    def road_ids(self) -> list[str]: ...
    @property
    def intersection_ids(self) -> list[str]: ...
    @property
    def landmark_ids(self) -> list[str]: ...
    @property
    def warnings(self) -> list[Issue]: ...
    def validate(self) -> list[Issue]: ...
    def info(self) -> dict[str, Any]: ...
    def pose_at(self, position: Pose) -> tuple[float, float, float]: ...
    def to_json(self) -> str: ...
    def save(self, path: str) -> None: ...
    def export_geojson(self, path: Optional[str] = None, origin: Optional[Sequence[float]] = None) -> str: ...

def validate(path: str) -> list[Issue]: ...

class Camera:
    """A camera: lens model, intrinsics, mount (docs/camera-format.md)."""
    @staticmethod
    def load(path: str) -> Camera: ...
    @staticmethod
    def assumed_photo(width: int, height: int) -> Camera: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def model(self) -> str: ...
    def project(self, point: Sequence[float]) -> Optional[tuple[float, float]]: ...
    def project_points(self, points: npt.ArrayLike) -> Points: ...
    def backproject(self, pixel: Sequence[float]) -> Optional[tuple[float, float]]: ...
    def in_image(self, pixel: Sequence[float]) -> bool: ...
    def to_json(self) -> str: ...

class PredictedRegion:
    id: str
    kind: str
    surface: str
    vehicle: list[Points]
    segments: list[str]

class InterestSegment:
    id: str
    owner: str
    side: str
    vehicle: Points
    image: Points
    left_surface: str
    right_surface: str

class SegmentRelation:
    type: str
    a: str
    b: str
    separation_m: float
    angle_rad: float
    point: tuple[float, float]

class PredictedLandmark:
    id: str
    kind: str
    vehicle: tuple[float, float]
    image_base: tuple[float, float]
    image_top: tuple[float, float]
    width_px: float

class Prediction:
    """What the camera should see from a pose."""
    objects: list[PredictedRegion]
    segments: list[InterestSegment]
    relations: list[SegmentRelation]
    landmarks: list[PredictedLandmark]
    footprint: Points
    pose: tuple[float, float, float]
    camera: Camera
    empty: bool
    road_mask: Image
    def to_json(self) -> str: ...

def predict(map: Map, camera: Camera, pose: Pose, near: float = 1.0, far: float = 15.0) -> Prediction: ...

class Route:
    start: str
    goal: str
    length_m: float
    cost: float
    legs: list[dict[str, Any]]
    roads: list[str]
    intersections: list[str]
    line: Points
    dialogue: str
    def to_json(self) -> str: ...

def route(map: Map, from_: str, to: str, block: Sequence[str] = ...) -> Route: ...

class DetectedLine:
    label: Optional[str]
    score: float
    frame_edge: bool
    image: Points
    vehicle: Points

class Detection:
    ok: bool
    reason: str
    confidence: float
    lines: list[DetectedLine]
    region_image: Points
    region_vehicle: Points
    centerline: Optional[Points]
    road_mask: Optional[Image]
    road_confidence: Optional[Image]
    def to_json(self) -> str: ...

class Segmentation:
    mask: Image
    confidence: Optional[Image]
    detection: Detection

class Pipeline:
    name: str
    def detect(self, image: Image, prediction: Prediction, timestamp: float = 0.0, masks: bool = False) -> Detection: ...
    def segment(self, image: Image, prediction: Prediction, masks: bool = False) -> Segmentation: ...
    def reset(self) -> None: ...

def pipelines() -> list[dict[str, Any]]: ...
def create_pipeline(name: str, options: Options = None) -> Pipeline: ...
def load_plugin(path: str) -> int: ...
def read_image(path: str) -> Image: ...
def write_png(path: str, image: Image) -> None: ...
def prediction_from_region(polygon: npt.ArrayLike, camera: Camera) -> Prediction: ...
def bottom_trapezoid(width: int, height: int) -> Points: ...
def sidewalk_scene(maps: str, frames: int = 8) -> tuple[Camera, list[Image], list[Prediction]]: ...

class ReplayLog:
    """A replay log folder (docs/replay-log-format.md)."""
    @staticmethod
    def open(dir: str, skip_bad_frames: bool = False) -> ReplayLog: ...
    name: str
    camera: Camera
    frame_rate_hz: float
    map: Optional[str]
    skipped: int
    issues: list[Issue]
    frames: list[dict[str, Any]]
    times: npt.NDArray[np.float64]
    odometry: Points
    truth: npt.NDArray[np.float64]
    def __len__(self) -> int: ...
    def image(self, i: int) -> Image: ...
    def mask(self, i: int) -> Optional[Image]: ...

def replay(mission: str, log: str, pipeline: Optional[str] = None, options: Options = None, max_frames: int = 0,
           trace: Optional[str] = None, strict: bool = False, map_options: Options = None) -> dict[str, Any]: ...
def run(mission: str, seed: Optional[int] = None, pipeline: Optional[str] = None, options: Options = None,
        max_frames: int = 0, trace: Optional[str] = None, map_options: Options = None) -> dict[str, Any]: ...
def parse_seed_list(text: str) -> list[int]: ...
def evaluate_segmentation(pipeline: Union[Pipeline, str], images: str, labels: str, road_values: Sequence[int] = ...,
                          ignore_values: Sequence[int] = ..., bootstrap: str = "trapezoid",
                          camera: Optional[str] = None, bev: bool = False,
                          bev_range: Optional[Sequence[float]] = None, bev_cell: Optional[float] = None,
                          overlays: Optional[str] = None, options: Options = None,
                          resize: Optional[tuple[int, int]] = None, grey: bool = False) -> dict[str, Any]: ...
def train_segmentation(output: str, images: Optional[str] = None, labels: Optional[str] = None,
                       logs: Sequence[str] = ..., log_stride: int = 5, road_values: Sequence[int] = ...,
                       ignore_values: Sequence[int] = ..., camera: Optional[str] = None, options: Options = None,
                       progress: Optional[Callable[[dict[str, Any]], None]] = None) -> dict[str, Any]: ...
