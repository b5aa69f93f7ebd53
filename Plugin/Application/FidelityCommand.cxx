// FidelityCommand.cxx: `ddg fidelity` — how far a design's neural image is from what ParaView will
// show with its explicit TF: .
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

struct FidelityArgs
{
  std::string model, volume, design, view, outHeat, outPair;
};

int runFidelity(const FidelityArgs& a)
{
  const auto session = openBundle(a.model, a.volume);
  ddg::DesignGallery& g = session->gallery();
  const ddg::View view = ddg::readView(a.view);
  const auto f = g.fidelity(resolveDesign(g, a.design), view);
  std::printf(
    "fidelity of %s at %dx%d: neural image vs. ray cast of its exported TF: PSNR %.2f dB, "
    "SSIM %.4f, largest pixel error %.3f\n",
    a.design.c_str(), view.width, view.height, f.psnr, f.ssim, f.maxError);
  if (!a.outHeat.empty())
    ddg::writeImage(f.heat, a.outHeat);
  if (!a.outPair.empty())
    ddg::writeImage(ddg::tileImages({ f.neural, f.real, f.heat }, 3), a.outPair);
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addFidelityCommand(CLI::App& app)
{
  auto fa = std::make_shared<FidelityArgs>();
  auto* fidelity = app.add_subcommand("fidelity",
    "How far a design's neural image is from what ParaView will show with its explicit TF: "
    "PSNR, SSIM and a heat map (black: equal, white: 0.25 or more).");
  fidelity->add_option("--model", fa->model, "Model bundle directory (with outline.bin)")
    ->required();
  fidelity->add_option("--volume", fa->volume, "The bundle's volume")->required();
  fidelity
    ->add_option(
      "--design", fa->design, "The design: row:N, image:PATH, latent:PATH or history:PATH")
    ->required();
  fidelity->add_option("--view", fa->view, "View JSON")->required();
  fidelity->add_option("--out-heat", fa->outHeat, "Write the heat map (PNG)");
  fidelity->add_option(
    "--out-pair", fa->outPair, "Write neural | ray cast | heat map side by side (PNG)");
  return { fidelity, [fa] { return runFidelity(*fa); } };
}
#endif
