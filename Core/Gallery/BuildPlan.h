// BuildPlan.h: what a design-space build will cost before it starts — a time budget turned into
// exemplar, training and outline sizes, the stages' estimated seconds and disk use — and the
// checks of the volume and the output folder that refuse bad input before anything is written.
#pragma once

#include "Volume/Volume.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddg
{

/// Volumes above this many voxels are downsampled for the design space (designSpaceVolume).
constexpr std::int64_t kMaxDesignSpaceVoxels = 16 * 1024 * 1024;

/// The share of a budget a plan fills (planBuild): a budgeted build's training ends when the plan
/// has it end (buildDesignSpace), so what is left covers the estimates of the stages after it.
constexpr double kBuildBudgetShare = 0.95;

struct DesignSpaceInput; // below

/// Measured costs of one build's units on this machine for one volume (wall-clock seconds with
/// the threads the build uses, under the machine's load at the time).
struct BuildRates
{
  double exemplarSeconds = 0;     ///< one exemplar generated (2 renders, the shard write)
  double renderSeconds = 0;       ///< one outline design's render (half an exemplar)
  double analyzeSeconds = 0;      ///< the analyzer on one image, alone (held-out figures)
  double analyzeBatchSeconds = 0; ///< ... per image in a batch (outline)
  double figureSeconds = 0;       ///< a held-out figure's PSNR, SSIM and colour-histogram EMD
  double framedSeconds = 0;       ///< a picture upsampled 3x and framed as a query (the query
                                  ///< key's pairs; the resizes use every thread)
  double keyFitSeconds = 0;       ///< the contrastive query key's training, per pair and epoch
  int threads = 1;                ///< threads the build's parallel stages use
  bool measured() const { return exemplarSeconds > 0; }
};

/// A build sized for a time budget, or the estimate of a build with given sizes.
struct BuildPlan
{
  double budgetMinutes = 0; ///< the budget it was planned for (0: sizes given, estimate only)
  int count = 0;            ///< training exemplars
  int heldout = 0;          ///< held-out exemplars (the recorded figures)
  int outlineCount = 0;     ///< designs in the outline
  int size = 64;            ///< image side
  double trainingMinutes = 0;
  /// Estimated seconds per stage: exemplars (training and held-out), training, evaluation
  /// (held-out figures, and saving the bundle: the training exemplars' latents), outline; and
  /// their sum with a fixed overhead.
  double exemplarSeconds = 0, trainingSeconds = 0, evaluationSeconds = 0, outlineSeconds = 0;
  double queryKeySeconds = 0; ///< the query key's part of outlineSeconds
  double totalSeconds = 0;
  std::int64_t diskBytes = 0;      ///< peak disk use (exemplar shards + the bundle)
  std::int64_t bundleBytes = 0;    ///< what stays (the bundle)
  std::array<int, 3> designDims{}; ///< the volume the design space is built on (downsampled?)
  int downsample = 1;              ///< its factor per axis (1: the volume as it is)
  BuildRates rates;

  /// The plan as JSON: every field above (the filter's BuildPlan property, `ddg build --budget`).
  std::string toJson() const;
  /// One line per stage with its estimated minutes, and the disk use, for people.
  std::string describe() const;
  /// A budgeted build's training minutes when its exemplars are done `elapsedSeconds` after the
  /// build started: training ends when the plan has it end (exemplars that took longer than
  /// estimated shorten it, faster ones lengthen it), but lasts at least half the planned minutes.
  double trainingMinutesAfter(double elapsedSeconds) const;
};

/// Times what a build does, on `volume` (its design-space volume: downsample first) at `size`
/// pixels: `probes` exemplars really generated (into a temporary folder, removed), the
/// analyzer alone and on a batch of 32 images (a decoder of the build's architecture, untrained
/// weights). ~0.3-2 s.
BuildRates measureBuildRates(const Volume& volume, int size = 64, int threads = 0, int probes = 16);

/// The estimate of a build with the given sizes (trainingMinutes is the training budget). The
/// outline's designs up to `count` are the training exemplars, analysed from their images
/// (outlineFromExemplars, Gallery.h), only those beyond it are rendered; with `outlineRendered`
/// (a spec whose analyzer images are users' pictures) every one is rendered.
BuildPlan estimateBuild(const std::array<int, 3>& designDims, int downsample,
  const BuildRates& rates, int count, int heldout, int outlineCount, int size,
  double trainingMinutes, bool outlineRendered = false);

/// Sizes a build so that all of it, outline included, is estimated to take ~95 % of
/// `budgetMinutes` (>= 1): outline designs as many as 10 % of it would render (1 000 - 10 000;
/// those that are training exemplars cost only the analyzer, estimateBuild), exemplars ~25 %
/// (256 - 30 000), held-out a tenth of them (50 - 200), training the rest (at least 35 % of the
/// budget; the exemplars and outline shrink to leave it). `volume` is the user's volume
/// (downsampled here for the probe when above maxDesignVoxels, as the build does). Throws
/// ddg::Error for a budget under 1 minute. `rates`: measured before (the plan shown to the user
/// is the plan built), else probed. `outlineRendered` as estimateBuild.
BuildPlan planBuild(const Volume& volume, double budgetMinutes, int size = 64, int threads = 0,
  const BuildRates& rates = {}, std::int64_t maxDesignVoxels = kMaxDesignSpaceVoxels,
  bool outlineRendered = false);
/// The same for a design space's input already made (its volume probed as it is).
BuildPlan planBuild(const DesignSpaceInput& input, double budgetMinutes, int size = 64,
  int threads = 0, const BuildRates& rates = {}, bool outlineRendered = false);

/// The volume the design space is built on: `volume` itself when it has at most `maxVoxels`
/// voxels, else its box-filtered average over f x f x f blocks (f the smallest integer that
/// brings it under the cap; spacing x f, same origin). `factor` receives f.
Volume designSpaceVolume(const Volume& volume, std::int64_t maxVoxels, int* factor = nullptr);

/// designSpaceVolume's f for a volume of `dims` points.
int designSpaceFactor(const std::array<int, 3>& dims, std::int64_t maxVoxels);

/// The volume a design space is built on, and what its bundle records of the user's volume.
struct DesignSpaceInput
{
  Volume volume;           ///< designSpaceVolume's (the user's volume itself when factor is 1)
  int factor = 1;          ///< its downsampling factor per axis
  std::string fingerprint; ///< with factor > 1: the user's volume's volumeFingerprint
};

/// checkBuildVolume, then designSpaceVolume and the user's volume's fingerprint.
DesignSpaceInput designSpaceInput(const Volume& volume, std::int64_t maxVoxels);

/// designSpaceVolume of a volume that arrives a slab of whole point planes at a time (z
/// ascending, x fastest; every slab but the last a multiple of factor() planes thick), e.g. from
/// the pieces of a volume split over processes: the same volume, bit for bit, holding only the
/// result (the design-space volume, at most maxVoxels: allocated with the first slab) and the
/// caller's slab.
class DesignSpaceAssembler
{
public:
  /// The user's volume: its points per axis, origin, spacing and scalar type.
  DesignSpaceAssembler(const std::array<int, 3>& dims, const std::array<double, 3>& origin,
    const std::array<double, 3>& spacing, ScalarType type, std::int64_t maxVoxels);
  int factor() const { return Factor; }
  /// A slab thickness of whole blocks with about `values` points (at least one block).
  int slabPlanes(std::int64_t values) const;
  /// The next slab: planes z0 .. z0 + planes - 1, dims[0] x dims[1] x planes values.
  void add(int z0, int planes, const float* values);
  /// The design-space volume once every plane came (else throws), with the user's volume's
  /// `fingerprint` (DesignSpaceInput).
  DesignSpaceInput finish(const std::string& fingerprint);

private:
  std::array<int, 3> Dims;
  std::array<double, 3> Origin, Spacing;
  ScalarType Type;
  int Factor = 1, Next = 0;
  std::vector<float> Values;
};

/// Refuses, with a message for the user, volumes a design space cannot be built on: a single
/// value everywhere, or fewer than 4 voxels along an axis (a slice, not a volume).
void checkBuildVolume(const Volume& volume);
/// The same from the volume's points per axis and its data range.
void checkBuildVolume(const std::array<int, 3>& dims, const std::array<double, 2>& range);

/// Refuses an output folder before anything is written: a path that is a file, a folder that
/// already holds a bundle (bundle.json) unless `overwrite`, a folder that cannot be written, or
/// less free space than `diskBytes` (+ 5 %). Writes nothing itself.
void checkBuildOutput(const std::string& bundleDir, std::int64_t diskBytes, bool overwrite);

} // namespace ddg
