#!/usr/bin/env python3
"""Generate the example maps maps/cmu_campus.json and maps/park_path.json.

Run from anywhere with a plain Python 3 (standard library only):

    python3 scripts/make_example_maps.py [--out-dir DIR] [--check-only]

The output is deterministic (same bytes on every run). Before writing, every map is checked against
the rules of docs/map-format.md that `mapnav map validate` enforces beyond the JSON Schema (ids,
references, end points at their intersections, no repeated points, no self-intersections, no
crossings away from shared intersections, kinds matching degrees, connectivity, ...): the script
fails with an AssertionError rather than write a map the validator would reject or warn about.
The landmarks (CAMPUS_FURNITURE, PARK_FURNITURE: lamp posts, trees, benches, manholes, jittered by a
fixed seed) are checked not to stand on any road's paved area nor more than 10 m from their road, the two
warnings `mapnav map validate` gives for landmarks.
The campus map is also checked to hold the dialogue of Wallace et al. 1985, section 2 ("Robot is at
road R1, 3 meters from I1. Navigate to R3, 2 meters from I3." / "Drive on it 2.5 meters and turn to
right 90 degrees"): the shortest route takes a 90 degree right turn at the cross intersection I1.
"""

import argparse
import heapq
import json
import math
import os
import random
import sys

FORMAT = "mapnav-map/1"
SCHEMA_REF = "schema/mapnav-map-1.schema.json"

# Mean colour and per-channel standard deviation (0-255 RGB) of each surface, as a camera sees it in
# daylight.
SURFACES = {
    "concrete": {"rgb": [178, 176, 168], "spread": [10, 10, 10]},
    "asphalt": {"rgb": [74, 74, 78], "spread": [8, 8, 9]},
    "grass": {"rgb": [70, 120, 50], "spread": [14, 18, 12]},
    "dirt": {"rgb": [122, 95, 68], "spread": [14, 12, 10]},
    "brick": {"rgb": [150, 72, 56], "spread": [16, 11, 10]},
    "gravel": {"rgb": [140, 134, 122], "spread": [20, 20, 19]},
}

END_TOLERANCE = 0.5  # m, how far a centre line's end may be from its intersection's position
REPEAT_TOLERANCE = 0.001  # m, consecutive points closer than this are "repeated"
COORD_LIMIT = 1e7  # m


# --------------------------------------------------------------------------------------------------
# Small geometry helpers
# --------------------------------------------------------------------------------------------------

def r3(v):
    """Round to millimetres, never producing -0."""
    v = round(float(v), 3)
    return 0.0 if v == 0 else v


def rp(p):
    return [r3(p[0]), r3(p[1])]


def dist(a, b):
    return math.hypot(a[0] - b[0], a[1] - b[1])


def polyline_length(pts):
    return sum(dist(pts[i], pts[i + 1]) for i in range(len(pts) - 1))


def point_segment_distance(p, a, b):
    ax, ay = b[0] - a[0], b[1] - a[1]
    L2 = ax * ax + ay * ay
    t = 0.0 if L2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / L2))
    return dist(p, (a[0] + t * ax, a[1] + t * ay))


def polyline_distance(p, pts):
    return min(point_segment_distance(p, pts[i], pts[i + 1]) for i in range(len(pts) - 1))


def point_beside(pts, s, offset):
    """The point `offset` m to the left (negative: right) of polyline `pts` at arc length `s`."""
    for i in range(len(pts) - 1):
        seg = dist(pts[i], pts[i + 1])
        if s <= seg or i == len(pts) - 2:
            t = min(max(s / seg, 0.0), 1.0)
            ux, uy = (pts[i + 1][0] - pts[i][0]) / seg, (pts[i + 1][1] - pts[i][1]) / seg
            return (pts[i][0] + t * seg * ux - offset * uy, pts[i][1] + t * seg * uy + offset * ux)
        s -= seg
    raise AssertionError("unreachable")


def cross(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _on_segment(p, a, b, eps):
    """p (known collinear with a-b within eps) lies within the segment's bounding box."""
    return (min(a[0], b[0]) - eps <= p[0] <= max(a[0], b[0]) + eps
            and min(a[1], b[1]) - eps <= p[1] <= max(a[1], b[1]) + eps)


def segment_intersections(a, b, c, d, eps=1e-9):
    """Points where the closed segments a-b and c-d meet: [] if they don't, one point for a crossing
    or a touch, the two ends of the shared stretch for collinear overlapping segments."""
    d1 = cross(c, d, a)
    d2 = cross(c, d, b)
    d3 = cross(a, b, c)
    d4 = cross(a, b, d)
    scale = max(1.0, dist(a, b) * dist(c, d))
    e = eps * scale
    if ((d1 > e and d2 < -e) or (d1 < -e and d2 > e)) and ((d3 > e and d4 < -e) or (d3 < -e and d4 > e)):
        t = d1 / (d1 - d2)
        return [(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))]
    pts = []
    if abs(d1) <= e and _on_segment(a, c, d, 1e-9):
        pts.append(tuple(a))
    if abs(d2) <= e and _on_segment(b, c, d, 1e-9):
        pts.append(tuple(b))
    if abs(d3) <= e and _on_segment(c, a, b, 1e-9):
        pts.append(tuple(c))
    if abs(d4) <= e and _on_segment(d, a, b, 1e-9):
        pts.append(tuple(d))
    uniq = []
    for p in pts:
        if all(dist(p, q) > 1e-9 for q in uniq):
            uniq.append(p)
    return uniq


