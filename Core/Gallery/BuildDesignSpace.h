// BuildDesignSpace.h: a design space for a new volume in one call — exemplars, the decoder model
// with its image loss, evaluation, the bundle and its outline (what scripts/train_model.sh runs
// step by step, sized by the caller's time budget).
#pragma once

#include "Gallery/Gallery.h"

#include <functional>
#include <string>

namespace ddg
{

/// Options (defaults in brackets; the shipped bundles used 10 000-30 000 exemplars and 30 min).
struct BuildOptions
{
  DesignSpaceSpec spec;      ///< design space [defaults, regions found automatically]
  int count = 2000;          ///< training exemplars [2000]
  int heldout = 200;         ///< held-out exemplars for the recorded figures [200]
  int size = 64;             ///< image side [64]
  double minutes = 5;        ///< training budget [5]
  int iterations = 0;        ///< 0: the budget decides; else also the cosine schedule's length [0]
  int outlineCount = 10000;  ///< designs in the outline [10000]
  int width = 16;            ///< analyzer width [16]
  std::uint64_t seed = 1;    ///< [1]
  int threads = 0;           ///< 0 = all cores
  std::string workDirectory; ///< exemplars go here ["" = bundleDir + "/exemplars", removed after]
  bool screen = true;        ///< designs that show structure only (GenerateOptions::screen) [true]
};

struct BuildReport
{
  EvaluationReport evaluation; ///< on the held-out exemplars
  TrainReport training;
  GenerateReport exemplars; ///< the training exemplars' (regions, the screen's counts)
  double generateSeconds = 0, outlineSeconds = 0;
};

/// The figures of a model as bundle.json's "metrics" holds them.
std::string metricsToJson(const EvaluationReport& e, const TrainReport* t, std::int64_t parameters);

/// Generates exemplars of `volume` (recording `volumeFile`), trains the decoder (image loss
/// weight 100, learning rate 1e-3, cosine schedule when iterations > 0), evaluates it, writes
/// the bundle to `bundleDir` and its outline. Progress gets the stage ("exemplars", "training",
/// "outline") and the overall fraction; returning false cancels (throws ddg::Cancelled; no
/// bundle.json is left). Throws ddg::Error for bad options or volumes.
BuildReport buildDesignSpace(const Volume& volume, const std::string& volumeFile,
  const std::string& bundleDir, const BuildOptions& options,
  const std::function<bool(const std::string& stage, double fraction)>& progress = {});

} // namespace ddg
