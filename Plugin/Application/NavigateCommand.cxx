// NavigateCommand.cxx: `ddg navigate` — navigate between 2-4 designs.
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

struct NavigateArgs
{
  std::string model, volume, out, view, window, lock, lockFrom;
  std::vector<std::string> designs;
  int rows = 5, cols = 5, thumb = 96;
};

int runNavigate(const NavigateArgs& a)
{
  const auto session = openBundle(a.model, a.volume);
  ddg::DesignGallery& g = session->gallery();
  std::vector<ddg::Latent> anchors;
  for (const auto& d : a.designs)
    anchors.push_back(resolveDesign(g, d));
  ddg::NavigationWindow w;
  if (!a.window.empty())
  {
    const auto v = parseNumbers(a.window, 4, "--window");
    w = { v[0], v[1], v[2], v[3] };
  }
  const int rows = anchors.size() == 2 ? 1 : a.rows;
  const auto cells = ddg::navigationGrid(anchors, rows, a.cols, w);
  const auto lock = makeLock(g, a.lock, a.lockFrom);
  const auto view =
    thumbnailView(session->volume(), session->gallery().model().spec(), a.view, a.thumb);
  const auto t0 = Clock::now();
  std::vector<ddg::Image> images;
  for (const auto& c : cells)
    images.push_back(c.latent.empty()
        ? ddg::Image(view.width, view.height, 3, 1.0f)
        : ddg::compositeOverBackground(g.render(c.latent, view, lock.get()), view.background));
  ddg::writeImage(ddg::tileImages(images, a.cols), a.out);
  std::printf("navigation grid %d x %d between %zu designs, window u [%g, %g] v [%g, %g]%s: %zu "
              "renders in %.0f ms; wrote %s\n",
    rows, a.cols, anchors.size(), w.u0, w.u1, w.v0, w.v1, lock ? " (feature lock)" : "",
    cells.size(), msSince(t0), a.out.c_str());
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addNavigateCommand(CLI::App& app)
{
  auto na = std::make_shared<NavigateArgs>();
  auto* navigate = app.add_subcommand("navigate",
    "Navigate between 2-4 designs (paper 1): a grid of the sub-space they span (2: a line, 3: "
    "barycentric triangle, 4: bilinear), each cell rendered by the model; --window pans and "
    "zooms inside it. Designs: row:N (outline row), image:PATH, latent:PATH, history:PATH.");
  navigate->add_option("--model", na->model, "Model bundle directory (with outline.bin)")
    ->required();
  navigate->add_option("--volume", na->volume, "The bundle's volume")->required();
  navigate->add_option("--design", na->designs, "A design (2 to 4 times)")
    ->required()
    ->expected(2, 4);
  navigate->add_option("--out", na->out, "Output grid (PNG)")->required();
  navigate->add_option("--rows", na->rows, "Grid rows (default 5; 1 for two designs)")
    ->check(CLI::Range(1, 64));
  navigate->add_option("--cols", na->cols, "Grid columns (default 5)")->check(CLI::Range(1, 64));
  navigate->add_option("--window", na->window, "u0,v0,u1,v1 shown (default 0,0,1,1)");
  navigate->add_option("--view", na->view, "View JSON (default: the volume's default view)");
  navigate->add_option("--thumb", na->thumb, "Cell side in pixels (default 96)")
    ->check(CLI::Range(8, 512));
  navigate->add_option(
    "--lock", na->lock, "Feature lock: regions (e.g. 0,2) kept from --lock-from");
  navigate->add_option("--lock-from", na->lockFrom, "The design the locked regions come from");
  return { navigate, [na] { return runNavigate(*na); } };
}
#endif
