"""Maps, validation issues, GeoJSON, info and cameras against the CLI."""
import json
import math

import numpy as np
import pytest

import mapnav
from conftest import CAMPUS, PINHOLE, SOURCE, cli, cli_error, cli_json


def test_load_gives_the_campus(campus):
    assert campus.name == json.load(open(CAMPUS))["name"]
    assert len(campus.road_ids) == 25 and len(campus.intersection_ids) == 17 and len(campus.landmark_ids) == 80
    assert campus.road_ids[0] == "R1"


def test_info_is_the_cli_json(campus):
    assert campus.info() == cli_json("map", "info", CAMPUS, "--json")


def broken_campus(tmp_path):
    doc = json.load(open(CAMPUS))
    doc["roads"][3]["to"] = "I99"
    path = tmp_path / "broken.json"
    path.write_text(json.dumps(doc))
    return str(path)


def test_a_validation_issue_has_its_pointer(tmp_path):
    path = broken_campus(tmp_path)
    issues = mapnav.validate(path)
    unknown = [i for i in issues if i.check == "roads.unknown_intersection"]
    assert [(i.pointer, i.severity) for i in unknown] == [("/roads/3/to", "error")]
    assert "I99" in unknown[0].message
    assert [i.format(path) for i in issues] == cli("map", "validate", path, "--quiet", expect=1)[0].splitlines()


def test_load_raises_the_issues_of_an_invalid_map(tmp_path):
    path = broken_campus(tmp_path)
    with pytest.raises(mapnav.ValidationError) as raised:
        mapnav.Map.load(path)
    assert raised.value.file == path
    assert "/roads/3/to" in [i.pointer for i in raised.value.issues]
    assert isinstance(raised.value, ValueError)


def test_a_valid_map_validates_as_the_cli_says(campus):
    printed = cli("map", "validate", CAMPUS)[0]
    assert printed.endswith(f"{CAMPUS}: valid (0 errors, {len(mapnav.validate(CAMPUS))} warnings)\n")
    assert all(i.severity == "warning" for i in campus.validate())


def test_save_and_load_again_is_the_same_map(campus, tmp_path):
    path = tmp_path / "copy.json"
    campus.save(str(path))
    assert mapnav.Map.load(str(path)).to_json() == campus.to_json() == path.read_text()


def test_geojson_export_is_the_clis_and_imports_back(campus, tmp_path):
    cli_file = tmp_path / "cli.geojson"
    cli("map", "export-geojson", CAMPUS, "-o", cli_file)
    text = campus.export_geojson(str(tmp_path / "py.geojson"))
    assert text == cli_file.read_text() == (tmp_path / "py.geojson").read_text()
    back = mapnav.Map.import_geojson(str(cli_file))
    assert back.road_ids == campus.road_ids and back.landmark_ids == campus.landmark_ids
    assert mapnav.Map.load(str(SOURCE / "maps" / "cmu_campus.geojson")).road_ids == campus.road_ids


def test_geojson_issues_point_into_the_geojson_file():
    path = str(SOURCE / "tests" / "data" / "malformed" / "latitude_out_of_range.geojson")
    issues = mapnav.validate(path)
    assert issues and all(i.pointer.startswith("/features/") for i in issues if i.pointer)
    assert [i.format(path) for i in issues] == [
        line for line in cli("map", "validate", path, "--quiet", expect=1)[0].splitlines()]


def test_a_missing_file_raises_an_io_error_naming_it(tmp_path):
    missing = str(tmp_path / "nowhere.json")
    with pytest.raises(mapnav.IoError, match="nowhere.json") as raised:
        mapnav.Map.load(missing)
    assert isinstance(raised.value, OSError)


def test_pose_at_is_on_the_road(campus):
    x, y, heading = campus.pose_at("R1@I1+3")
    view = cli_json("predict", "--map", CAMPUS, "--camera", PINHOLE, "--at", "R1@I1+3", "--json")
    assert (round(x, 3), round(y, 3), round(math.degrees(heading), 3)) == (
        view["pose"]["x"], view["pose"]["y"], view["pose"]["heading_deg"])
    with pytest.raises(mapnav.NotFound):
        campus.pose_at("R99@I1+3")


def test_camera_projects_and_backprojects(pinhole):
    assert (pinhole.width, pinhole.height, pinhole.model) == (512, 480, "pinhole")
    u, v = pinhole.project((5.0, 0.0, 0.0))
    assert pinhole.in_image((u, v))
    x, y = pinhole.backproject((u, v))
    assert (x, y) == pytest.approx((5.0, 0.0), abs=1e-9)
    assert not pinhole.in_image((-1.0, 10.0)) and pinhole.project((-5.0, 0.0, 0.0)) is None  # behind the camera
    pixels = pinhole.project_points(np.array([[5.0, 0.0, 0.0], [-5.0, 0.0, 0.0]]))
    assert pixels[0] == pytest.approx((u, v)) and np.isnan(pixels[1]).all()
    assert json.loads(pinhole.to_json()) == json.loads(mapnav.Camera.load(PINHOLE).to_json())


def test_bad_camera_input_raises(pinhole):
    with pytest.raises(mapnav.InvalidInput):
        pinhole.project((math.nan, 0.0, 0.0))
    with pytest.raises(mapnav.InvalidInput):
        pinhole.project_points(np.zeros((3, 2)))
    with pytest.raises(mapnav.ValidationError):
        mapnav.Camera.load(CAMPUS)