def point_in_polygon(p, poly):
    inside = False
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        if (a[1] > p[1]) != (b[1] > p[1]):
            x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
            if x > p[0]:
                inside = not inside
    return inside


def polygon_is_simple(poly):
    n = len(poly)
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        for j in range(i + 1, n):
            c, d = poly[j], poly[(j + 1) % n]
            hits = segment_intersections(a, b, c, d)
            if not hits:
                continue
            adjacent = j == i + 1 or (i == 0 and j == n - 1)
            if not adjacent:
                return False
            shared = b if j == i + 1 else a
            if any(dist(h, shared) > 1e-9 for h in hits):
                return False
    return True


def heading_deg(v):
    return math.degrees(math.atan2(v[1], v[0]))


def turn_deg(h_in, h_out):
    """Signed change of heading, degrees, left positive, in (-180, 180]."""
    t = (h_out - h_in + 180.0) % 360.0 - 180.0
    return 180.0 if t == -180.0 else t


def circumradius(a, b, c):
    ab, bc, ca = dist(a, b), dist(b, c), dist(c, a)
    area2 = abs(cross(a, b, c))
    return math.inf if area2 < 1e-12 else ab * bc * ca / (2.0 * area2)


def cubic_bezier(p0, p1, p2, p3, step):
    """Points along a cubic Bezier curve, about `step` metres apart (uniform in arc length)."""
    def at(t):
        u = 1 - t
        return (u ** 3 * p0[0] + 3 * u * u * t * p1[0] + 3 * u * t * t * p2[0] + t ** 3 * p3[0],
                u ** 3 * p0[1] + 3 * u * u * t * p1[1] + 3 * u * t * t * p2[1] + t ** 3 * p3[1])
    fine = [at(i / 2000) for i in range(2001)]
    cum = [0.0]
    for i in range(1, len(fine)):
        cum.append(cum[-1] + dist(fine[i - 1], fine[i]))
    n = max(1, math.ceil(cum[-1] / step))
    out, j = [tuple(p0)], 0
    for k in range(1, n):
        s = cum[-1] * k / n
        while cum[j + 1] < s:
            j += 1
        f = (s - cum[j]) / (cum[j + 1] - cum[j])
        out.append((fine[j][0] + f * (fine[j + 1][0] - fine[j][0]),
                    fine[j][1] + f * (fine[j + 1][1] - fine[j][1])))
    out.append(tuple(p3))
    return out


# --------------------------------------------------------------------------------------------------
# The validator's rules (beyond the schema), as a reference implementation used for assertions
# --------------------------------------------------------------------------------------------------

KIND_DEGREE = {"end": lambda n: n == 1, "L": lambda n: n == 2, "T": lambda n: n == 3,
               "Y": lambda n: n == 3, "cross": lambda n: n == 4, "plaza": lambda n: n >= 3,
               "other": lambda n: True}


