#include "mapnav/map/random_campus.h"

#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/core/seeded_draw.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/map/geojson.h"

namespace mapnav {

const OptionTable<RandomCampusOptions>& randomCampusOptionTable() {
  using O = RandomCampusOptions;
  static const OptionTable<O> table =
      OptionTable<O>("RandomCampusOptions")
          .field("seed", &O::seed, "the same seed, the same map and mission")
          .field("junctions", &O::junctions, inRange(1, 8), "junctions along the spine")
          .field("min_width_m", &O::min_width_m, above(0), "every road's width at least, m")
          .field("max_width_m", &O::max_width_m, "... and at most, m")
          .field("min_leg_m", &O::min_leg_m, "spine roads' lengths at least, m")
          .field("max_leg_m", &O::max_leg_m, "... and at most, m")
          .field("min_branch_m", &O::min_branch_m, "side branches' lengths at least, m")
          .field("max_branch_m", &O::max_branch_m, "... and at most, m")
          .check("max_width_m", [](const O& o) { return o.max_width_m >= o.min_width_m; }, ">= min_width_m")
          .check("min_leg_m", [](const O& o) { return o.min_leg_m > 3 * o.max_width_m; }, "> 3 max_width_m")
          .check("max_leg_m", [](const O& o) { return o.max_leg_m >= o.min_leg_m; }, ">= min_leg_m")
          .check("min_branch_m", [](const O& o) { return o.min_branch_m > 3 * o.max_width_m; }, "> 3 max_width_m")
          .check("max_branch_m", [](const O& o) { return o.max_branch_m >= o.min_branch_m; }, ">= min_branch_m");
  return table;
}

void RandomCampusOptions::validate() const { randomCampusOptionTable().validate(*this); }

namespace {

using Draw = SeededDraw;

struct Builder {
  const RandomCampusOptions& o;
  Draw& draw;
  MapData map;
  std::vector<std::string> family;

  void node(const std::string& id, IntersectionKind kind, const Vec2& at) {
    map.intersections.push_back({id, kind, at, std::nullopt});
  }
  // A road from `from` heading `heading` for `length` m, turning by `bend` rad on the way (an arc;
  // 0: straight). Returns its end point and sets `heading` to the heading there.
  Vec2 road(const std::string& id, const std::string& from, const std::string& to, const Vec2& start, double& heading,
            double length, double bend) {
    std::vector<Vec2> points{start};
    const int pieces = bend == 0 ? 1 : std::max(2, static_cast<int>(std::ceil(length)));
    Vec2 p = start;
    for (int i = 0; i < pieces; ++i) {
      const double h = heading + bend * (i + 0.5) / pieces;
      p += length / pieces * Vec2(std::cos(h), std::sin(h));
      points.push_back(p);
    }
    heading += bend;
    Road r;
    r.id = id;
    r.from = from;
    r.to = to;
    r.centerline = Polyline2(std::move(points));
    r.width = draw.uniform(o.min_width_m, o.max_width_m);
    r.surface = family[static_cast<std::size_t>(draw.index(static_cast<int>(family.size())))];
    static const char* shoulders[] = {"grass", "grass", "dirt", "gravel"};
    r.left = shoulders[draw.index(4)];
    r.right = shoulders[draw.index(4)];
    if (r.left == r.surface) r.left = "grass";
    if (r.right == r.surface) r.right = "grass";
    map.roads.push_back(std::move(r));
    return p;
  }
};

RandomCampus drawCampus(const RandomCampusOptions& o, Draw& draw) {
  Builder b{o, draw, {}, {}};
  b.map.surfaces = standardSurfaces();
  b.family = draw.index(2) == 0 ? std::vector<std::string>{"concrete", "brick"} : std::vector<std::string>{"asphalt", "gravel"};
  RandomCampus c;
  double heading = draw.uniform(-kPi, kPi);
  Vec2 at = Vec2::Zero();
  b.node("I0", IntersectionKind::End, at);
  std::vector<std::pair<std::string, double>> branches;  // id, length
  for (int k = 1; k <= o.junctions + 1; ++k) {
    const std::string from = k == 1 ? "I0" : "J" + std::to_string(k - 1);
    const std::string to = k == o.junctions + 1 ? "I" + std::to_string(k) : "J" + std::to_string(k);
    const double length = draw.uniform(o.min_leg_m, o.max_leg_m);
    const double bend = draw.index(3) == 0 ? draw.sign() * degToRad(draw.uniform(20, 60)) : 0.0;
    at = b.road("S" + std::to_string(k), from, to, at, heading, length, bend);
    if (k == 1) c.start = "S1@I0+5";
    if (k == o.junctions + 1) {
      b.node(to, IntersectionKind::End, at);
      c.goal = strprintf("S%d@%s+%.1f", k, from.c_str(), std::floor(length - 5));
      break;
    }
    // The junction: which kind, the spine's turn through it and its branches' headings.
    const IntersectionKind kind =
        std::vector<IntersectionKind>{IntersectionKind::Cross, IntersectionKind::T, IntersectionKind::Y,
                                      IntersectionKind::L}[static_cast<std::size_t>(draw.index(4))];
    c.junctions.push_back(kind);
    b.node(to, kind, at);
    const double side = draw.sign();
    std::vector<double> arms;
    double turn = 0;
    if (kind == IntersectionKind::L) turn = side * degToRad(draw.uniform(60, 120));
    if (kind == IntersectionKind::T) arms = {side * degToRad(draw.uniform(70, 110))};
    if (kind == IntersectionKind::Y) {
      turn = side * degToRad(draw.uniform(20, 40));
      arms = {-side * degToRad(draw.uniform(20, 40))};
    }
    if (kind == IntersectionKind::Cross) arms = {degToRad(draw.uniform(60, 120)), -degToRad(draw.uniform(60, 120))};
    for (std::size_t a = 0; a < arms.size(); ++a) {
      const std::string id = "B" + std::to_string(k) + static_cast<char>('a' + a);
      const std::string end = "E" + std::to_string(k) + static_cast<char>('a' + a);
      double h = heading + arms[a];
      const double l = draw.uniform(o.min_branch_m, o.max_branch_m);
      b.node(end, IntersectionKind::End, b.road(id, to, end, at, h, l, 0.0));
      branches.emplace_back(id + "@" + to, l);
    }
    heading += turn;
  }
  if (!branches.empty() && draw.index(2) == 0) {
    const auto& [branch, length] = branches[static_cast<std::size_t>(draw.index(static_cast<int>(branches.size())))];
    c.via.push_back(strprintf("%s+%.1f", branch.c_str(), std::floor(length - 3)));
  }
  b.map.name = "random campus";
  c.map = std::move(b.map);
  return c;
}

}  // namespace

RandomCampus makeRandomCampus(const RandomCampusOptions& options) {
  options.validate();
  for (std::uint64_t attempt = 1; attempt <= 100; ++attempt) {
    Draw draw(options.seed * 1000003ULL + attempt);
    RandomCampus c = drawCampus(options, draw);
    c.map.name = "random campus " + std::to_string(options.seed);
    try {
      const Map valid(c.map, c.map.name);
      c.attempts = attempt;
      return c;
    } catch (const ValidationError&) {
      // a spine that crossed itself or a branch: draw again
    }
  }
  throw Error("random campus " + std::to_string(options.seed) + ": no valid map in 100 draws");
}

}  // namespace mapnav
