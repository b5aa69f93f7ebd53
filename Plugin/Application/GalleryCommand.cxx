// GalleryCommand.cxx: `ddg gallery` — write the outline sheet.
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

struct GalleryArgs
{
  std::string model, volume, out, view, box, state, saveState, list, lock, lockFrom;
  int count = 64, thumb = 96, side = 1024;
  std::uint64_t seed = 1;
};

int runGallery(const GalleryArgs& a)
{
  const auto session = openBundle(a.model, a.volume);
  ddg::DesignGallery& g = session->gallery();
  ddg::OutlineViewState state;
  if (!a.state.empty())
  {
    std::ifstream in(a.state);
    if (!in)
      throw ddg::Error("cannot open the view state " + a.state);
    std::stringstream text;
    text << in.rdbuf();
    state = ddg::OutlineViewState::fromJson(text.str());
  }
  else
  {
    state.boxes = { g.outline().bounds() };
    state.count = a.count;
    state.seed = a.seed;
  }
  if (!a.box.empty())
    state.drillIn(parseBox(a.box));
  const auto view =
    thumbnailView(session->volume(), session->gallery().model().spec(), a.view, a.thumb);
  const auto t0 = Clock::now();
  const auto rows = ddg::selectThumbnails(g.outline(), state.current(), state.count, state.seed);
  const double selectMs = msSince(t0);
  const auto t1 = Clock::now();
  const auto lock = makeLock(g, a.lock, a.lockFrom);
  const ddg::Image sheet = g.sheet(state, view, a.side, lock.get());
  const double sheetMs = msSince(t1);
  ddg::writeImage(sheet, a.out);
  const auto& b = state.current();
  std::printf("outline of %d designs, box [%.3g, %.3g] x [%.3g, %.3g] holds %zu; %zu thumbnails "
              "(dispersion %.3f of the box)\n",
    g.outline().count(), b.x0, b.x1, b.y0, b.y1, g.outline().inside(b).size(), rows.size(),
    ddg::dispersion(g.outline(), b, rows));
  std::printf("times: load %.0f ms, PCA + layout %.0f ms, thumbnail choice %.1f ms, renders + "
              "sheet %.0f ms; wrote %s\n",
    session->outlineReadMs(), session->outlinePcaMs(), selectMs, sheetMs, a.out.c_str());
  if (!a.saveState.empty())
    ddg::writeFileAtomic(a.saveState, state.toJson(), "outline view state");
  if (!a.list.empty())
  {
    std::string csv = "row,design_index,x,y\n";
    char line[128];
    for (int r : rows)
    {
      const auto p = g.outline().point(r);
      std::snprintf(line, sizeof(line), "%d,%llu,%.5f,%.5f\n", r,
        static_cast<unsigned long long>(g.outline().latents().indices[r]), p[0], p[1]);
      csv += line;
    }
    ddg::writeFileAtomic(a.list, csv, "thumbnail list");
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addGalleryCommand(CLI::App& app)
{
  auto ga = std::make_shared<GalleryArgs>();
  auto* gallery = app.add_subcommand("gallery",
    "Write the outline sheet (paper 5.1): every design of the bundle's outline as a dot on the "
    "PCA plane and K thumbnails chosen to cover the box shown (farthest-point sampling), "
    "rendered by the model at the view.");
  gallery->add_option("--model", ga->model, "Model bundle directory (with outline.bin)")
    ->required();
  gallery->add_option("--volume", ga->volume, "The bundle's volume")->required();
  gallery->add_option("--out", ga->out, "Output sheet (PNG)")->required();
  gallery->add_option(
    "--view", ga->view, "View JSON of the thumbnails (default: the volume's default view)");
  gallery->add_option("--box", ga->box, "Drill into x0,y0,x1,y1 on the PCA plane");
  gallery->add_option("--count", ga->count, "Thumbnails K (default 64)")
    ->check(CLI::Range(1, 1024));
  gallery->add_option(
    "--seed", ga->seed, "Thumbnail sampling seed; another seed resamples (default 1)");
  gallery->add_option("--thumb", ga->thumb, "Thumbnail side in pixels (default 96)")
    ->check(CLI::Range(8, 512));
  gallery->add_option("--side", ga->side, "Sheet side in pixels (default 1024)")
    ->check(CLI::Range(64, 8192));
  gallery->add_option("--state", ga->state,
    "Start from a saved view state JSON ({\"boxes\": [[x0,y0,x1,y1], ...], \"count\", \"seed\"})");
  gallery->add_option("--save-state", ga->saveState, "Write the view state JSON shown");
  gallery->add_option("--lock", ga->lock,
    "Feature lock: regions (e.g. 0,2) kept from --lock-from in every thumbnail");
  gallery->add_option("--lock-from", ga->lockFrom, "The design the locked regions come from");
  gallery->add_option(
    "--list", ga->list, "Write the thumbnails' rows, design indices and positions (CSV)");
  return { gallery, [ga] { return runGallery(*ga); } };
}
#endif