def check_map(m):
    """Problems found in map `m` as (json pointer, severity, check) triples, in document order.

    Implements the checks of docs/map-format.md that the JSON Schema cannot express (and the
    coordinate range). `where` follows the doc; segment problems point at the first vertex of the
    offending segment of the road that comes first in the roads array.
    """
    issues = []
    inters = m["intersections"]
    roads = m["roads"]

    # ids.duplicate: intersections first, then roads, in document order.
    seen = set()
    for kind, arr in (("intersections", inters), ("roads", roads)):
        for i, o in enumerate(arr):
            if o["id"] in seen:
                issues.append((f"/{kind}/{i}/id", "error", "ids.duplicate"))
            seen.add(o["id"])
    by_id = {}
    for it in inters:
        by_id.setdefault(it["id"], it)

    def coord_ok(p):
        return all(math.isfinite(v) and abs(v) <= COORD_LIMIT for v in p)

    bad_geometry = set()  # roads whose geometry is not checked further
    clean = {}  # road index -> (centre line without repeated points, their indices in the file)
    for i, it in enumerate(inters):
        if not coord_ok(it["position"]):
            issues.append((f"/intersections/{i}/position", "error", "geometry.invalid_coordinate"))
        shape = it.get("shape")
        if shape is not None:
            for k, p in enumerate(shape):
                if not coord_ok(p):
                    issues.append((f"/intersections/{i}/shape/{k}", "error", "geometry.invalid_coordinate"))
            if len(shape) < 3:
                issues.append((f"/intersections/{i}/shape", "error", "intersections.too_few_points"))
            elif all(coord_ok(p) for p in shape) and not polygon_is_simple(shape):
                issues.append((f"/intersections/{i}/shape", "error", "intersections.self_intersecting_shape"))

    for i, r in enumerate(roads):
        for k, p in enumerate(r["centerline"]):
            if not coord_ok(p):
                issues.append((f"/roads/{i}/centerline/{k}", "error", "geometry.invalid_coordinate"))
                bad_geometry.add(i)
        for end in ("from", "to"):
            if r[end] not in by_id:
                issues.append((f"/roads/{i}/{end}", "error", "roads.unknown_intersection"))
        w = r["width"]
        if not (math.isfinite(w) and 0 < w <= 100):
            issues.append((f"/roads/{i}/width", "error", "roads.invalid_width"))
        for member in ("surface", "left", "right"):
            if r[member] not in m["surfaces"]:
                issues.append((f"/roads/{i}/{member}", "error", "surfaces.unknown"))
        cl = r["centerline"]
        if len(cl) < 2:
            issues.append((f"/roads/{i}/centerline", "error", "roads.too_few_points"))
            bad_geometry.add(i)
            continue
        if i in bad_geometry:
            continue
        for k in range(1, len(cl)):
            if dist(cl[k], cl[k - 1]) <= REPEAT_TOLERANCE:
                issues.append((f"/roads/{i}/centerline/{k}", "error", "roads.repeated_point"))
        for end, k in (("from", 0), ("to", len(cl) - 1)):
            it = by_id.get(r[end])
            if it is None or not coord_ok(it["position"]):
                continue
            near = dist(cl[k], it["position"]) <= END_TOLERANCE
            inside = it.get("shape") is not None and len(it["shape"]) >= 3 and point_in_polygon(cl[k], it["shape"])
            if not near and not inside:
                issues.append((f"/roads/{i}/centerline/{k}", "error", "roads.end_far_from_intersection"))
        # The remaining geometry checks see the line without its repeated points (reported above).
        # (Segment k of the cleaned line starts at point orig[k] of the file's line.)
        orig = [k for k in range(len(cl)) if k == 0 or dist(cl[k], cl[k - 1]) > REPEAT_TOLERANCE]
        cl = [cl[k] for k in orig]
        clean[i] = (cl, orig)
        # roads.self_intersection
        loop = r["from"] == r["to"]
        nseg = len(cl) - 1
        found = False
        for k in range(nseg):
            for l in range(k + 1, nseg):
                hits = segment_intersections(cl[k], cl[k + 1], cl[l], cl[l + 1])
                if not hits:
                    continue
                allowed = []
                if l == k + 1:
                    allowed.append(cl[l])
                if loop and k == 0 and l == nseg - 1:
                    allowed.append(cl[0])
                if all(any(dist(h, a) <= 1e-6 for a in allowed) for h in hits):
                    continue
                issues.append((f"/roads/{i}/centerline/{orig[k]}", "error", "roads.self_intersection"))
                found = True
                break
            if found:
                break
        if polyline_length(cl) < 1.0:
            issues.append((f"/roads/{i}/centerline", "warning", "roads.very_short"))

    # roads.crossing_without_intersection
    def near_intersection(p, it):
        if dist(p, it["position"]) <= END_TOLERANCE:
            return True
        shape = it.get("shape")
        return shape is not None and len(shape) >= 3 and point_in_polygon(p, shape)

    ok_roads = sorted(clean)
    for a_idx, i in enumerate(ok_roads):
        ri = roads[i]
        for j in ok_roads[a_idx + 1:]:
            rj = roads[j]
            shared = [by_id[x] for x in {ri["from"], ri["to"]} & {rj["from"], rj["to"]} if x in by_id]
            ci, cj = clean[i][0], clean[j][0]
            hit_k = None
            for k in range(len(ci) - 1):
                for l in range(len(cj) - 1):
                    hits = segment_intersections(ci[k], ci[k + 1], cj[l], cj[l + 1])
                    if any(not any(near_intersection(h, s) for s in shared) for h in hits):
                        hit_k = k
                        break
                if hit_k is not None:
                    break
            if hit_k is not None:
                issues.append((f"/roads/{i}/centerline/{clean[i][1][hit_k]}", "error",
                               "roads.crossing_without_intersection"))

    # Degrees, kinds, connectivity.
    degree = {it["id"]: 0 for it in inters}
    adj = {it["id"]: set() for it in inters}
    for r in roads:
        for end in ("from", "to"):
            if r[end] in degree:
                degree[r[end]] += 1
        if r["from"] in adj and r["to"] in adj:
            adj[r["from"]].add(r["to"])
            adj[r["to"]].add(r["from"])
    if inters:
        comp = {}
        for it in inters:
            if it["id"] in comp:
                continue
            c = len(set(comp.values()))
            stack = [it["id"]]
            comp[it["id"]] = c
            while stack:
                x = stack.pop()
                for y in adj[x]:
                    if y not in comp:
                        comp[y] = c
                        stack.append(y)
        reported = {comp[inters[0]["id"]]}
        for i, it in enumerate(inters):
            if comp[it["id"]] not in reported:
                reported.add(comp[it["id"]])
                issues.append((f"/intersections/{i}", "warning", "topology.disconnected"))
    for i, it in enumerate(inters):
        rule = KIND_DEGREE.get(it["kind"])
        if rule is not None and not rule(degree[it["id"]]):
            issues.append((f"/intersections/{i}/kind", "warning", "intersections.kind_mismatch"))
    return issues


