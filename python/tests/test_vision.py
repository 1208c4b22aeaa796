"""Vision pipelines on numpy frames against `mapnav detect --json` and `mapnav segment`'s PNG, and
the checks of what Python hands in."""
import json

import numpy as np
import pytest

import mapnav
from conftest import CAMPUS, DIALOGUE, PINHOLE, cli, cli_error, cli_json


@pytest.fixture(scope="module")
def frame_file(frame, tmp_path_factory):
    path = tmp_path_factory.mktemp("frame") / "frame.png"
    mapnav.write_png(str(path), frame)
    return str(path)


@pytest.fixture(scope="module")
def view(campus, pinhole):
    return mapnav.predict(campus, pinhole, "R1@I1+3")


def vision_args(command, frame_file, *more):
    return (command, frame_file, "--map", CAMPUS, "--camera", PINHOLE, "--at", "R1@I1+3", *more)


def test_a_png_reads_back_as_the_frame(frame, frame_file):
    assert frame.shape == (480, 512, 3) and frame.dtype == np.uint8
    assert np.array_equal(mapnav.read_image(frame_file), frame)


def test_the_pipelines_are_the_clis():
    names = [p["name"] for p in mapnav.pipelines()]
    assert names[:len(names)] == [n for n in cli("pipelines", "--names")[0].split() if n in names]
    assert {"sidewalk", "cluster-perceptron", "edge-tracker"} <= set(names)
    sidewalk = next(p for p in mapnav.pipelines() if p["name"] == "sidewalk")
    assert {"name", "default", "description"} == set(sidewalk["options"][0])


def test_detect_on_a_numpy_frame_is_the_clis(frame, frame_file, view):
    detection = mapnav.create_pipeline("sidewalk").detect(frame, view)
    printed = json.loads(cli(*vision_args("detect", frame_file, "--json"))[0])
    assert json.loads(detection.to_json()) == printed
    assert detection.ok and printed["status"] == "ok"
    assert [l.label for l in detection.lines] == [l["label"] for l in printed["lines"]]
    assert any(l.label == "R1.left.0" for l in detection.lines)
    # the JSON rounds pixels to 0.01 px
    assert np.allclose(detection.region_image, printed["region_image"], rtol=0, atol=0.5e-2 + 1e-9)


def test_segment_on_a_numpy_frame_is_the_clis_png(frame, frame_file, view, tmp_path):
    mask_file = tmp_path / "mask.png"
    cli(*vision_args("segment", frame_file, "-o", mask_file))
    segmentation = mapnav.create_pipeline("sidewalk").segment(frame, view)
    assert segmentation.mask.shape == (480, 512) and segmentation.mask.dtype == np.uint8
    assert np.array_equal(segmentation.mask, mapnav.read_image(str(mask_file)))
    assert set(np.unique(segmentation.mask)) == {0, 255} and segmentation.confidence is None
    assert segmentation.mask[0, 0] == 0 and segmentation.mask[-1, 256] == 255  # the sky, the road ahead


def test_segment_gives_the_confidence_where_the_pipeline_has_one(frame, view):
    segmentation = mapnav.create_pipeline("sidewalk").segment(frame, view, masks=True)
    assert segmentation.confidence.shape == (480, 512)
    road = segmentation.mask == 255
    assert (segmentation.confidence[road] >= 129).mean() > 0.9


def test_a_region_prediction_segments_as_the_cli(frame, frame_file, pinhole, tmp_path):
    region = "100,470;412,470;300,300;212,300"
    mask_file = tmp_path / "mask.png"
    cli("segment", frame_file, "--camera", PINHOLE, "--train-region", region, "-o", mask_file)
    polygon = np.array([[float(c) for c in p.split(",")] for p in region.split(";")])
    segmentation = mapnav.create_pipeline("sidewalk").segment(frame, mapnav.prediction_from_region(polygon, pinhole))
    assert np.array_equal(segmentation.mask, mapnav.read_image(str(mask_file)))


def test_bad_frames_raise_never_crash(frame, view):
    pipeline = mapnav.create_pipeline("sidewalk")
    with pytest.raises(TypeError, match="uint8"):
        pipeline.detect(frame.astype(np.float32), view)
    with pytest.raises(mapnav.InvalidInput, match=r"\(H, W, 3\), got \(480, 512\)"):
        pipeline.detect(np.ascontiguousarray(frame[:, :, 0]), view)
    with pytest.raises(mapnav.InvalidInput, match="C-contiguous"):
        pipeline.detect(frame[::-1], view)
    with pytest.raises(mapnav.InvalidInput, match="C-contiguous"):
        pipeline.detect(np.asfortranarray(frame), view)
    with pytest.raises(mapnav.InvalidInput, match="the image is 256x480 but the camera's is 512x480"):
        pipeline.detect(np.ascontiguousarray(frame[:, :256]), view)
    with pytest.raises(mapnav.InvalidInput, match="timestamp"):
        pipeline.detect(frame, view, timestamp=float("nan"))
    with pytest.raises(TypeError):
        pipeline.detect("frame.png", view)
    with pytest.raises(mapnav.InvalidInput, match="not finite"):
        mapnav.prediction_from_region([[0, 0], [float("nan"), 1], [2, 2]], view.camera)
    assert pipeline.detect(frame, view).ok  # and the pipeline still works


