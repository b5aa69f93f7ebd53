// ReconstructCarry.cxx: `ddg reconstruct --carry-look`, a picture of another volume of the same
// kind: its look carried over (Core's carryLook).
#include "ReconstructSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Reconstruct/CarryLook.h"
#include "Render/DifferentiableRenderer.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <cstdio>
#include <filesystem>

#ifndef DDG_DATA_DIR
#define DDG_DATA_DIR ""
#endif

namespace
{
// Options of the match and the fits that the carried look does not take (its fit has its own
// settings: Core's CarryLookOptions).
const char* const kNotForCarry[] = { "--bins", "--gradient-bins", "--primitives", "--loss",
  "--smoothness", "--lr", "--rays", "--resample", "--ssim-weight", "--camera-candidates",
  "--background" };

} // namespace

namespace ddg::cli::reconstruct
{

void noteCarryOptions(const CLI::App& reconstruct, ReconstructArgs& a)
{
  a.iterationsGiven = reconstruct.count("--iterations") > 0;
  for (const char* name : kNotForCarry)
    if (reconstruct.count(name) > 0)
      a.notForCarry.emplace_back(name);
}

int runCarry(const ReconstructArgs& a)
{
  if (a.targets.size() != 1 || !a.views.empty() || !a.masks.empty() || a.twoD || a.estimateView ||
    !a.outView.empty() || !a.outOverlay.empty())
    throw ddg::Error("--carry-look takes one --target and no --view, --mask, --2d, "
                     "--estimate-view, --out-view or --out-overlay");
  if (!a.notForCarry.empty())
  {
    std::string names;
    for (const auto& n : a.notForCarry)
      names += (names.empty() ? "" : ", ") + n;
    throw ddg::Error("--carry-look does not use " + names +
      " (its fit compares colour distributions at its own settings; it takes --iterations, "
      "--init, --seed, --shade, --threads, --array, --out-image, --kind-network and --quiet)");
  }
  const auto t0 = Clock::now();
  // the kind check: --kind-network, by default the shipped network when it is there (loaded
  // before the fit: a bad one fails before anything is written)
  std::string kindOption = a.kindNetwork;
#ifdef DDG_WITH_TORCH
  if (kindOption.empty() && std::filesystem::exists(DDG_DATA_DIR "/Models/kind/kind.json"))
    kindOption = DDG_DATA_DIR "/Models/kind";
#endif
  const std::string kind = kindNetworkOption(kindOption);
  const ddg::Image picture = readTarget(a.targets[0], nullptr, false);
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  const ddg::DifferentiableRenderer renderer(volume);
  ddg::CarryLookOptions opt;
  opt.fit.seed = a.seed;
  opt.fit.render.threads = a.threads;
  if (a.iterationsGiven)
    opt.fit.iterations = a.iterations;
  if (!a.init.empty()) // from a TF of this volume (a query's design): free bins from it
    ddg::carryLookFrom(opt, ddg::readPreset(a.init), volume.range());
  if (a.shade == "on")
    opt.lighting.shade = true;
  const double tLoad = msSince(t0);
  const auto r = ddg::carryLook(renderer, picture, opt,
    [&](int step, double loss, const ddg::ReconstructionResult*)
    {
      if (!a.quiet && step % 50 == 0)
      {
        std::printf("step %4d  colour distance %.3f\n", step, loss);
        std::fflush(stdout);
      }
      return true;
    });
  const ddg::View view = ddg::carriedLookView(volume.bounds(), r, opt, 512);
  writeResult(r.fit, a, "carried look", renderer.caster(), view);
  std::printf("background: (%.3f %.3f %.3f); overlays left out: %.1f %% of the foreground\n",
    r.background.bottom[0], r.background.bottom[1], r.background.bottom[2], 100 * r.overlayShare);
  for (const auto& c : r.regions)
    std::printf("region [%g, %g] <- the picture's colour (%.2f %.2f %.2f), %.0f %% of its object\n",
      c.region.lo, c.region.hi, c.colour[0], c.colour[1], c.colour[2], 100 * c.share);
  std::printf(
    "shape agreement %.2f (this volume's best silhouette against the picture's object)%s\n",
    r.shapeAgreement,
    r.shapesAgree ? "" : ": the shapes disagree, the picture may show a volume of another kind");
  std::printf("colour distance %.2f -> %.2f (CIELAB, sliced Wasserstein) after %d steps; %.2f s "
              "(load %.0f ms); wrote %s\n",
    r.distanceStart, r.distanceEnd, r.fit.iterations, r.seconds, tLoad, a.out.c_str());
  if (!a.outImage.empty())
    ddg::writeImage(ddg::compositeOverBackground(
                      ddg::renderResult(renderer.caster(), r.fit, view, {}), view.background),
      a.outImage);
  printKindCheck(kind, a.threads, picture, volume);
  return 0;
}

} // namespace ddg::cli::reconstruct