def assert_valid(m):
    issues = check_map(m)
    assert not issues, f"{m['name']}: " + "; ".join(f"{w}: {s}: {c}" for w, s, c in issues)
    # Things the schema checks, cheaply re-checked here so the script stands alone.
    assert m["format"] == FORMAT
    for it in m["intersections"]:
        assert it["kind"] in KIND_DEGREE, it
    ids = [o["id"] for o in m["intersections"] + m["roads"]]
    for x in ids:
        assert x[0].isalpha() and len(x) <= 64 and all(ch.isalnum() or ch in "_-" for ch in x), x


# --------------------------------------------------------------------------------------------------
# Routing on the map (only to check the campus dialogue route)
# --------------------------------------------------------------------------------------------------

def shortest_route(m, start_road, start_node, start_dist, goal_road, goal_node, goal_dist, banned=()):
    """Shortest route from the point on start_road start_dist metres (along the centre line) from
    start_node to the point on goal_road goal_dist metres from goal_node, not using the roads in
    `banned` between the two. Either end of either road may be used. Returns (length,
    [intersection ids], [road ids, start_road first and goal_road last]) or None."""
    roads = {r["id"]: r for r in m["roads"]}
    length = {rid: polyline_length(r["centerline"]) for rid, r in roads.items()}
    adj = {}
    for rid, r in roads.items():
        if rid in banned:
            continue
        adj.setdefault(r["from"], []).append((r["to"], rid))
        adj.setdefault(r["to"], []).append((r["from"], rid))

    def other(road, node):
        return road["to"] if road["from"] == node else road["from"]

    sr, gr = roads[start_road], roads[goal_road]
    s_ends = [(start_node, start_dist), (other(sr, start_node), length[start_road] - start_dist)]
    g_ends = {goal_node: goal_dist, other(gr, goal_node): length[goal_road] - goal_dist}
    best = None
    for s_node, s_cost in s_ends:
        dist_to = {s_node: (s_cost, [s_node], [])}
        pq = [(s_cost, s_node)]
        while pq:
            d, u = heapq.heappop(pq)
            if d > dist_to[u][0]:
                continue
            for v, rid in adj.get(u, []):
                nd = d + length[rid]
                if v not in dist_to or nd < dist_to[v][0] - 1e-9:
                    dist_to[v] = (nd, dist_to[u][1] + [v], dist_to[u][2] + [rid])
                    heapq.heappush(pq, (nd, v))
        for g_node, g_cost in g_ends.items():
            if g_node in dist_to:
                d, nodes, rids = dist_to[g_node]
                cand = (d + g_cost, nodes, [start_road] + rids + [goal_road])
                if best is None or cand[0] < best[0]:
                    best = cand
    return best


def road_heading_at(road, node_id, leaving):
    """Heading (degrees) of `road` where it touches intersection node_id: leaving it or arriving."""
    cl = road["centerline"]
    at_start = road["from"] == node_id
    if at_start:
        v = (cl[1][0] - cl[0][0], cl[1][1] - cl[0][1])
        return heading_deg(v) if leaving else heading_deg((-v[0], -v[1]))
    v = (cl[-1][0] - cl[-2][0], cl[-1][1] - cl[-2][1])
    return heading_deg(v) if not leaving else heading_deg((-v[0], -v[1]))


# --------------------------------------------------------------------------------------------------
# JSON output: 2-space indent, anything that fits on a line (points, short objects) on one line
# --------------------------------------------------------------------------------------------------

def fmt_number(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    assert math.isfinite(v)
    if v == int(v) and abs(v) < 1e15:
        return str(int(v))
    return repr(v)  # the shortest text that reads back as the same double


def to_json(v, indent=0, width=100):
    def inline(x):
        if isinstance(x, dict):
            return "{" + ", ".join(json.dumps(k) + ": " + inline(y) for k, y in x.items()) + "}"
        if isinstance(x, list):
            return "[" + ", ".join(inline(y) for y in x) + "]"
        if isinstance(x, (int, float)) and not isinstance(x, bool):
            return fmt_number(x)
        return json.dumps(x, ensure_ascii=False)

    s = inline(v)
    if indent + len(s) <= width or not isinstance(v, (dict, list)) or not v:
        return s
    pad = " " * (indent + 2)
    if isinstance(v, dict):
        items = []
        for k, y in v.items():
            key = json.dumps(k) + ": "
            items.append(pad + key + to_json(y, indent + 2 + len(key), width).lstrip()
                         if not isinstance(y, (dict, list))
                         else pad + key + to_json(y, indent + 2, width))
        return "{\n" + ",\n".join(items) + "\n" + " " * indent + "}"
    # A long list of points: several points per line, as many as fit.
    if all(isinstance(p, list) and all(isinstance(c, (int, float)) for c in p) for p in v):
        lines, cur = [], ""
        for p in v:
            t = inline(p)
            if cur and len(pad) + len(cur) + 2 + len(t) + 1 > width:
                lines.append(cur + ",")
                cur = t
            else:
                cur = t if not cur else cur + ", " + t
        lines.append(cur)
        return "[\n" + "\n".join(pad + ln for ln in lines) + "\n" + " " * indent + "]"
    return "[\n" + ",\n".join(pad + to_json(y, indent + 2, width) for y in v) + "\n" + " " * indent + "]"


def write_map(m, path):
    text = to_json(m) + "\n"
    assert json.loads(text) == json.loads(json.dumps(m)), "formatter changed the data"
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)


