// BuildDesignSpace.h: a design space for a new volume in one call — exemplars, the decoder model
// with its image loss, evaluation, the bundle and its outline (what scripts/train_model.sh runs
// step by step, sized by the caller's time budget).
#pragma once

#include "Design/ExemplarGenerator.h"
#include "Gallery/BuildPlan.h"
#include "Gallery/Gallery.h"

#include <chrono>
#include <functional>
#include <string>

namespace ddg
{

/// Options (defaults in brackets; the shipped bundles used 10 000-30 000 exemplars and 30 min).
struct BuildOptions
{
  DesignSpaceSpec spec;     ///< design space [defaults, regions found automatically]
  int count = 2000;         ///< training exemplars [2000]
  int heldout = 200;        ///< held-out exemplars for the recorded figures [200]
  int size = 64;            ///< image side [64]
  double minutes = 5;       ///< training budget [5]
  int iterations = 0;       ///< 0: the budget decides; else also the cosine schedule's length [0]
  int outlineCount = 10000; ///< designs in the outline [10000]
  int width = 16;           ///< analyzer width [16]
  /// share of the analyzer's training images from each exemplar's other view
  /// (TrainOptions::otherViewFraction; Documentation/DesignSpaces.md) [0.5]
  double otherViewFraction = 0.5;
  /// the image loss's sample distance over ParaView's (TrainOptions::imageSampleScale) [1]
  double imageSampleScale = 1.0;
  std::uint64_t seed = 1;    ///< [1]
  int threads = 0;           ///< 0 = all cores
  std::string workDirectory; ///< exemplars go here ["" = a staging folder, removed after]
  /// > 0: planBuild sizes count, heldout, minutes and outlineCount (overriding them) so that
  /// the whole build takes about this many minutes (>= 1) [0: the sizes above]
  double budgetMinutes = 0;
  bool overwrite = false; ///< replace a bundle already in bundleDir (else refused) [false]
  /// volumes above this many voxels are downsampled for the design space [16 Mi]
  std::int64_t maxDesignVoxels = kMaxDesignSpaceVoxels;
  /// rates measured before (e.g. for the plan shown to the user: the build then follows that
  /// plan); not measured: probed at the start [not measured]
  BuildRates rates;
  bool screen = true; ///< designs that show structure only (GenerateOptions::screen) [true]
  /// Other processes that render shares of the exemplars and of the outline's designs
  /// (GenerateOptions::workers, buildOutlineLatents; not owned, not ended: the caller sends them
  /// "end") [none]
  ExemplarWorkers* workers = nullptr;
};

struct BuildReport
{
  EvaluationReport evaluation; ///< on the held-out exemplars
  TrainReport training;
  GenerateReport exemplars; ///< the training exemplars' (regions, the screen's counts)
  int workerCandidates = 0; ///< candidates (training and held-out) rendered by options.workers
  double generateSeconds = 0, outlineSeconds = 0, totalSeconds = 0;
  double evaluationSeconds = 0, savingSeconds = 0; ///< held-out figures; the bundle's files
  BuildPlan plan; ///< what was planned (the budget's plan, or the estimate of the sizes given)
  /// The query key's view pairs (0: the bundle has none; queryKeyNote says why: queries then
  /// compare latents as they are)
  int queryKeyPairs = 0;
  std::string queryKeyNote;
};

/// The figures of a model as bundle.json's "metrics" holds them.
std::string metricsToJson(const EvaluationReport& e, const TrainReport* t, std::int64_t parameters);

/// Checks the volume (checkBuildVolume) and the output folder (checkBuildOutput) before writing
/// anything; downsamples a volume above options.maxDesignVoxels for the design space
/// (designSpaceVolume; the bundle keeps the original volume's fingerprint, so it is the
/// original's model); with a budget, sizes the build (planBuild). Then generates exemplars of
/// `volume` (recording `volumeFile`), trains the decoder (image loss weight 100, learning rate
/// 1e-3, cosine schedule when iterations > 0), evaluates it and builds its outline, all in a
/// staging folder inside `bundleDir`, whose files are moved into `bundleDir` at the end
/// (bundle.json last). Progress gets the stage ("exemplars", "training", "evaluation",
/// "outline") and the overall fraction (stages weighted by their estimated time, so that it
/// grows about linearly with time); it is called at least every ~0.5 s; returning false
/// cancels: ddg::Cancelled is thrown and the staging folder removed (a folder created by the
/// build too): `bundleDir` keeps what it had. Throws ddg::Error for bad options, volumes or
/// folders (nothing written then).
BuildReport buildDesignSpace(const Volume& volume, const std::string& volumeFile,
  const std::string& bundleDir, const BuildOptions& options,
  const std::function<bool(const std::string& stage, double fraction)>& progress = {});

/// The same on a design space's input already made (designSpaceInput in one process; a
/// DesignSpaceAssembler fed the slabs of a volume split over processes): options.maxDesignVoxels
/// is not used. `start`: when the build began (its reported total time counts from there).
BuildReport buildDesignSpace(const DesignSpaceInput& input, const std::string& volumeFile,
  const std::string& bundleDir, const BuildOptions& options,
  const std::function<bool(const std::string& stage, double fraction)>& progress,
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now());

} // namespace ddg
