// ReconstructSupport.h: what `ddg reconstruct`'s two files share: its arguments, reading a
// target, writing the TF, and the carried look's part (ReconstructCarry.cxx: --carry-look).
#pragma once

#include "CommandSupport.h"

#include "Image/Image.h"
#include "Reconstruct/Match.h"
#include "Reconstruct/Reconstruction.h"
#include "Render/RayCaster.h"
#include "Render/View.h"

#include <string>
#include <vector>

namespace ddg::cli::reconstruct
{

struct ReconstructArgs
{
  std::string volume, out, outImage, init, array, loss = "l1";
  std::vector<std::string> targets, views, masks;
  std::vector<double> background;
  bool twoD = false, resample = false, quiet = false, estimateView = false, otherVolume = false;
  std::string outView, outOverlay, shade = "auto";
  std::string kindNetwork; ///< --carry-look: "" the shipped one (when built here), "none": no check
  int bins = 128, gradientBins = 32, iterations = 500, rays = -1, threads = 0, primitives = 0;
  int cameraCandidates = ddg::MatchOptions().cameraCandidates;
  double smoothness = 0.01, learningRate = 0.2, ssimWeight = 0.0;
  unsigned seed = 1;
  bool iterationsGiven = false;
  /// Options given on the command line that --carry-look does not use (refused with it).
  std::vector<std::string> notForCarry;
};

/// Reads a target image for reconstruction and checks what the reconstruction can use; the size
/// against `view`'s when there is one (a match without a view takes any size).
ddg::Image readTarget(const std::string& path, const ddg::View* view, bool resample);

/// The TF file, named for the volume, what made it and the file (Core's export).
void writeResult(const ddg::ReconstructionResult& result, const ReconstructArgs& a,
  const std::string& origin, const ddg::RayCaster& caster, const ddg::View& view);

/// Records which options the command line gave that matter to --carry-look: --iterations, and
/// those of the match's fit it refuses (notForCarry).
void noteCarryOptions(const CLI::App& reconstruct, ReconstructArgs& a);

/// --carry-look: a picture of another volume, Core's carryLook (its colours carried over by
/// region).
int runCarry(const ReconstructArgs& a);

} // namespace ddg::cli::reconstruct