def finish_map(name, origin, intersections, roads):
    """Assemble a map dict with coordinates rounded to millimetres and the standard surfaces."""
    for it in intersections:
        it["position"] = rp(it["position"])
        if "shape" in it:
            it["shape"] = [rp(p) for p in it["shape"]]
    for r in roads:
        r["centerline"] = [rp(p) for p in r["centerline"]]
    return {
        "$schema": SCHEMA_REF,
        "format": FORMAT,
        "name": name,
        "origin": origin,
        "surfaces": {k: dict(v) for k, v in SURFACES.items()},
        "intersections": intersections,
        "roads": roads,
    }


# --------------------------------------------------------------------------------------------------
# maps/cmu_campus.json
# --------------------------------------------------------------------------------------------------

def make_cmu_campus():
    """A 150 m x 120 m sidewalk network: a 4 x 3 grid of blocks (x = 0, 50, 100, 150; y = 0, 40,
    80) with a plaza in the north-east, a Y fork north of the centre whose two branches curve to the
    top corners, and a dead-end spur to a building entrance. The south row runs along a street
    (asphalt shoulder on the street side)."""
    I = {}  # id -> intersection object

    def node(iid, kind, x, y, shape=None):
        I[iid] = {"id": iid, "kind": kind, "position": [x, y]}
        if shape is not None:
            I[iid]["shape"] = shape

    # The dialogue: robot on R1 3 m east of the cross intersection I1, heading west; it turns right
    # (north) at I1, goes straight through I2, bears left at the Y fork I4 onto the curved branch to
    # the corner I3, and there turns left (south) onto R3; the goal is 2 m from I3.
    node("I1", "cross", 50, 40)
    node("I2", "cross", 50, 80)
    node("I3", "L", 0, 120)
    node("I4", "Y", 50, 100)
    node("I5", "T", 0, 80)
    node("I6", "T", 0, 40)
    node("I7", "L", 0, 0)
    node("I8", "T", 50, 0)
    node("I9", "T", 100, 0)
    node("I10", "L", 150, 0)
    node("I11", "cross", 100, 40)
    node("I12", "T", 150, 40)
    node("I13", "T", 150, 80)
    # The plaza: a regular octagon of radius 4 m (vertices at 22.5 deg + k * 45 deg).
    plaza = [(100 + 4 * math.cos(math.radians(22.5 + 45 * k)), 80 + 4 * math.sin(math.radians(22.5 + 45 * k)))
             for k in range(8)]
    node("I14", "plaza", 100, 80, shape=plaza)
    node("I15", "T", 100, 120)
    node("I16", "L", 150, 120)
    node("I17", "end", 114, 94)  # a building entrance north-east of the plaza

    step = 2.0
    # The Y fork at I4: the stem comes from the south, the branches leave 30 deg either side of
    # north (60 deg apart) and curve gently to arrive horizontally at the top corners I3 and I15.
    s30, c30 = math.sin(math.radians(30)), math.cos(math.radians(30))
    # Each branch leaves straight for 8 m, then curves (tangent-continuous) to its corner.
    def branch(sgn, corner_x):
        p0 = (50 + sgn * 8 * s30, 100 + 8 * c30)
        p1 = (p0[0] + sgn * 8 * s30, p0[1] + 8 * c30)
        return [(50, 100)] + cubic_bezier(p0, p1, (50 + sgn * 28, 120), (corner_x, 120), step)
    branch_w = branch(-1, 0)
    branch_e = branch(+1, 100)

    C, G, A, Br, D = "concrete", "grass", "asphalt", "brick", "dirt"
    R = []

    def road(rid, a, b, width, left=G, right=G, surface=C, centerline=None, **extra):
        cl = centerline or [I[a]["position"], I[b]["position"]]
        r = {"id": rid, "from": a, "to": b, "centerline": [list(p) for p in cl], "width": width,
             "surface": surface, "left": left, "right": right}
        r.update(extra)
        R.append(r)

    road("R1", "I1", "I11", 2.5)                        # I1 -> east
    road("R2", "I1", "I2", 2.5)                         # I1 -> north
    road("R3", "I3", "I5", 2.0)                         # I3 -> south
    road("R4", "I2", "I4", 2.0)                         # stem of the Y
    road("R5", "I4", "I3", 1.8, centerline=branch_w)    # west branch, curved
    road("R6", "I4", "I15", 1.8, centerline=branch_e)   # east branch, curved
    road("R7", "I6", "I1", 2.0)
    road("R8", "I8", "I1", 2.5)
    road("R9", "I5", "I2", 2.0)
    road("R10", "I6", "I5", 1.5, left="gravel", right=G)  # along a gravel flower bed (west side)
    road("R11", "I7", "I6", 1.5)
    # The south row runs along a street: the asphalt is on the right walking east.
    road("R12", "I7", "I8", 3.0, left=G, right=A)
    road("R13", "I8", "I9", 3.0, left=G, right=A)
    road("R14", "I9", "I10", 3.0, left=G, right=A)
    road("R15", "I9", "I11", 2.5)
    road("R16", "I10", "I12", 2.0)
    road("R17", "I11", "I12", 2.5)
    road("R18", "I11", "I14", 2.5)
    road("R19", "I2", "I14", 2.5, left=Br, right=G)       # brick planters on the plaza's west side
    road("R20", "I12", "I13", 2.0)
    road("R21", "I14", "I13", 2.5, left=G, right=Br)
    road("R22", "I14", "I15", 3.0, surface=Br, left=G, right=G)  # brick-paved walk north of the plaza
    road("R23", "I15", "I16", 2.0)
    road("R24", "I13", "I16", 2.0)
    road("R25", "I14", "I17", 1.5, left=D, right=G)       # worn path to the entrance

    order = sorted(I, key=lambda k: int(k[1:]))
    m = finish_map("CMU campus sidewalks", {"lat": 40.4433, "lon": -79.9436, "alt": 280.0},
                   [I[k] for k in order], R)
    assert_valid(m)

    # Layout checks from the brief.
    kinds = [it["kind"] for it in m["intersections"]]
    assert len(kinds) >= 12 and len(m["roads"]) >= 16
    for k, n in (("cross", 2), ("T", 2), ("Y", 1), ("L", 1), ("plaza", 1), ("end", 1)):
        assert kinds.count(k) >= n, k
    xs = [p[0] for r in m["roads"] for p in r["centerline"]]
    ys = [p[1] for r in m["roads"] for p in r["centerline"]]
    assert max(xs) - min(xs) <= 160 and max(ys) - min(ys) <= 130
    assert all(1.5 <= r["width"] <= 3.0 for r in m["roads"])
    assert point_in_polygon(I["I14"]["position"], I["I14"]["shape"]) and polygon_is_simple(I["I14"]["shape"])
    check_angles(m)
    add_landmarks(m, CAMPUS_FURNITURE, 0.3)
    return m


