// BuildCommand.cxx: `ddg build` — build a design space for a volume in one command: exemplars, the
// decoder model trained within a budget, its figures, the bundle and its outline.
#ifdef DDG_WITH_TORCH
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/BuildDesignSpace.h"
#include "Gallery/BundleSession.h"
#include "Gallery/DesignReference.h"
#include "Gallery/Export.h"
#include "Gallery/Gallery.h"
#include "Gallery/History.h"
#include "Image/Image.h"
#include "Render/View.h"
#include "TransferFunction/ColorSpace.h"

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct BuildArgs
{
  std::string volume, out, spec;
  ddg::BuildOptions o;
  bool quiet = false, planOnly = false;
};

volatile std::sig_atomic_t interrupted = 0;

int runBuild(BuildArgs a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume);
  if (!a.spec.empty())
    a.o.spec = ddg::readDesignSpaceSpec(a.spec);
  if (a.planOnly)
  {
    if (!(a.o.budgetMinutes > 0))
      throw ddg::Error("--plan needs --budget MINUTES");
    ddg::checkBuildVolume(volume);
    const ddg::BuildPlan plan = ddg::planBuild(volume, a.o.budgetMinutes, a.o.size, a.o.threads, {},
      a.o.maxDesignVoxels, a.o.spec.pictureFraction > 0);
    std::printf("plan for %g min:\n%s%s\n", a.o.budgetMinutes, plan.describe().c_str(),
      plan.toJson().c_str());
    ddg::checkBuildOutput(a.out, plan.diskBytes, a.o.overwrite);
    return 0;
  }
  // Ctrl+C cancels: the build removes what it wrote
  interrupted = 0;
  const auto previous = std::signal(SIGINT, [](int) { interrupted = 1; });
  std::string lastStage;
  int lastPercent = -1;
  const auto r = ddg::buildDesignSpace(volume, a.volume, a.out, a.o,
    [&](const std::string& stage, double f)
    {
      const int p = static_cast<int>(100 * f);
      if (!a.quiet && (stage != lastStage || p / 10 != lastPercent / 10))
      {
        std::printf("build: %-9s %3d %%\n", stage.c_str(), p);
        std::fflush(stdout);
        lastStage = stage;
        lastPercent = p;
      }
      return interrupted == 0;
    });
  std::signal(SIGINT, previous);
  if (!a.quiet)
    std::printf("planned (%s):\n%s", a.o.budgetMinutes > 0 ? "budget" : "estimate",
      r.plan.describe().c_str());
  std::printf("built %s in %.1f min: %d exemplars %.0f s, training %d iterations in %.0f s "
              "(%d image-loss rays), evaluation %.0f s + saving %.0f s, outline %d designs %.0f s; "
              "held-out %d: PSNR %.2f dB, SSIM %.4f, EMD %.3f, invariance %.3f\n",
    a.out.c_str(), r.totalSeconds / 60, r.plan.count, r.generateSeconds, r.training.iterations,
    r.training.seconds, r.training.imageRays, r.evaluationSeconds, r.savingSeconds,
    r.plan.outlineCount, r.outlineSeconds, r.evaluation.count, r.evaluation.psnr, r.evaluation.ssim,
    r.evaluation.emd, r.evaluation.invariance);
  if (r.queryKeyPairs > 0)
    std::printf("query key: fitted on %d view pairs\n", r.queryKeyPairs);
  else
    std::printf(
      "query key: none (%s); queries compare latents as they are\n", r.queryKeyNote.c_str());
  const auto& x = r.exemplars;
  if (a.o.screen)
    std::printf(
      "designs that show structure: %zu feature region(s), %d left out; %d candidates for "
      "%d exemplars, %d empty and %d flat box passed over%s\n",
      x.regions.size(), x.regionsLeftOut, x.candidates, x.count, x.empty, x.flatBox,
      x.screenExhausted ? "; candidates ran out, the last exemplars kept as drawn" : "");
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addBuildCommand(CLI::App& app)
{
  auto ba = std::make_shared<BuildArgs>();
  auto* build = app.add_subcommand("build",
    "Build a design space for a volume in one command: exemplars, the decoder model trained "
    "within --minutes, its held-out figures, the bundle and its outline (the steps of "
    "scripts/train_model.sh, sized for your own volume). With --budget MINUTES the whole build "
    "is sized to take that long (--count, --heldout, --minutes and --outline are then ignored); "
    "--plan shows what it would cost and writes nothing. Refused before anything is written: a "
    "volume with one value or under 4 voxels along an axis, a folder that already holds a "
    "bundle (unless --overwrite), a folder you cannot write to or without the free space. "
    "Volumes over 16 Mi voxels (--design-voxels) are downsampled (box average) for the design "
    "space; the bundle still belongs to the original volume. Ctrl+C or a failure leaves the "
    "folder as it was.");
  build->add_option("--volume", ba->volume, "Volume file")->required();
  build->add_option("--out", ba->out, "Bundle directory to write")->required();
  build->add_option(
    "--spec", ba->spec, "Design-space spec JSON (default: found from the histogram)");
  build->add_option("--count", ba->o.count, "Training exemplars (default 2000)")
    ->check(CLI::Range(8, 10000000));
  build->add_option("--heldout", ba->o.heldout, "Held-out exemplars (default 200)")
    ->check(CLI::Range(1, 100000));
  build->add_option("--size", ba->o.size, "Image side (default 64)")->check(CLI::Range(16, 512));
  build->add_option("--minutes", ba->o.minutes, "Training budget (default 5)")
    ->check(CLI::PositiveNumber);
  build
    ->add_option("--iterations", ba->o.iterations,
      "Training iterations (default 0: the budget decides; the image loss's rays are then "
      "adapted to what a step costs, while a fixed count keeps 512 and repeats to the byte)")
    ->check(CLI::NonNegativeNumber);
  build->add_option("--outline", ba->o.outlineCount, "Outline designs (default 10000)")
    ->check(CLI::Range(3, 10000000));
  build->add_option("--width", ba->o.width, "Analyzer width (default 16)")
    ->check(CLI::Range(2, 256));
  build
    ->add_option("--other-view", ba->o.otherViewFraction,
      "Share of the analyzer's training images taken from each exemplar's other view (its "
      "ground truth over black or white) instead of its image at V_exp (default 0.5)")
    ->check(CLI::Range(0.0, 1.0));
  build
    ->add_option("--image-sample-scale", ba->o.imageSampleScale,
      "The training image loss's sample distance over ParaView's (opacity corrected; default 1)")
    ->check(CLI::Range(0.25, 8.0));
  build->add_option("--seed", ba->o.seed, "Seed (default 1)");
  build->add_option("--threads", ba->o.threads, "Threads (default 0: all cores)");
  build
    ->add_option("--budget", ba->o.budgetMinutes,
      "Minutes for the whole build, outline included (>= 1; sizes exemplars, training and "
      "outline from a short timed probe; default 0: the sizes given)")
    ->check(CLI::Range(1.0, 100000.0));
  build
    ->add_option("--design-voxels", ba->o.maxDesignVoxels,
      "Volumes above this many voxels are downsampled (box average) for the design space: "
      "cheaper exemplars and training steps, a coarser volume (default 16 Mi = 16777216; e.g. "
      "2097152 = 128^3; see Documentation/DesignSpaces.md)")
    ->check(CLI::Range(std::int64_t(4096), std::int64_t(1) << 40));
  build->add_flag("--plan", ba->planOnly,
    "With --budget: print the plan (stages, estimated minutes, disk use) and stop");
  build->add_flag("--overwrite", ba->o.overwrite, "Replace a bundle already in --out");
  build->add_flag("--quiet", ba->quiet, "Do not print progress");
  return { build, [ba] { return runBuild(*ba); } };
}
#endif
