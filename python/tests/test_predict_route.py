"""Predicted views and routes against `mapnav predict --json` and `mapnav route --json`."""
import json
import math

import numpy as np
import pytest

import mapnav
from conftest import CAMPUS, PINHOLE, cli, cli_error, cli_json


@pytest.fixture(scope="module")
def view(campus, pinhole):
    return mapnav.predict(campus, pinhole, "R1@I1+3")


@pytest.fixture(scope="module")
def cli_view():
    return cli_json("predict", "--map", CAMPUS, "--camera", PINHOLE, "--at", "R1@I1+3", "--json")


def test_the_predicted_view_is_the_clis(view, cli_view):
    assert json.loads(view.to_json()) == cli_view


def test_the_objects_are_the_clis(view, cli_view):
    printed = cli_view["view"]
    assert [(o.id, o.kind, o.surface) for o in view.objects] == [
        (o["id"], o["kind"], o["surface"]) for o in printed["regions"]]
    assert [o.id for o in view.objects] == ["R1"]
    segments = {s["id"]: s for s in printed["segments"]}
    assert sorted(s.id for s in view.segments) == sorted(segments)
    for s in view.segments:
        assert s.vehicle.shape == (2, 2) and s.image.shape == (2, 2)
        # the JSON rounds metres to 0.1 mm and pixels to 0.01 px
        assert np.allclose(s.vehicle, segments[s.id]["vehicle"], rtol=0, atol=0.5e-4 + 1e-9)
        assert np.allclose(s.image, segments[s.id]["image"], rtol=0, atol=0.5e-2 + 1e-9)
        assert (s.left_surface, s.right_surface) == (segments[s.id]["left_surface"], segments[s.id]["right_surface"])


def test_the_relations_are_the_clis(view, cli_view):
    printed = cli_view["view"]["relations"]
    assert [(r.type, r.a, r.b) for r in view.relations] == [(r["type"], r["a"], r["b"]) for r in printed]
    for r, c in zip(view.relations, printed):
        if r.type == "parallel":
            assert abs(r.separation_m - c["separation_m"]) <= 0.5e-4 + 1e-9  # metres to 0.1 mm
        else:
            assert abs(math.degrees(r.angle_rad) - c["angle_deg"]) <= 0.5e-4 + 1e-9  # degrees to 1e-4


def test_the_road_mask_covers_the_road_ahead(view, pinhole):
    mask = view.road_mask
    assert mask.shape == (480, 512) and mask.dtype == np.uint8 and set(np.unique(mask)) == {0, 255}
    segment = {s.id: s for s in view.segments}
    left, right = segment["R1.left.0"].image, segment["R1.right.0"].image
    # Between the road's two edges at the bottom of their image segments: road; the sky: not.
    u = int((left[:, 0].mean() + right[:, 0].mean()) / 2)
    v = int(max(left[:, 1].max(), right[:, 1].max())) - 2
    assert mask[v, u] == 255 and mask[0, 0] == 0


def test_a_pose_tuple_gives_the_same_view(campus, pinhole, view):
    assert json.loads(mapnav.predict(campus, pinhole, campus.pose_at("R1@I1+3")).to_json()) == json.loads(view.to_json())


def test_bad_poses_raise_the_clis_messages(campus, pinhole):
    with pytest.raises(mapnav.InvalidInput, match="must be finite"):
        mapnav.predict(campus, pinhole, (math.nan, 0.0, 0.0))
    with pytest.raises(mapnav.InvalidInput) as raised:
        mapnav.predict(campus, pinhole, "R1@I1+9999")
    assert str(raised.value) == cli_error("predict", "--map", CAMPUS, "--camera", PINHOLE, "--at", "R1@I1+9999")
    with pytest.raises(mapnav.InvalidInput):
        mapnav.predict(campus, pinhole, "R1-I1")
    with pytest.raises(TypeError):
        mapnav.predict(campus, pinhole, ("a", 0, 0))


def test_the_route_is_the_clis(campus):
    route = mapnav.route(campus, "R1@I1+3", "R3@I3+2")
    printed = cli_json("route", "--map", CAMPUS, "--from", "R1@I1+3", "--to", "R3@I3+2", "--json")
    assert json.loads(route.to_json()) == printed
    assert route.legs == printed["legs"] and route.legs[0] == {"action": "drive", "road": "R1", "meters": route.legs[0]["meters"]}
    assert round(route.length_m, 3) == pytest.approx(printed["length_m"], abs=1e-3)
    assert route.dialogue.startswith("Drive on R1")
    assert cli("route", "--map", CAMPUS, "--from", "R1@I1+3", "--to", "R3@I3+2")[0].startswith(route.dialogue)


def test_the_route_line_runs_from_start_to_goal(campus):
    route = mapnav.route(campus, "R1@I1+3", "R3@I3+2")
    assert route.line.ndim == 2 and route.line.shape[1] == 2 and route.line.shape[0] >= 3
    assert route.line[0] == pytest.approx(campus.pose_at("R1@I1+3")[:2], abs=1e-9)
    assert route.line[-1] == pytest.approx(campus.pose_at("R3@I3+2")[:2], abs=1e-9)
    length = np.linalg.norm(np.diff(route.line, axis=0), axis=1).sum()
    assert length == pytest.approx(route.length_m, rel=1e-9)


def test_a_blocked_route_is_the_clis(campus):
    route = mapnav.route(campus, "R1@I1+3", "R3@I3+2", block=["R2"])
    printed = cli_json("route", "--map", CAMPUS, "--from", "R1@I1+3", "--to", "R3@I3+2", "--block", "R2", "--json")
    assert json.loads(route.to_json()) == printed and "R2" not in route.roads
    assert route.length_m > mapnav.route(campus, "R1@I1+3", "R3@I3+2").length_m


def test_no_route_raises_the_clis_reason(campus):
    args = ("R1@I1+3", "R3@I3+2")
    with pytest.raises(mapnav.NotFound, match="the goal road R3 is blocked") as raised:
        mapnav.route(campus, *args, block=["R3"])
    assert str(raised.value) == cli_error("route", "--map", CAMPUS, "--from", args[0], "--to", args[1], "--block", "R3")
    with pytest.raises(mapnav.NotFound):
        mapnav.route(campus, "R99@I1+3", "R3@I3+2")