def angles_at(m, iid):
    """Sorted headings (degrees, 0..360) of the roads leaving intersection iid."""
    hs = []
    for r in m["roads"]:
        for end in ("from", "to"):
            if r[end] == iid:
                hs.append(road_heading_at(r, iid, leaving=True) % 360.0)
    return sorted(hs)


def check_angles(m):
    """Kinds fit the angles (within 5 deg): cross and T roads 90 deg apart, L 90 deg, Y branches
    60 deg apart (and 150 deg from the stem)."""
    expected = {"cross": [90, 90, 90, 90], "T": [90, 90, 180], "L": [90, 270], "Y": [60, 150, 150]}
    for it in m["intersections"]:
        hs = angles_at(m, it["id"])
        gaps = sorted((hs[(i + 1) % len(hs)] - hs[i]) % 360.0 for i in range(len(hs)))
        if it["kind"] in expected:
            want = expected[it["kind"]]
            assert len(gaps) == len(want) and all(abs(g - w) < 5 for g, w in zip(gaps, want)), (it["id"], gaps)
        elif it["kind"] == "plaza":
            assert len(hs) == 5, (it["id"], hs)


def check_dialogue(m):
    """The paper's dialogue: from R1, 3 m from I1, to R3, 2 m from I3. Returns (length, length of
    the best route not taking it, turns)."""
    length, nodes, rids = shortest_route(m, "R1", "I1", 3.0, "R3", "I3", 2.0)
    assert nodes[0] == "I1" and nodes[-1] == "I3", nodes
    assert len(nodes) >= 3
    # Any other route leaves out at least one road of this one: it must be clearly longer.
    second = min((shortest_route(m, "R1", "I1", 3.0, "R3", "I3", 2.0, banned={rid}) or (math.inf,))[0]
                 for rid in rids[1:-1])
    assert second - length >= 5.0, (length, second)
    roads = {r["id"]: r for r in m["roads"]}
    kinds = {it["id"]: it["kind"] for it in m["intersections"]}
    turns = []
    for n, (a, b) in zip(nodes, zip(rids, rids[1:])):
        h_in = road_heading_at(roads[a], n, leaving=False)
        h_out = road_heading_at(roads[b], n, leaving=True)
        turns.append((n, kinds[n], a, b, turn_deg(h_in, h_out)))
    n, kind, _, _, t = turns[0]
    assert kind == "cross" and abs(t + 90) < 1e-6, turns[0]  # right 90 deg at I1
    return length, second, turns


# --------------------------------------------------------------------------------------------------
# maps/park_path.json
# --------------------------------------------------------------------------------------------------

