#pragma once
// Road / non-road colour classification (Wallace 1985, 3.4): one Gaussian per class, trivariate in
// log RGB or bivariate in normalised colour rg (r = R/(R+G+B), g = G/(R+G+B), 3.4.3: robust to
// shadows, which scale a colour) — optionally with the log brightness as a third feature whose
// spread is floored (brightness_sigma: a shadow stays within reach, a black car or a white wall
// does not) — and a Bayes decision with quadratic boundaries (the log-likelihood
// ratio plus the log prior ratio). The models adapt frame to frame (3.4.2: the colours drift) with a
// guard against drifting away: an update is a blend, and a class estimate that moves the mean by
// more than N sigma, or rests on too few pixels, is refused (the class keeps its old model).
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

/// LogRGB: each channel c as 255 ln(c + 1) / ln 256 (0..255). The paper's classes are in RGB (3.4);
/// in its log a shadow, which scales the channels, moves a colour along the grey axis by the same
/// amount wherever the colour is, so one Gaussian with a spread along that axis (brightness_sigma)
/// covers a road in sun and shade without covering every grey (docs/measurements.md). NormalizedRG:
/// r = R/(R+G+B), g = G/(R+G+B).
enum class ColorSpace { LogRGB, NormalizedRG };

/// A Gaussian in 2 (rg) or 3 (log RGB; rg and brightness) dimensions; in 2-D only the upper-left
/// block is used.
struct GaussianClass {
  Vec3 mean = Vec3::Zero();
  Mat3 cov = Mat3::Identity();
  double count = 0;    ///< pixels of the last accepted estimate
  bool valid = false;
};

struct ColorClassifierOptions {
  ColorSpace space = ColorSpace::NormalizedRG;
  /// Weight of a frame's estimate when blended into a trained model (1 = replace). In (0, 1].
  double blend = 0.5;
  /// Refuse a road estimate whose mean is more than this many sigma (Mahalanobis, under the old
  /// model) from the old mean; a non-road one too unless it was gated (nonroad_gate_sigma > 0 with a
  /// road model to gate by): that one holds no road colour and follows the surroundings as they
  /// change (lawn, dirt, shadow). > 0.
  double max_mean_shift_sigma = 4.0;
  /// Refuse a class estimate from fewer labelled pixels than this. ≥ 1.
  int min_pixels = 400;
  /// Use every n-th pixel of each n-th row for training (speed). ≥ 1.
  int stride = 2;
  /// Leave out of the non-road estimate the pixels labelled non-road whose colour lies within this
  /// many sigma (Mahalanobis) of the road: the frame's road estimate, or the road model when the
  /// frame's is refused. On real roads "everything outside the predicted road" is mostly road; only
  /// what is confidently not road-coloured may train the non-road class. 0 = every labelled pixel.
  /// ≥ 0.
  double nonroad_gate_sigma = 0;
  /// The spread in log brightness added to every class (natural-log units: 0.1 is a 10 % brightness
  /// change), so that a road learnt in even light does not reject every shade (a deeper shadow is in
  /// reach when the road's spread, learnt from frames that show shadows, covers it).
  /// NormalizedRG: > 0 makes the log brightness ln((R + G + B + 3) / 3) a third feature with this
  /// added to its variance (rg alone cannot tell a grey road from a grey car, wall or kerb; the
  /// brightness can); 0 = rg only (Wallace 3.4.3). LogRGB: added along the grey axis (a brightness
  /// change δ moves every channel by 255 δ / ln 256). ≥ 0.
  double brightness_sigma = 0;
  /// With brightness_sigma > 0: the brightness is used only while rg alone separates the road and
  /// non-road models by less than this Bhattacharyya distance. Where colour tells road from its
  /// surroundings (grey path, green lawn: 5 and more), rg alone stays robust to shadows; where it
  /// does not (a grey road among grey cars and walls: 2 to 4), the brightness is needed. ≥ 0 and
  /// finite (an option's number is); the default, the largest double, is "whatever the separation".
  double brightness_separation = std::numeric_limits<double>::max();
  /// The camera's noise, 8-bit levels per channel: its variance is added to every class's (scaled to
  /// one level's effect at mid-grey: in rg by 1/500², in log RGB by (255 / ln 256 / 129)²). 1 suits rendered frames;
  /// a real camera's noise and compression call for more (the colour pipelines' 3). > 0.
  double noise_sigma = 1;

