"""evaluate_segmentation against `mapnav eval segmentation --json` on three CamVid photos
(../shared/data/real/camvid), and its bad input."""
import json
import shutil

import pytest

import mapnav
from conftest import cli_error, cli_json, shared_data

STEMS = ["0006R0_f00930", "0016E5_00390", "Seq05VD_f00000"]  # three sequences
ROAD, IGNORE = [3, 4], [11]  # CamVid: road and pavement; unlabelled

# A pin-hole of the photos' size, 1.3 m up and tilted 5 degrees down: a camera for the bird's-eye grid
# (CamVid has none; the figures only need to be the CLI's).
CAMERA = {"format": "mapnav-camera/1", "model": "pinhole", "image": {"width": 480, "height": 360},
          "focal_px": [432.0, 432.0], "principal_point": [239.5, 179.5], "distortion": [],
          "mount": {"x": 0.0, "y": 0.0, "height_m": 1.3, "tilt_deg": 5.0, "roll_deg": 0.0, "yaw_deg": 0.0}}


@pytest.fixture(scope="module")
def photos(tmp_path_factory):
    """The three photos and their labels copied to a folder of their own (images/, labels/)."""
    camvid = shared_data("camvid")
    root = tmp_path_factory.mktemp("camvid")
    for folder in ("images", "labels"):
        (root / folder).mkdir()
        for stem in STEMS:
            shutil.copy(camvid / folder / f"{stem}.png", root / folder / f"{stem}.png")
    return root


def eval_args(photos, *more):
    return ["eval", "segmentation", "--images", photos / "images", "--labels", photos / "labels",
            "--road-values", "3,4", "--ignore-values", "11", *more]


def evaluate(photos, pipeline, **kwargs):
    return mapnav.evaluate_segmentation(pipeline, str(photos / "images"), str(photos / "labels"),
                                        road_values=ROAD, ignore_values=IGNORE, **kwargs)


def test_a_pipelines_figures_are_the_clis_json(photos):
    figures = evaluate(photos, mapnav.create_pipeline("sidewalk"))
    assert figures == cli_json(*eval_args(photos, "--pipeline", "sidewalk", "--json"))
    assert figures["images"] == 3 and [p["image"] for p in figures["per_image"]] == [f"{s}.png" for s in STEMS]
    assert figures["space"] == "image" and figures["margin"] is not None


def test_a_pipeline_by_name_with_options_from_the_first_label(photos):
    options = {"adaptive": False}
    figures = evaluate(photos, "color-rgb", options=options, bootstrap="labels-first-frame")
    assert figures == cli_json(*eval_args(photos, "--pipeline", "color-rgb", "--options", json.dumps(options),
                                          "--bootstrap", "labels-first-frame", "--json"))
    assert figures["bootstrap"] == "labels-first-frame" and figures["pipeline"] == "color-rgb"


def test_photos_resized_are_scored_as_the_clis_resize(photos):
    figures = evaluate(photos, "color-rgb", resize=(240, 180))
    assert figures == cli_json(*eval_args(photos, "--pipeline", "color-rgb", "--resize", "240x180", "--json"))
    assert figures != evaluate(photos, "color-rgb")
    with pytest.raises(mapnav.InvalidInput, match="resize_height"):
        evaluate(photos, "color-rgb", resize=(240, 0))


def test_photos_greyed_are_scored_as_the_clis_grey(photos):
    grey = evaluate(photos, "cluster-perceptron", grey=True)
    assert grey == cli_json(*eval_args(photos, "--pipeline", "cluster-perceptron", "--grey", "--json"))
    assert grey != evaluate(photos, "cluster-perceptron")  # the colours were there to lose


def test_a_birds_eye_grid_and_its_overlays_are_the_clis(photos, tmp_path):
    camera = tmp_path / "camera.json"
    camera.write_text(json.dumps(CAMERA))
    figures = evaluate(photos, "blue-band", camera=str(camera), bev=True, bev_range=[-8, 8, 4, 30], bev_cell=0.1,
                       overlays=str(tmp_path / "python"))
    printed = cli_json(*eval_args(photos, "--pipeline", "blue-band", "--camera", camera, "--bev", "--bev-range",
                                  "-8,8,4,30", "--bev-cell", "0.1", "--overlays", tmp_path / "cli", "--json"))
    assert figures == printed
    assert figures["space"] == "bev" and figures["bev"]["columns"] == 160 and figures["bev"]["rows"] == 260
    for stem in STEMS:
        for name in (f"{stem}.png", f"{stem}.bev.png"):
            assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name


def test_a_used_pipeline_carries_what_it_learnt(photos):
    """A Pipeline runs as it is (an adaptive one carries its colours into the next evaluation); after
    reset() it gives the first evaluation's figures again."""
    pipeline = mapnav.create_pipeline("sidewalk")
    first = evaluate(photos, pipeline)
    pipeline.reset()
    assert evaluate(photos, pipeline) == first


def test_bad_input_raises_the_clis_message(photos, tmp_path):
    with pytest.raises(mapnav.IoError) as missing:
        mapnav.evaluate_segmentation("sidewalk", str(tmp_path / "nowhere"), str(photos / "labels"))
    assert str(missing.value) == f"{tmp_path / 'nowhere'}: no such folder (the images)"
    assert str(missing.value) == cli_error("eval", "segmentation", "--images", tmp_path / "nowhere", "--labels",
                                           photos / "labels", expect=2)
    with pytest.raises(mapnav.InvalidInput, match="ignore: label value 3 is also a road value"):
        mapnav.evaluate_segmentation("sidewalk", str(photos / "images"), str(photos / "labels"), road_values=[3],
                                     ignore_values=[3])
    with pytest.raises(mapnav.InvalidInput, match="SegmentationEvalOptions::bev = true: must be false without a camera"):
        evaluate(photos, "sidewalk", bev=True)
    with pytest.raises(mapnav.InvalidInput, match="bootstrap \"middle\": expected trapezoid or labels-first-frame"):
        evaluate(photos, "sidewalk", bootstrap="middle")
    with pytest.raises(mapnav.InvalidInput, match="options: only with a pipeline's name"):
        evaluate(photos, mapnav.create_pipeline("sidewalk"), options={"adaptive": False})
    with pytest.raises(mapnav.NotFound, match="no vision pipeline \"nope\""):
        evaluate(photos, "nope")
