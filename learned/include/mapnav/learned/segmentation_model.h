#pragma once
// A small fully-convolutional road segmentation network (docs/learned.md): trained on labelled
// photos (train_segmentation.h), saved as one file, run on CPU. No Torch in this header: the network
// lives behind a private pointer (src/network.h).
//
// Input: an RGB frame and where its camera sees the ground (1 = ground), resized to the model's
// input size; the colours normalised by the training set's mean and spread. Output: P(road) per pixel.
//
// The file (written atomically): the line "mapnav-segmentation-model 1", one line of JSON (input
// size, normalisation, the architecture's parameter names and shapes, how it was trained and the
// command that made it), then every parameter as little-endian float32 in that order.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace mapnav {

/// How a model was trained: the figures its file records.
struct SegmentationTraining {
  std::string command;                ///< the command line that made it
  std::uint64_t seed = 0;
  int epochs = 0;
  int training_images = 0, validation_images = 0;
  double final_loss = 0;              ///< mean training loss of the last epoch
  double validation_iou = -1;         ///< road IoU on the held-apart images at P > 0.5; -1 when none
};

class SegmentationModel {
 public:
  /// A fresh network of input `width` × `height` with weights drawn from `seed` (Torch's default
  /// initialisation), colours normalised by `mean` and `spread` (per channel, 0..255 levels).
  SegmentationModel(int width, int height, std::uint64_t seed, const std::vector<double>& mean = {127.5, 127.5, 127.5},
                    const std::vector<double>& spread = {64, 64, 64});
  SegmentationModel(SegmentationModel&&) noexcept;
  SegmentationModel& operator=(SegmentationModel&&) noexcept;
  ~SegmentationModel();

  /// Reads a model file. Throws IoError (missing, unreadable) or InvalidInput naming the file and
  /// what is wrong (not a model, bad JSON, unknown architecture, a parameter's shape, truncated).
  static SegmentationModel load(const std::filesystem::path& path);
  /// The file's bytes; save() writes them atomically.
  std::string bytes() const;
  void save(const std::filesystem::path& path) const;

  int inputWidth() const;
  int inputHeight() const;
  /// Number of weights and biases.
  std::size_t parameterCount() const;
  const SegmentationTraining& training() const;
  void setTraining(SegmentationTraining training);

  /// P(road) of each pixel of `rgb` (width × height × 3, row-major), width × height values in
  /// [0, 1]; `ground` (width × height, non-zero = the camera sees the ground there) or null (all
  /// ground). The frame is resized to the input size and the answer back (bilinear). Uses Torch's
  /// intra-op threads as set (setThreads).
  std::vector<float> roadProbability(const std::uint8_t* rgb, int width, int height, const std::uint8_t* ground) const;

  /// One step of online fine-tuning (the learned pipeline's `adapt`): plain gradient descent at
  /// `learning_rate` on the binary cross-entropy of the last `layers` convolutions' weights (1..11;
  /// the others as they are), against `labels` (width × height as roadProbability's frame: 0 not
  /// road, 1 road, any other value left out). The first call keeps the weights it starts from for
  /// resetAdaptation(). Returns the step's loss before it, or -1 when no pixel is labelled (no step).
  /// Throws InvalidInput for an empty frame or `layers` out of range.
  double adapt(const std::uint8_t* rgb, int width, int height, const std::uint8_t* ground, const std::uint8_t* labels,
               double learning_rate, int layers);
  /// Back to the weights before the first adapt() (nothing when it was never called).
  void resetAdaptation();

  /// Torch's CPU threads for this process (inference and training): 0 = leave Torch's default.
  static void setThreads(int threads);

  struct Impl;
  /// For train_segmentation.cpp only.
  Impl& impl() { return *impl_; }

 private:
  explicit SegmentationModel(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace mapnav
