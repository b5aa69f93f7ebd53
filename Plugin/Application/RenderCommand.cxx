// RenderCommand.cxx: `ddg render` — render a volume with a TF file and a view file to an image.
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Image/Image.h"
#include "Render/RayCaster.h"
#include "Render/View.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct RenderArgs
{
  std::string volume, tf, view, out, array;
  bool alpha = false, jitter = false, noSkip = false;
  double sampleDistance = 0, sampleOffset = 0.5;
  int threads = 0;
};

int runRender(const RenderArgs& a)
{
  const auto t0 = Clock::now();
  const ddg::View view = ddg::readView(a.view);
  const ddg::TransferFunctionFile tf = ddg::readTransferFunctionFile(a.tf);
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  if (volume.nonFiniteCount() > 0)
  {
    std::cerr << "ddg render: warning: " << volume.nonFiniteCount()
              << " NaN/infinite voxels were set to the minimum value " << volume.range()[0] << "\n";
  }
  const ddg::RayCaster caster(volume);
  const double tLoad = msSince(t0);
  ddg::RenderOptions opt;
  opt.jitter = a.jitter;
  opt.sampleDistance = a.sampleDistance;
  opt.sampleOffset = a.sampleOffset;
  opt.emptySpaceSkipping = !a.noSkip;
  opt.threads = a.threads;
  const auto t1 = Clock::now();
  const ddg::Image rgba = caster.render(tf, view, opt);
  const double tRender = msSince(t1);
  if (a.alpha)
  {
    ddg::writeImage(ddg::unpremultiplyAlpha(rgba), a.out); // PNG convention: straight alpha
  }
  else
  {
    ddg::writeImage(ddg::compositeOverBackground(rgba, view.background), a.out);
  }
  std::printf("wrote %s (%d x %d) load %.0f ms, render %.1f ms\n", a.out.c_str(), view.width,
    view.height, tLoad, tRender);
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addRenderCommand(CLI::App& app)
{
  auto ra = std::make_shared<RenderArgs>();
  auto* render = app.add_subcommand("render",
    "Render a volume with a TF file and a view file to an image (as ParaView's Volume "
    "representation would).");
  render->add_option("--volume", ra->volume, "Volume file")->required();
  render
    ->add_option("--tf", ra->tf,
      "Transfer function file (ParaView preset JSON, DDG 2D JSON, or ParaView's 2D boxes as\n"
      "`ddg export --format paraview-2d` writes them)")
    ->required();
  render
    ->add_option(
      "--view", ra->view, "View JSON (camera, size, background, opacity_unit_distance, lighting)")
    ->required();
  render->add_option("--out", ra->out, "Output image (.png, .jpg, .tif, .exr, ...)")->required();
  render->add_option("--array", ra->array, "Point array to render (default: the active scalars)");
  render->add_flag(
    "--alpha", ra->alpha, "Write RGBA with straight alpha instead of RGB over the background");
  render->add_flag("--jitter", ra->jitter,
    "Jitter the first sample per pixel as ParaView does (its 64x64 blue-noise tile; default: off)");
  render
    ->add_option("--sample-distance", ra->sampleDistance,
      "Sample distance in world units (default 0: ParaView's rule, mean spacing / 2)")
    ->check(CLI::NonNegativeNumber);
  render
    ->add_option("--sample-offset", ra->sampleOffset,
      "First sample at entry + offset * step when not jittering (default 0.5)")
    ->check(CLI::Range(0.0, 1.0));
  render->add_flag("--no-skip", ra->noSkip, "Disable empty-space skipping (same image, slower)");
  render->add_option("--threads", ra->threads, "Worker threads (default 0: all cores)")
    ->check(CLI::Range(0, 256));
  return { render, [ra] { return runRender(*ra); } };
}