def make_park_path():
    """A ~1 km asphalt path winding through a park, built from straights and circular arcs (radii
    15 m to 80 m, arcs sampled every ~1.5 m), split into roads at `other` nodes where the shoulders
    change, with dead ends at both extremities."""
    # Pieces: ("S", length) or ("A", radius, degrees left(+)/right(-)). A marker ("N",) between
    # pieces splits the path into roads there, at an intersection of kind `other`.
    program = [
        ("S", 40.0),
        ("A", 60.0, 40.0),
        ("S", 70.0),
        ("A", 35.0, -80.0),
        ("S", 30.0),
        ("N",),
        ("S", 30.0),
        ("A", 50.0, -60.0),
        ("S", 60.0),
        ("A", 15.0, 170.0),     # the hairpin: radius 15 m
        ("S", 50.0),
        ("N",),
        ("S", 35.0),
        ("A", 80.0, -35.0),
        ("S", 40.0),
        ("A", 25.0, 95.0),
        ("S", 45.0),
        ("N",),
        ("S", 25.0),
        ("A", 40.0, -110.0),
        ("S", 45.0),
        ("A", 30.0, 70.0),
        ("S", 30.0),
        ("N",),
        ("S", 20.0),
        ("A", 45.0, -50.0),
        ("S", 40.0),
    ]
    step = 1.5
    x, y, h = 0.0, 0.0, math.radians(10.0)
    sections = [[(x, y)]]
    radii = []
    for piece in program:
        if piece[0] == "N":
            sections.append([(x, y)])
            continue
        pts = sections[-1]
        if piece[0] == "S":
            x += piece[1] * math.cos(h)
            y += piece[1] * math.sin(h)
            pts.append((x, y))
        else:
            rad, deg = piece[1], piece[2]
            radii.append(rad)
            sgn = 1.0 if deg > 0 else -1.0
            cx, cy = x - sgn * rad * math.sin(h), y + sgn * rad * math.cos(h)
            a0 = math.atan2(y - cy, x - cx)
            sweep = math.radians(deg)
            n = max(2, math.ceil(rad * abs(sweep) / step))
            for k in range(1, n + 1):
                a = a0 + sweep * k / n
                pts.append((cx + rad * math.cos(a), cy + rad * math.sin(a)))
            x, y = pts[-1]
            h += sweep

    # Shoulders per section (left, right as seen walking from the west end).
    shoulders = [("grass", "grass"), ("grass", "dirt"), ("dirt", "grass"), ("grass", "gravel"), ("grass", "dirt")]
    assert len(shoulders) == len(sections)
    inters, roads = [], []
    for k in range(len(sections) + 1):
        kind = "end" if k in (0, len(sections)) else "other"
        p = sections[k][0] if k < len(sections) else sections[-1][-1]
        inters.append({"id": f"I{k + 1}", "kind": kind, "position": list(p)})
    for k, pts in enumerate(sections):
        left, right = shoulders[k]
        roads.append({"id": f"R{k + 1}", "from": f"I{k + 1}", "to": f"I{k + 2}",
                      "centerline": [list(p) for p in pts], "width": 3.0, "surface": "asphalt",
                      "left": left, "right": right})
    m = finish_map("Schenley Park path", {"lat": 40.4365, "lon": -79.9465, "alt": 275.0}, inters, roads)
    assert_valid(m)
    add_landmarks(m, PARK_FURNITURE, 0.7)
    total = sum(polyline_length(r["centerline"]) for r in m["roads"])
    assert 950 <= total <= 1100, total
    min_r = min(circumradius(cl[i - 1], cl[i], cl[i + 1])
                for cl in (r["centerline"] for r in m["roads"]) for i in range(1, len(cl) - 1))
    assert min(radii) == 15.0 and 14.5 <= min_r <= 15.5, min_r  # (mm rounding moves it a little)
    for r in m["roads"]:
        cl = r["centerline"]
        assert max(dist(cl[i], cl[i + 1]) for i in range(len(cl) - 1)) <= 80.0
    return m, total, min(radii), max(radii), min_r


# A real park's furniture along each road (arc lengths from the road's `from` end, m): lamp posts at
# the paving's edge every 25-40 m on the lit stretches, trees 1-2 m off the edge in groups, a few
# benches on grass shoulders, a manhole cover in the paving now and then. Side +1 is the
# left as seen walking from `from` to `to`, -1 the right.
PARK_FURNITURE = {
    "R1": {"pole": (-1, [18, 50, 83, 112, 146, 180, 212]), "tree": (1, [56, 62, 70, 121, 128, 176]),
           "bench": (1, [34, 150]), "manhole": [27, 138]},
    "R2": {"pole": (1, [14, 48, 80, 115, 151, 187, 221]), "tree": (-1, [31, 200]), "bench": (1, [62]),
           "manhole": [101]},
    "R3": {"tree": (-1, [18, 44, 67, 95, 121, 148, 171, 197]), "bench": (-1, [108]), "manhole": [72, 158]},
    "R4": {"pole": (-1, [16, 47, 80, 113, 143, 176, 207]), "tree": (1, [38, 46, 153]), "bench": (1, [95]),
           "manhole": [121]},
    "R5": {"pole": (1, [11, 43, 74]), "bench": (1, [58]), "manhole": [35]},
}
BENCH_DEPTH = 0.5  # m, as the map's kBenchDepthM
LANDMARK_REACH = {"pole": 0.10, "tree": 0.15, "bench": BENCH_DEPTH / 2}  # the kinds' default radii