def test_an_empty_frame_fails_with_a_reason(view):
    detection = mapnav.create_pipeline("sidewalk").detect(np.zeros((480, 512, 3), np.uint8), view)
    assert not detection.ok and detection.reason


def test_pipeline_errors_are_the_clis(frame_file):
    with pytest.raises(mapnav.NotFound) as raised:
        mapnav.create_pipeline("no-such-pipeline")
    assert str(raised.value) == cli_error(*vision_args("detect", frame_file, "--pipeline", "no-such-pipeline"))
    with pytest.raises(mapnav.InvalidInput) as raised:
        mapnav.create_pipeline("sidewalk", {"blend": 2})
    assert str(raised.value) == cli_error(*vision_args("detect", frame_file, "--options", '{"blend": 2}'))


def test_the_learned_pipeline_is_created_from_python_as_the_cli_runs_it(frame, frame_file, view, tmp_path):
    """create_pipeline("learned") opens the learned module (Torch) itself; its mask is the CLI's."""
    options = {"model": "sim"}
    mask_file = tmp_path / "learned.png"
    cli(*vision_args("segment", frame_file, "-o", mask_file, "--pipeline", "learned", "--options", json.dumps(options)))
    learned = mapnav.create_pipeline("learned", options)
    assert learned.name == "learned"
    segmentation = learned.segment(frame, view)
    assert np.array_equal(segmentation.mask, mapnav.read_image(str(mask_file)))
    assert segmentation.mask[-1, 256] == 255  # the path ahead


def test_train_segmentation_makes_the_clis_model(frame, view, tmp_path):
    """train_segmentation on a simulated log's truth masks: the summary --json prints, a progress call per
    epoch, and the same weights as `mapnav train segmentation` (the same probabilities on a frame)."""
    log = tmp_path / "log"
    cli("simulate", "--mission", DIALOGUE, "--seed", "5", "--max-frames", "6", "-o", log)
    printed = cli_json("train", "segmentation", "--log", log, "--log-stride", "2", "--epochs", "2", "--size", "64x60",
                       "--threads", "1", "-o", tmp_path / "cli.mnseg", "--json")
    epochs = []
    model = str(tmp_path / "python.mnseg")
    summary = mapnav.train_segmentation(model, logs=[str(log)], log_stride=2,
                                        options={"epochs": 2, "width": 64, "height": 60, "threads": 1},
                                        progress=epochs.append)
    assert summary == {**printed, "model": model}
    assert summary["training_images"] + summary["validation_images"] == 3  # frames 0, 2, 4
    assert [e["epoch"] for e in epochs] == [1, 2] and epochs[-1]["loss"] == pytest.approx(summary["final_loss"], abs=1e-4)
    ours = mapnav.create_pipeline("learned", {"model": model}).segment(frame, view, masks=True)
    theirs = mapnav.create_pipeline("learned", {"model": str(tmp_path / "cli.mnseg")}).segment(frame, view, masks=True)
    assert ours.confidence is not None and np.array_equal(ours.confidence, theirs.confidence)


def test_train_segmentation_names_bad_input_and_writes_nothing(tmp_path):
    model = tmp_path / "m.mnseg"
    with pytest.raises(mapnav.InvalidInput, match="nothing to train on"):
        mapnav.train_segmentation(str(model))
    with pytest.raises(mapnav.InvalidInput, match="images and labels go together"):
        mapnav.train_segmentation(str(model), images=str(tmp_path))
    with pytest.raises(mapnav.InvalidInput, match="options: option epochs = 0: must be in"):
        mapnav.train_segmentation(str(model), logs=[str(tmp_path)], options={"epochs": 0})
    with pytest.raises(mapnav.InvalidInput, match="progress: must be callable"):
        mapnav.train_segmentation(str(model), logs=[str(tmp_path)], progress=3)
    with pytest.raises(mapnav.IoError):
        mapnav.train_segmentation(str(model), logs=[str(tmp_path / "no-such-log")])
    assert list(tmp_path.iterdir()) == []
