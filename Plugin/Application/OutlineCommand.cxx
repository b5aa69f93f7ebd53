// OutlineCommand.cxx: `ddg outline` — build a bundle's design-space outline.
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
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct OutlineArgs
{
  std::string model, volume, out;
  int count = 50000, threads = 0;
  std::uint64_t seed = 1, firstIndex = 0;
  bool quiet = false, screen = false;
};

int runOutline(const OutlineArgs& a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume);
  const auto model = ddg::NeuralDesignModel::loadBundle(a.model, ddg::volumeFingerprint(volume));
  const auto t0 = Clock::now();
  int lastPercent = -1;
  const auto set = ddg::buildOutlineLatents(
    model, volume, a.count, a.seed, a.firstIndex, a.threads,
    [&](double f)
    {
      const int p = static_cast<int>(f * 100);
      if (!a.quiet && p / 10 != lastPercent / 10)
      {
        std::printf("outline: %3d %%  %.0f s\n", p, msSince(t0) / 1000);
        std::fflush(stdout);
      }
      lastPercent = p;
      return true;
    },
    a.screen);
  const double seconds = msSince(t0) / 1000;
  const std::string out = a.out.empty() ? ddg::outlineFile(a.model) : a.out;
  ddg::writeLatentSet(set, out);
  const auto t1 = Clock::now();
  const ddg::DesignOutline outline(set);
  std::printf("outline: %d designs in %.1f s (%.0f designs/s); PCA %.0f ms, the plane explains "
              "%.1f %% + %.1f %% of the variance; wrote %s\n",
    set.count(), seconds, set.count() / seconds, msSince(t1), 100 * outline.explainedVariance(0),
    100 * outline.explainedVariance(1), out.c_str());
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addOutlineCommand(CLI::App& app)
{
  auto oa = std::make_shared<OutlineArgs>();
  auto* outline = app.add_subcommand("outline",
    "Build a bundle's design-space outline (paper 5.1): latents of many generated designs "
    "(each rendered at its own view and analyzed), stored as outline.bin in the bundle.");
  outline->add_option("--model", oa->model, "Model bundle directory")->required();
  outline->add_option("--volume", oa->volume, "The bundle's volume")->required();
  outline->add_option("--count", oa->count, "Designs (default 50000)")
    ->check(CLI::Range(3, 10000000));
  outline->add_option("--seed", oa->seed,
    "Design-space seed (default 1: designs 0..N-1 include the training exemplars)");
  outline->add_option("--first-index", oa->firstIndex, "Index of the first design (default 0)");
  outline->add_option("--threads", oa->threads, "Render threads (default 0: all cores)");
  outline->add_option("--out", oa->out, "Output file (default MODEL/outline.bin)");
  outline->add_flag("--screen", oa->screen,
    "Pass over designs whose image is empty or a flat box (as generate --screen; ddg build "
    "screens)");
  outline->add_flag("--quiet", oa->quiet, "Do not print progress");
  return { outline, [oa] { return runOutline(*oa); } };
}
#endif