# A campus's: lamp posts every 25-40 m on one side of each walk, a manhole cover (a utility vault,
# a drain) in each walk's paving, now and then a tree or two and a bench on a lawn.
# Drawn once (seed 28) by that rule; the arc lengths are the map's.
CAMPUS_FURNITURE = {
    "R1": {"pole": (1, [13]), "tree": (-1, [13, 36]), "bench": (-1, [14]), "manhole": [29]},
    "R2": {"pole": (1, [12]), "tree": (-1, [14, 35]), "manhole": [19]},
    "R3": {"pole": (1, [9]), "manhole": [20]},
    "R4": {"pole": (1, [14]), "manhole": [8]},
    "R5": {"pole": (-1, [12, 41]), "tree": (1, [32]), "manhole": [38]},
    "R6": {"pole": (1, [11, 36]), "tree": (-1, [43, 44]), "manhole": [36]},
    "R7": {"pole": (1, [10, 39]), "manhole": [30]},
    "R8": {"pole": (1, [9]), "manhole": [17]},
    "R9": {"pole": (-1, [9]), "tree": (1, [27]), "manhole": [18]},
    "R10": {"pole": (-1, [9]), "manhole": [19]},
    "R11": {"pole": (-1, [11]), "tree": (1, [18, 30]), "manhole": [13]},
    "R12": {"pole": (1, [13, 44]), "manhole": [17]},
    "R13": {"pole": (-1, [9, 36]), "tree": (1, [8, 35]), "bench": (1, [35]), "manhole": [28]},
    "R14": {"pole": (1, [11, 41]), "manhole": [33]},
    "R15": {"pole": (-1, [11]), "tree": (1, [22, 33]), "manhole": [23]},
    "R16": {"pole": (1, [14]), "manhole": [24]},
    "R17": {"pole": (-1, [14]), "manhole": [18]},
    "R18": {"pole": (1, [9]), "tree": (-1, [23]), "manhole": [27]},
    "R19": {"pole": (1, [11, 40]), "tree": (-1, [19, 24]), "manhole": [35]},
    "R20": {"pole": (1, [13]), "manhole": [24]},
    "R21": {"pole": (1, [8]), "manhole": [17]},
    "R22": {"pole": (-1, [9]), "manhole": [21]},
    "R23": {"pole": (-1, [12, 45]), "tree": (1, [15, 21]), "manhole": [34]},
    "R24": {"pole": (-1, [14]), "bench": (1, [17]), "manhole": [18]},
    "R25": {"pole": (1, [14]), "manhole": [6]},
}


def add_landmarks(m, furniture, manhole_offset):
    """Place `furniture` beside the map's roads, jittered by a fixed seed, numbered along the roads
    per kind (P1, T1, B1, M1, ...), a manhole cover up to `manhole_offset` m off the centre line;
    asserts what `mapnav map validate` warns about: nothing standing within its reach of any road's
    paved area, nothing more than 10 m from its road."""
    rng = random.Random(28)
    count = {"pole": 0, "tree": 0, "bench": 0, "manhole": 0}
    landmarks = []
    for road in m["roads"]:
        plan, pts, half = furniture[road["id"]], road["centerline"], road["width"] / 2
        placed = []
        for kind in ("pole", "tree", "bench", "manhole"):
            if kind not in plan:
                continue
            side, stations = plan[kind] if kind != "manhole" else (0, plan[kind])
            for s in stations:
                if kind == "pole":
                    off = side * (half + rng.uniform(0.35, 0.5))
                elif kind == "tree":
                    off = side * (half + rng.uniform(1.0, 2.0))
                elif kind == "bench":
                    assert road["left" if side > 0 else "right"] == "grass", (road["id"], s)
                    off = side * (half + BENCH_DEPTH / 2 + rng.uniform(0.08, 0.12))
                else:
                    off = rng.uniform(-manhole_offset, manhole_offset)
                placed.append((s + rng.uniform(-1.5, 1.5), kind, off))
        for s, kind, off in sorted(placed):
            count[kind] += 1
            p = rp(point_beside(pts, s, off))
            near = min(polyline_distance(p, r["centerline"]) - r["width"] / 2 for r in m["roads"])
            if kind == "manhole":
                assert polyline_distance(p, pts) <= half - 0.3, (kind, road["id"], s)
            else:
                assert near >= LANDMARK_REACH[kind] + 0.05, (kind, road["id"], s, near)
            assert polyline_distance(p, pts) - half <= 10.0
            landmarks.append({"id": f"{kind[0].upper()}{count[kind]}", "kind": kind, "position": p,
                              "road": road["id"]})
    m["landmarks"] = landmarks


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--out-dir", default=os.path.join(here, "..", "maps"), help="where to write (default: maps/)")
    ap.add_argument("--check-only", action="store_true", help="build and check the maps, write nothing")
    args = ap.parse_args()

    campus = make_cmu_campus()
    length, second, turns = check_dialogue(campus)
    park, park_len, r_min, r_max, park_min_r = make_park_path()
    if not args.check_only:
        write_map(campus, os.path.join(args.out_dir, "cmu_campus.json"))
        write_map(park, os.path.join(args.out_dir, "park_path.json"))
    print(f"cmu_campus: {len(campus['intersections'])} intersections, {len(campus['roads'])} roads")
    print(f"  dialogue route R1 (3 m from I1) -> R3 (2 m from I3): {length:.1f} m (next best {second:.1f} m)")
    for n, kind, a, b, t in turns:
        what = "straight" if abs(t) < 10 else ("left" if t > 0 else "right") + f" {abs(t):.0f} deg"
        print(f"  at {n} ({kind}): {a} -> {b}: {what}")
    print(f"park_path: {len(park['intersections'])} intersections, {len(park['roads'])} roads, "
          f"{len(park['landmarks'])} landmarks, "
          f"{park_len:.1f} m, arc radii {r_min:.0f}-{r_max:.0f} m "
          f"(smallest measured on the written points: {park_min_r:.1f} m)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
