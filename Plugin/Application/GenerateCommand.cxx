// GenerateCommand.cxx: `ddg generate` — render design exemplars.
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/Export.h"
#include "Image/Image.h"
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

struct GenerateArgs
{
  std::string volume, spec, out, array, preview, tfs;
  int count = 1000, size = 64, threads = 0, shardSize = 256;
  std::uint64_t seed = 1, firstIndex = 0;
  bool quiet = false, screen = false, noViewport = false;
};

/// Writes every exemplar's TF into `dir` as the file a user opens in ParaView (a 1D preset, the
/// DDG 2D JSON in 2D), named by the exemplar's index; returns how many.
int writeExemplarTransferFunctions(const ddg::Volume& volume, const std::string& datasetDir,
  std::uint64_t seed, const std::string& dir)
{
  const ddg::ExemplarDataset data(datasetDir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw ddg::Error("cannot create the TF folder '" + dir + "': " + ec.message());
  const int dimensions = data.spec().dimensions;
  const std::array<double, 2> gradientRange =
    dimensions == 2 ? volume.gradientMagnitudeRange() : std::array<double, 2>{ 0, 1 };
  for (const ddg::Exemplar& e : data.exemplars())
  {
    const std::string name = "exemplar_" + std::to_string(ddg::exemplarIndex(e, seed)) + ".json";
    const std::string path = (std::filesystem::path(dir) / name).string();
    ddg::TransferFunctionFile tf =
      ddg::primitivesToTransferFunction(e.primitives, dimensions, volume.range(), gradientRange);
    tf = ddg::renamed(tf, ddg::exportName(data.volumeFile(), "exemplar", path));
    if (tf.is2D)
      ddg::writeTransferFunction2D(tf.tf2D, path);
    else
      ddg::writePreset(tf.tf1D, path);
  }
  return static_cast<int>(data.exemplars().size());
}

int runGenerate(const GenerateArgs& a)
{
  const ddg::DesignSpaceSpec spec =
    a.spec.empty() ? ddg::DesignSpaceSpec{} : ddg::readDesignSpaceSpec(a.spec);
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  ddg::GenerateOptions opt;
  opt.count = a.count;
  opt.size = a.size;
  opt.seed = a.seed;
  opt.firstIndex = a.firstIndex;
  opt.threads = a.threads;
  opt.shardSize = a.shardSize;
  opt.screen = a.screen;
  opt.viewport = !a.noViewport;
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(a.volume, ec);
  opt.volumeFile = ec ? a.volume : absolute.lexically_normal().string();
  int lastPercent = -1;
  const auto report = ddg::generateExemplars(volume, spec, a.out, opt,
    [&](double f)
    {
      const int percent = static_cast<int>(100 * f);
      if (!a.quiet && percent / 10 != lastPercent / 10)
      {
        std::printf("generated %3d %%\n", percent);
        std::fflush(stdout);
      }
      lastPercent = percent;
      return true;
    });
  for (const auto& r : report.regions)
  {
    if (r.twoD())
      std::printf("region value [%g, %g] peak %g, gradient magnitude [%g, %g] peak %g (%.1f %% of "
                  "non-air voxels)\n",
        r.lo, r.hi, r.peak, r.gradientLo, r.gradientHi, r.gradientPeak, 100 * r.mass);
    else
      std::printf(
        "region [%g, %g] peak %g (%.1f %% of non-air voxels)\n", r.lo, r.hi, r.peak, 100 * r.mass);
  }
  if (a.screen)
    std::printf("screen: %d candidates, %d empty and %d flat-box designs passed over, %d feature "
                "region(s) left out%s\n",
      report.candidates, report.empty, report.flatBox, report.regionsLeftOut,
      report.screenExhausted ? "; candidates ran out, the last exemplars kept as drawn" : "");
  std::printf("wrote %d exemplars of %d x %d to %s in %.2f s (%.1f exemplars/s)\n", report.count,
    a.size, a.size, a.out.c_str(), report.seconds, report.count / report.seconds);
  if (!a.tfs.empty())
    std::printf("wrote %d exemplar TFs to %s\n",
      writeExemplarTransferFunctions(volume, a.out, a.seed, a.tfs), a.tfs.c_str());
  if (!a.preview.empty())
  {
    // contact sheet: up to 8 rows of (image at V_exp | viewport | ground truth over grey)
    const ddg::ExemplarDataset data(a.out);
    std::vector<ddg::Image> cells;
    for (int r = 0; r < std::min(8, data.count()); ++r)
    {
      const auto im = data.images(r);
      cells.push_back(im.rgbExp);
      cells.push_back(ddg::compositeOverBackground(im.viewport, { 0.5, 0.5, 0.5 }));
      cells.push_back(ddg::compositeOverBackground(im.truth, { 0.5, 0.5, 0.5 }));
    }
    const ddg::Image sheet = ddg::tileImages(cells, 3);
    ddg::writeImage(sheet, a.preview);
    std::printf("wrote preview %s\n", a.preview.c_str());
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addGenerateCommand(CLI::App& app)
{
  auto ga = std::make_shared<GenerateArgs>();
  auto* generate = app.add_subcommand("generate",
    "Render design exemplars (paper 4.3.1): random Gaussian-primitive TFs over the volume's "
    "feature regions, "
    "each at a random view on black or white, with a viewport image and the ground truth at "
    "another view.");
  generate->add_option("--volume", ga->volume, "Volume file")->required();
  generate->add_option(
    "--spec", ga->spec, "Design space spec JSON (default: the documented defaults)");
  generate->add_option("--count", ga->count, "Exemplars (default 1000)")
    ->check(CLI::Range(1, 10000000));
  generate->add_option("--size", ga->size, "Image side in pixels (default 64)")
    ->check(CLI::Range(8, 1024));
  generate->add_option("--out", ga->out, "Output directory (shards + dataset.json)")->required();
  generate->add_option(
    "--seed", ga->seed, "Seed (default 1): the dataset is a function of volume, spec and seed");
  generate->add_option("--first-index", ga->firstIndex,
    "Index of the first exemplar (default 0; use another range for held-out sets)");
  generate->add_option("--shard-size", ga->shardSize, "Exemplars per shard (default 256)")
    ->check(CLI::Range(1, 1000000));
  generate->add_option("--threads", ga->threads, "Worker threads (default 0: all cores)")
    ->check(CLI::Range(0, 256));
  generate->add_flag("--screen", ga->screen,
    "Designs that show structure only: leave out feature regions that paint the volume's box "
    "or show nothing, and pass over designs whose image is empty or a flat box (the next index "
    "is taken; see Documentation/DesignSpaces.md, 'Designs that show structure')");
  generate->add_option(
    "--preview", ga->preview, "Also write a contact sheet of the first exemplars");
  generate->add_option("--tfs", ga->tfs,
    "Also write every exemplar's TF into this folder as exemplar_<index>.json (a ParaView "
    "preset; a 2D spec: the DDG 2D TF JSON), to open or render it elsewhere");
  generate->add_option("--array", ga->array, "Point array (default: the active scalars)");
  generate->add_flag("--no-viewport", ga->noViewport,
    "Leave out the U-Net's viewport image (the decoder does not read it): two renders per "
    "exemplar instead of three");
  generate->add_flag("--quiet", ga->quiet, "Do not print progress");
  return { generate, [ga] { return runGenerate(*ga); } };
}
