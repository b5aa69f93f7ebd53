// NeuralDesignModel.h: the neural design model — the paper's Neural DVR Analyzer, Renderer
// (U-Net) and PatchGAN Discriminator, or the lean decoder — its training on design exemplars,
// and model bundles. libtorch stays inside Core/Neural's .cxx files (and its private headers
// NeuralNetworks.h, NeuralDesignModelInternals.h); this header does not include it.
#pragma once

#include "Design/ExemplarGenerator.h"
#include "Image/Image.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ddg
{

/// Architecture (defaults in brackets). Images are size x size; every block halves the side
/// with a 4x4 stride-2 convolution down to 4 x 4.
struct NetworkConfig
{
  /// "unet": the paper's renderer (U-Net on the viewport image); "decoder": the lean variant,
  /// a small MLP from the latent to explicit Gaussian-primitive parameters per feature region,
  /// shown by the real ray caster (exact images, an explicit TF, viewport invariant) ["unet"].
  std::string kind = "unet";
  int imageSize = 64;   ///< [64] power of two, 16..512
  int width = 16;       ///< channels of the first block, doubled per block up to 8x [16]
  int latent = 64;      ///< latent TF size [64]
  double dropout = 0.5; ///< in the renderer's up blocks [0.5]
  int regions = 0;      ///< decoder: feature regions (set from the training data)
  int dimensions = 1;   ///< decoder: 1D or 2D TFs (set from the training data's spec)

  void validate() const;
};

/// Training options (defaults in brackets; the paper's where it gives them).
struct TrainOptions
{
  int batch = 16;             ///< [16]
  double learningRate = 2e-4; ///< Adam, beta1 0.5, beta2 0.999 [2e-4]
  double lambdaL1 = 1000;     ///< L = L_adv + lambda L1 [1000]
  double minutes = 10;        ///< wall-clock budget [10]
  int maxIterations = 0;      ///< 0 = until the budget
  std::uint64_t seed = 1;     ///< initialisation and batch order [1]
  int threads = 0;            ///< libtorch intra-op threads, 0 = all cores
  std::string checkpoint;     ///< file to write every checkpointEvery iterations ("" = none)
  int checkpointEvery = 500;
  bool resume = false; ///< continue from `checkpoint` if it exists
  /// Decoder only: weight of the image loss through the real ray caster (L1 of premultiplied
  /// RGBA at V_view against the ground truth, on `imageRays` random pixels per exemplar; the
  /// renderer's adjoint and the rasterization adjoint carry its gradient into decoder and
  /// analyzer). 0 = TF-parameter regression only. Needs attachVolume() first [0].
  double imageWeight = 0;
  int imageRays = 512; ///< [512]
  /// The image loss's rays sample every imageSampleScale x ParaView's sample distance (opacity
  /// corrected): its truths are 64-pixel images, which a step of a voxel resolves about as well
  /// as ParaView's half voxel, at half the samples. With adaptiveRays the timed steps sample at
  /// ParaView's step and the scale applies after them: the rays are chosen as without it, and
  /// what the coarser march saves goes to more steps [1: the truths' own step]
  double imageSampleScale = 1.0;
  /// With the image loss: time the image loss and the rest of the step over the first steps of
  /// this call (kAdaptiveRaysFrom to kAdaptiveRaysTo), then cast adaptiveImageRays(imageRays,
  /// ...) rays per exemplar, so that a training bounded by minutes spends no more on the image
  /// loss than on the rest of a step (TrainReport::imageRays says how many). It depends on the
  /// machine's timing: leave it off where a training must repeat to the byte [false].
  bool adaptiveRays = false;
  /// Share of the analyzer's images that are the exemplar at its other view: the ground truth at
  /// V_view composed over black or white (drawn with it), instead of the image at V_exp. Both
  /// views are drawn alike, so this doubles the pictures of a design the analyzer learns from
  /// without rendering any more; the targets (the TF, the image at V_view) stay [0].
  double otherViewFraction = 0;
  /// Cosine learning-rate schedule from learningRate down to 5 % of it at maxIterations (a
  /// function of the iteration, so resuming continues it) or, without maxIterations, at the end
  /// of the time budget (a function of the seconds spent in this call) [false].
  bool cosineSchedule = false;
  /// Asked on the calling thread between the image-loss renders of a batch (an iteration can
  /// take ~1 s on a loaded machine); returning true stops at once: train() throws
  /// ddg::Cancelled [none]
  std::function<bool()> interrupt;
};

/// Which of a batch's `count` analyzer images are taken from the exemplar's other view
/// (TrainOptions::otherViewFraction = `fraction`), and over which background: per image, -1 for
/// its image at V_exp, else 0 (black) or 1 (white). Drawn from (seed, iteration) alone, so a
/// resumed training draws what an uninterrupted one does.
std::vector<int> otherViewDraw(int count, double fraction, std::uint64_t seed, int iteration);

struct TrainProgress
{
  int iteration = 0;
  double lossG = 0, lossD = 0, l1 = 0; ///< generator (adv + lambda L1), discriminator, mean L1
  double image = 0; ///< decoder: mean image L1 through the ray caster (0 when not used)
  double seconds = 0, eta = 0;
};

struct TrainReport
{
  int iterations = 0;
  double seconds = 0;
  double exemplarsPerSecond = 0;
  bool cancelled = false;
  int imageRays = 0; ///< image-loss rays per exemplar at the end (0: no image loss)
};

/// The steps of a train() call timed by TrainOptions::adaptiveRays: [from, to) after its start.
constexpr int kAdaptiveRaysFrom = 5, kAdaptiveRaysTo = 25;

/// The image-loss rays of a training with TrainOptions::adaptiveRays, from the seconds its
/// timed steps spent in the image loss and on the rest: maxRays x min(1, rest / image), rounded
/// to maxRays over the nearest power of two (in log), and at least maxRays / 4 (and 1).
int adaptiveImageRays(int maxRays, double imageSeconds, double restSeconds);

/// Image-quality figures of a model on held-out exemplars (neural render vs. ground truth,
/// both over a mid-grey background, 8 bit) and of its analyzer's viewpoint invariance.
struct EvaluationReport
{
  int count = 0;
  double psnr = 0, ssim = 0, emd = 0;
  double invariance = 0; ///< fraction of triplets where the same TF from two views is closer
  double analyzerMs = 0, rendererMs = 0; ///< one image, batch 1
  struct Item
  {
    double psnr = 0, ssim = 0, emd = 0;
  };
  std::vector<Item> items; ///< per exemplar, in order
};

/// What a bundle keeps of its training exemplars, for the gallery: their latents (count x
/// latent, row-major) and their TFs (1D Gaussian primitives).
struct TrainingDesigns
{
  int latent = 0;
  std::vector<float> latents;
  std::vector<std::vector<GaussianPrimitive>> tfs;
  int count() const { return static_cast<int>(tfs.size()); }
  const float* latentOf(int i) const { return latents.data() + static_cast<size_t>(i) * latent; }
};

/// Analyzer + renderer + discriminator.
class NeuralDesignModel
{
public:
  explicit NeuralDesignModel(const NetworkConfig& config, std::uint64_t seed = 1);
  ~NeuralDesignModel();
  NeuralDesignModel(NeuralDesignModel&&) noexcept;
  NeuralDesignModel& operator=(NeuralDesignModel&&) noexcept;

  const NetworkConfig& config() const;
  /// Parameters of analyzer + renderer (the discriminator is not shipped).
  std::int64_t parameterCount() const;

  /// Latent of an RGB (or RGBA: alpha dropped) image of any size (resized to the model's).
  std::vector<float> analyze(const Image& image) const;
  /// Latents of many images at once (each resized like analyze): images.size() x latent,
  /// row-major. Batched, so much faster per image than analyze().
  std::vector<float> analyzeBatch(const std::vector<Image>& images) const;
  /// Neural render of `latent` with the viewport image (premultiplied RGBA at the model's size):
  /// premultiplied RGBA.
  Image render(const std::vector<float>& latent, const Image& viewport) const;

  /// The image of `latent` at `view` (premultiplied RGBA, the view's size): the U-Net's render
  /// of the viewport image (resized to the model's size) or, for the decoder, the ray cast of
  /// the decoded TF (needs attachVolume).
  Image renderAt(const std::vector<float>& latent, const Image& viewport, const View& view) const;

  /// Decoder: the explicit TF of a latent (DecoderLayout::decode: opacity x sigmoid(logit)).
  std::vector<GaussianPrimitive> decode(const std::vector<float>& latent) const;
  /// Decoder: one primitive per feature region (DecoderLayout::decodeRegions, none left out).
  std::vector<GaussianPrimitive> decodeRegions(const std::vector<float>& latent) const;

  /// Decoder: the volume to ray cast (its fingerprint must match the bundle's when loaded).
  void attachVolume(const Volume& volume);

  /// Trains on `data` (its images must be config().imageSize). progress may cancel.
  TrainReport train(const ExemplarDataset& data, const TrainOptions& options,
    const std::function<bool(const TrainProgress&)>& progress = {});

  /// Figures on the first maxExemplars of `data`. Progress gets the fraction done after each
  /// exemplar and may cancel (throws ddg::Cancelled).
  EvaluationReport evaluate(const ExemplarDataset& data, int maxExemplars = 1000,
    const std::function<bool(double)>& progress = {}) const;

  /// Writes a bundle directory: weights (model.pt), bundle.json (config, the volume's
  /// fingerprint, spec, regions, metrics json), latents.bin (float32, training latents) and
  /// exemplars.json (their TF parameters); a query key of the old weights is removed
  /// (kQueryKeyFileName). Atomic per file; bundle.json last. Progress gets
  /// the fraction of the training latents analysed (every 128) and may cancel (throws
  /// ddg::Cancelled; bundle.json is not written then).
  void saveBundle(const std::string& dir, const ExemplarDataset& training,
    const std::string& metricsJson, const std::function<bool(double)>& progress = {}) const;
  /// Loads a bundle; throws ddg::Error for a missing/corrupt/truncated bundle, a wrong
  /// architecture, or (when expectedFingerprint is not empty) a bundle of another volume.
  static NeuralDesignModel loadBundle(
    const std::string& dir, const std::string& expectedFingerprint = "");

  /// The training designs of a loaded bundle (empty otherwise).
  const TrainingDesigns& trainingDesigns() const;
  /// The feature regions and design-space spec the model was trained with.
  const std::vector<FeatureRegion>& regions() const;
  const DesignSpaceSpec& spec() const;

  /// The model's networks and state: opaque here, defined in Core/Neural's private
  /// NeuralDesignModelInternals.h (libtorch), shared by the model's inference, training and
  /// bundles.
  struct Internals;

private:
  std::unique_ptr<Internals> In;
};

} // namespace ddg
