// QueryCommand.cxx: `ddg query` — query the design space with an image.
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

struct QueryArgs
{
  std::string model, volume, image, view, outPreview, outTF, outInput, format = "paraview", history;
  std::string kindNetwork;
  int neighbours = 5;
  bool noKey = false;
};

int runQuery(const QueryArgs& a)
{
  const auto t0 = Clock::now();
  const std::string kind = kindNetworkOption(a.kindNetwork); // a bad one fails first
  const auto session = openBundle(a.model, a.volume);
  ddg::DesignGallery& g = session->gallery();
  if (a.noKey)
    g.setQueryKey({});
  const bool keyed = !g.outline().queryKey().empty();
  const ddg::View view = ddg::readView(a.view);
  // read as the query reads it (at most kQueryPictureSide a side: an 8K picture is not held whole)
  const ddg::Image image = ddg::readShrunkPicture(a.image, ddg::kQueryPictureSide);
  const double loadMs = msSince(t0);
  const auto t1 = Clock::now();
  const auto r = g.query(image, view, a.neighbours);
  const double queryMs = msSince(t1);
  std::printf(
    "query %s: outline position (%.4f, %.4f)\n", a.image.c_str(), r.position[0], r.position[1]);
  for (size_t i = 0; i < r.neighbours.size(); ++i)
  {
    const auto& n = r.neighbours[i];
    std::printf("  neighbour %zu: design row %d (index %llu), %s distance %.4f\n", i + 1, n.row,
      static_cast<unsigned long long>(g.outline().latents().indices[n.row]),
      keyed ? "key" : "latent", n.distance);
  }
  if (!r.warning.empty())
    std::fprintf(stderr, "warning: %s\n", r.warning.c_str());
  std::printf("against the picture: %.2f dB (both framed on their content; the design %s, the "
              "better of unlit and lit)\n",
    r.picturePSNR, r.pictureLit ? "lit" : "unlit");
  printKindCheck(kind, 0, image, session->volume());
  if (!a.outInput.empty())
    ddg::writeImage(r.input, a.outInput);
  if (!a.history.empty())
    ddg::DesignReference::parse("image:" + a.image).history().write(a.history);
  if (!a.outPreview.empty())
    ddg::writeImage(ddg::compositeOverBackground(r.preview, view.background), a.outPreview);
  double tfMs = 0;
  if (!a.outTF.empty())
  {
    const auto t2 = Clock::now();
    const auto tf = g.explicitTransferFunction(r.latent, view);
    ddg::exportTransferFunction(ddg::renamed(tf, ddg::exportName(a.volume, "query", a.outTF)),
      a.outTF, a.format, g.caster(), view);
    tfMs = msSince(t2);
  }
  std::printf("times: load %.0f ms (PCA %.0f ms), query (analyzer, neighbours, %dx%d preview) "
              "%.1f ms, TF file %.0f ms; screenshot -> TF file %.0f ms\n",
    loadMs, session->outlinePcaMs(), view.width, view.height, queryMs, tfMs, queryMs + tfMs);
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addQueryCommand(CLI::App& app)
{
  auto qa = std::make_shared<QueryArgs>();
  auto* query = app.add_subcommand("query",
    "Query the design space with an image (paper 5.2): a screenshot of this volume, another "
    "volume or a figure; any size and aspect, RGB or RGBA; any uniform background (one neither "
    "black nor white, ParaView's palette say, becomes the nearer of the two with the overlays over "
    "it) or ParaView's gradient (framed around its content, see README); a screenshot of "
    "ParaView's whole window is read at its render view, a figure (a render pasted on a page "
    "of one colour) inside the pasted render. Prints its outline "
    "position, nearest designs and PSNR "
    "against the picture (both framed on their content; the better of the design unlit and lit), "
    "writes the model's render at the view and the explicit TF.");
  query->add_option("--model", qa->model, "Model bundle directory (with outline.bin)")->required();
  query->add_option("--volume", qa->volume, "The bundle's volume")->required();
  query->add_option("--image", qa->image, "Query image")->required();
  query->add_option("--view", qa->view, "View JSON of the preview and the TF (the current camera)")
    ->required();
  query->add_option(
    "--out-preview", qa->outPreview, "Write the preview (PNG, over the view's background)");
  query->add_option("--out-tf", qa->outTF,
    "Write the explicit TF (decoder: its output; U-Net: reconstructed from its render)");
  query->add_option("--format", qa->format, "TF file format: paraview (default) or slicer")
    ->check(CLI::IsMember({ "paraview", "slicer" }));
  query->add_option("--out-input", qa->outInput, "Write what the analyzer saw (PNG)");
  query->add_option("--history", qa->history,
    "Start a history file that replays this path (ddg edit --history, ddg replay)");
  query->add_option("--neighbours", qa->neighbours, "Nearest designs listed (default 5)")
    ->check(CLI::Range(0, 1000));
  query->add_option("--kind-network", qa->kindNetwork,
    "Check whether the picture shows a volume of this volume's kind with this kind network "
    "(e.g. Data/Models/kind; `ddg kind`; about 10 s; default and none: no check)");
  query->add_flag("--no-key", qa->noKey,
    "Find the nearest designs by the latents as they are, not by the bundle's query key "
    "(query_key.json); the distances printed say which (key or latent)");
  return { query, [qa] { return runQuery(*qa); } };
}
#endif
