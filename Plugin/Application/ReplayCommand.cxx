// ReplayCommand.cxx: `ddg replay` — replay a history file.
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

struct ReplayArgs
{
  std::string model, volume, history, view, outTF, outDesign, outLatent, format = "paraview";
};

int runReplay(const ReplayArgs& a)
{
  const auto session = openBundle(a.model, a.volume);
  ddg::DesignGallery& g = session->gallery();
  const auto history = ddg::DesignHistory::read(a.history);
  std::vector<float> z;
  for (size_t i = 0; i < history.steps.size(); ++i)
  {
    z = ddg::applyHistoryStep(g, history.steps[i], z);
    const auto p = g.outline().project(z.data());
    std::printf("step %zu (%s): outline position (%.4f, %.4f)\n", i + 1,
      history.steps[i].action.c_str(), p[0], p[1]);
  }
  const ddg::View view = a.view.empty()
    ? ddg::designDefaultView(session->volume(), session->gallery().model().spec(), 256)
    : ddg::readView(a.view);
  if (!a.outLatent.empty())
    ddg::writeLatentFile(z, a.outLatent);
  if (!a.outDesign.empty())
    ddg::writeImage(ddg::compositeOverBackground(g.render(z, view), view.background), a.outDesign);
  if (!a.outTF.empty())
  {
    const auto& last = history.steps.back();
    if (last.action == "match")
    {
      // the design matched to the picture again at its camera (or the TF it recorded)
      bool rematched = false;
      double fit = 0;
      const auto tf = ddg::replayMatch(g, z, last, &rematched, &fit);
      if (rematched)
        std::printf("match: the design matched to %s again at its camera (fit %.2f dB)\n",
          last.image.c_str(), fit);
      else
        std::printf("match: the picture %s cannot be read; the TF the history recorded\n",
          last.image.empty() ? "(unnamed)" : last.image.c_str());
      ddg::exportTransferFunction(ddg::renamed(tf, ddg::exportName(a.volume, "match", a.outTF)),
        a.outTF, a.format, g.caster(), ddg::parseView(last.viewJson, "the match's view"));
    }
    else
    {
      ddg::exportTransferFunction(
        ddg::renamed(g.explicitTransferFunction(z, view),
          ddg::exportName(a.volume, ddg::designOrigin(last.action), a.outTF)),
        a.outTF, a.format, g.caster(), view);
    }
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addReplayCommand(CLI::App& app)
{
  auto pa = std::make_shared<ReplayArgs>();
  auto* replay = app.add_subcommand("replay",
    "Replay a history file (query -> picks -> edits -> TF; written by query/edit --history): "
    "prints each step's outline position and writes the design it ends on.");
  replay->add_option("--model", pa->model, "Model bundle directory (with outline.bin)")->required();
  replay->add_option("--volume", pa->volume, "The bundle's volume")->required();
  replay->add_option("--history", pa->history, "History file")->required();
  replay->add_option(
    "--view", pa->view, "View JSON of the outputs (default: the volume's default view)");
  replay->add_option("--out-tf", pa->outTF,
    "Write the final design's explicit TF (after a match step: the design matched to the "
    "step's picture again at its camera, or the TF it recorded when the picture is unreadable)");
  replay->add_option("--format", pa->format, "TF file format: paraview (default) or slicer")
    ->check(CLI::IsMember({ "paraview", "slicer" }));
  replay->add_option("--out-design", pa->outDesign, "Write the final design's render (PNG)");
  replay->add_option("--out-latent", pa->outLatent, "Write the final latent (JSON)");
  return { replay, [pa] { return runReplay(*pa); } };
}
#endif
