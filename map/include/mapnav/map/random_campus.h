#pragma once
// Random small campuses for the suite of unseen maps: a spine of roads through a few
// junctions — crosses, Ts and Ys at random angles, Ls — some of its roads arcs, each junction's side
// branches short stubs; widths 1.5–4 m, surfaces drawn from one family per map (paved slabs:
// concrete and brick; or park paths: asphalt and gravel), shoulders grass, dirt or gravel. With a
// mission on it: start near the spine's first end, goal near its last, and on half the maps a via
// point at the end of a side branch (out and back along it). Everything follows from the seed.
#include <cstdint>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct RandomCampusOptions {
  std::uint64_t seed = 1;  ///< the same seed, the same map and mission
  int junctions = 3;       ///< junctions along the spine, 1–8
  double min_width_m = 1.5, max_width_m = 4.0;  ///< every road's width, drawn uniformly, m
  double min_leg_m = 25.0, max_leg_m = 45.0;    ///< spine roads' lengths, m
  double min_branch_m = 15.0, max_branch_m = 25.0;  ///< side branches' lengths, m

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// RandomCampusOptions' fields by name, with their rules.
const OptionTable<RandomCampusOptions>& randomCampusOptionTable();

struct RandomCampus {
  MapData map;                      ///< valid (Map(map) does not throw)
  std::string start, goal;          ///< road positions, ROAD@NODE+METERS
  std::vector<std::string> via;     ///< empty, or one branch's far end
  std::vector<IntersectionKind> junctions;  ///< the spine's junctions in order
  std::uint64_t attempts = 1;       ///< draws until one was valid (self-crossing spines are drawn again)
};

/// A random campus and mission (see the file comment). Spine roads S1..S{n+1} from I0 through
/// J1..Jn to I{n+1}; branches B<k>a, B<k>b from Jk to E<k>a, E<k>b. Throws InvalidInput for bad
/// options, Error when 100 draws gave no valid map.
RandomCampus makeRandomCampus(const RandomCampusOptions& options);

}  // namespace mapnav