  /// colorClassifierOptionTable()'s rules. Throws InvalidInput naming the first bad field.
  void validate() const;
};
/// Its table: each option's name (the member's), rule and description.
const OptionTable<ColorClassifierOptions>& colorClassifierOptionTable();

/// Feature dimensions: 2 (rg), 3 (rg and log brightness, or log RGB).
int featureDims(const ColorClassifierOptions& options);
/// The feature of one pixel (rg in [0, 1] and ln((R+G+B+3)/3) in [0, 5.55]; log RGB in 0..255), in
/// the first featureDims() entries, 0 in the rest.
Vec3 colorFeature(const ColorClassifierOptions& options, const std::uint8_t* rgb);

/// The fast path's form of the log-odds: k + l·u + uᵀ q u in u = feature − c, single precision
/// (q's off-diagonal entries doubled). Internal to ColorClassifier; built from the class models.
struct LogOddsQuadratic {
  float c0 = 0, c1 = 0, c2 = 0;
  float q00 = 0, q01 = 0, q02 = 0, q11 = 0, q12 = 0, q22 = 0;
  float l0 = 0, l1 = 0, l2 = 0, k = 0;
};

class ColorClassifier {
 public:
  explicit ColorClassifier(ColorClassifierOptions options = {});

  struct UpdateResult {
    bool road_accepted = false;
    bool nonroad_accepted = false;
    std::string note;  ///< why an estimate was refused
  };
  /// Estimates both classes from labelled pixels (`road`, `nonroad`: w × h, non-zero = labelled)
  /// and blends them into the models (first call: takes them as they are). `nonroad_gate_sigma`:
  /// this update's gate (>= 0) in place of options().nonroad_gate_sigma.
  UpdateResult update(const std::uint8_t* rgb, int width, int height, const std::uint8_t* road,
                      const std::uint8_t* nonroad, std::optional<double> nonroad_gate_sigma = std::nullopt);
  /// log p(x | road) − log p(x | non-road) + log P(road)/P(non-road) for every pixel (row-major);
  /// only where `where` is non-zero (nullptr: everywhere), 0 elsewhere. Requires trained().
  /// The fast path: the two quadratic forms folded into one, centred between the class means,
  /// evaluated in single precision on planar colour (vectorised); it agrees with
  /// logOddsReference() to about 1e-4 in the log-odds (tested).
  std::vector<float> logOdds(const std::uint8_t* rgb, int width, int height, const std::uint8_t* where = nullptr) const;
  float logOdds(const std::uint8_t* pixel) const;
  /// The reference path: each class's Mahalanobis distance in double precision, pixel by pixel.
  std::vector<float> logOddsReference(const std::uint8_t* rgb, int width, int height,
                                      const std::uint8_t* where = nullptr) const;
  float logOddsReference(const std::uint8_t* pixel) const;

  bool trained() const { return road_.valid && nonroad_.valid; }
  /// Whether the log brightness is in use (brightness_sigma, brightness_separation).
  bool brightnessUsed() const { return brightness_used_; }
  /// Bhattacharyya distance between the two class models as used (0: indistinguishable).
  double separation() const;
  const GaussianClass& road() const { return road_; }
  const GaussianClass& nonroad() const { return nonroad_; }
  double priorRoad() const { return prior_road_; }
  const ColorClassifierOptions& options() const { return options_; }
  void reset();

 private:
  ColorClassifierOptions options_;
  GaussianClass road_, nonroad_;
  double prior_road_ = 0.5;
  // cached for logOdds: the models as used (in rg alone when the brightness is not)
  GaussianClass used_road_, used_nonroad_;
  bool brightness_used_ = false;
  Mat3 road_inv_, nonroad_inv_;
  double road_logdet_ = 0, nonroad_logdet_ = 0;
  LogOddsQuadratic quad_;
  void refreshCache();
};

}  // namespace mapnav
