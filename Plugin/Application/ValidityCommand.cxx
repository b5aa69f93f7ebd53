// ValidityCommand.cxx: `ddg validity` — design-space validity.
#ifdef DDG_WITH_TORCH
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Gallery/OutlineCheck.h"
#include "Image/Image.h"
#include "Neural/DesignValidity.h"
#include "Neural/NeuralDesignModel.h"
#include "Render/View.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct ValidityArgs
{
  std::string model, volume, view, out, outlineSheet;
  int count = 6, size = 128, outlineCount = 200;
  std::uint64_t seed = 1;
};

int runValidity(const ValidityArgs& a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume);
  auto model = ddg::NeuralDesignModel::loadBundle(a.model, ddg::volumeFingerprint(volume));
  const ddg::View view =
    a.view.empty() ? ddg::defaultView(volume, a.size, a.size) : ddg::readView(a.view);
  const auto r = ddg::designSpaceValidity(model, volume, view, a.count, a.seed);
  for (size_t i = 0; i < r.rows.size(); ++i)
  {
    const auto& row = r.rows[i];
    std::printf("random latent %zu: nearest by cosine #%d (%.3f, PSNR %.2f dB), by distance #%d "
                "(%.3f, PSNR %.2f dB)\n",
      i, row.nearestCosine, row.cosine, row.psnrCosine, row.nearestEuclidean, row.euclidean,
      row.psnrEuclidean);
  }
  std::printf("mean PSNR of a random latent's design against its nearest training design: "
              "%.2f dB (cosine), %.2f dB (Euclidean)\n",
    r.meanPsnrCosine, r.meanPsnrEuclidean);
  ddg::writeImage(r.sheet, a.out);
  std::printf(
    "wrote %s (rows: random latent | nearest by cosine | nearest by distance)\n", a.out.c_str());
  if (a.outlineCount > 0 && std::filesystem::exists(ddg::outlineFile(a.model)))
  {
    ddg::DesignGallery gallery(model, volume, ddg::readLatentSet(ddg::outlineFile(a.model)));
    const auto check = ddg::checkOutline(gallery, a.outlineCount, a.seed);
    std::printf("outline: %zu of %d designs checked at azimuth 0/120/240, elevation 20: %d empty, "
                "%d flat box (%.1f %% junk); %d give the volume's boundary faces a mean opacity "
                "above 0.01\n",
      check.rows.size(), gallery.outline().count(), check.empty, check.flatBox,
      100 * check.junkFraction(), check.hazyFaces);
    if (!a.outlineSheet.empty())
    {
      ddg::writeImage(check.sheet, a.outlineSheet);
      std::printf(
        "wrote %s (the checked designs at azimuth 0; framed blue: empty, red: flat box)\n",
        a.outlineSheet.c_str());
    }
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addValidityCommand(CLI::App& app)
{
  auto vda = std::make_shared<ValidityArgs>();
  auto* validity = app.add_subcommand("validity",
    "Design-space validity (paper 7.2.2): random latents rendered by the model next to the "
    "nearest training designs (cosine and Euclidean), as a PNG sheet with PSNRs.");
  validity->add_option("--model", vda->model, "Model bundle directory")->required();
  validity->add_option("--volume", vda->volume, "The bundle's volume")->required();
  validity->add_option("--out", vda->out, "Output sheet (PNG)")->required();
  validity->add_option("--count", vda->count, "Random latents (rows; default 6)")
    ->check(CLI::Range(1, 1000));
  validity->add_option("--view", vda->view, "View JSON (default: the volume's default view)");
  validity->add_option("--size", vda->size, "Image size without --view (default 128)")
    ->check(CLI::Range(8, 4096));
  validity->add_option("--seed", vda->seed, "Seed of the random latents (default 1)");
  validity
    ->add_option("--outline-count", vda->outlineCount,
      "Outline designs to check for structure (default 200; 0: none): each design's TF at "
      "azimuth 0/120/240, elevation 20; empty (under 1 % of the volume's box shows alpha >= 0.03) "
      "at all three, or a flat box (90 % of the box and 80 % of its outline shown) at two")
    ->check(CLI::Range(0, 1000000));
  validity->add_option("--outline-sheet", vda->outlineSheet,
    "Also write the checked outline designs as a PNG sheet (junk framed)");
  return { validity, [vda] { return runValidity(*vda); } };
}
#endif
