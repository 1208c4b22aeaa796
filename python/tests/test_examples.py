"""The three examples of examples/python, run as a user would, their figures checked against the CLI."""
import subprocess
import sys

import numpy as np

import mapnav
from conftest import CAMPUS, SOURCE, cli, cli_json, shared_data

EXAMPLES = SOURCE / "examples" / "python"


def example(name, *args, cwd=None):
    done = subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)], capture_output=True, text=True, cwd=cwd)
    assert done.returncode == 0, f"{name}: exit {done.returncode}\n{done.stderr}"
    return done.stdout


def test_predict_view_writes_the_predicted_road(tmp_path, campus, pinhole):
    printed = example("predict_view.py", "-o", tmp_path / "view")
    assert printed.startswith("Vision will see straight road R1.\n  R1.left.0 ")
    mask = mapnav.predict(campus, pinhole, "R1@I1+3").road_mask
    assert f"{100 * (mask == 255).mean():.1f}% road" in printed
    if "road_mask.png" in printed:  # without matplotlib
        assert np.array_equal(mapnav.read_image(str(tmp_path / "view" / "road_mask.png")), mask)
    else:
        assert (tmp_path / "view" / "view.png").is_file()


def test_route_campus_says_the_clis_routes():
    printed = example("route_campus.py")
    for block in ([], ["--block", "R2"]):
        said = cli("route", "--map", CAMPUS, "--from", "R1@I1+3", "--to", "R3@I3+2", *block)[0]
        dialogue = said.rsplit("(", 1)[0].strip()
        assert "  " + dialogue.replace("\n", "\n  ") in printed
    assert "122.1 m over 5 roads, 4 turns" in printed and "131.0 m over 4 roads, 3 turns" in printed


def test_score_camvid_gives_the_iou_of_mapnav_eval():
    camvid = shared_data("camvid")
    printed = example("score_camvid.py", "--photos", camvid)
    scores = cli_json("eval", "segmentation", "--pipeline", "sidewalk", "--images", camvid / "images", "--labels",
                      camvid / "labels", "--road-values", "3,4", "--ignore-values", "11", "--json")
    assert printed == (f"sidewalk: 30 photos, road IoU {scores['iou']:.4f} "
                       f"(everything below the horizon: {scores['baseline_horizon_iou']:.4f})\n")


def test_score_camvid_names_a_missing_folder(tmp_path):
    done = subprocess.run([sys.executable, str(EXAMPLES / "score_camvid.py"), "--photos", str(tmp_path / "camvid")],
                          capture_output=True, text=True)
    assert done.returncode == 1 and f"{tmp_path / 'camvid'}: the CamVid photos are missing" in done.stderr
