// CompareCommand.cxx: `ddg compare` — print PSNR.
#include "CommandSupport.h"

#include "Common/Error.h"
#include "Image/Image.h"
#include "Image/ImageMetrics.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct CompareArgs
{
  std::string a, b;
  double minPsnr = -1;
  bool json = false;
};

int runCompare(const CompareArgs& c)
{
  const ddg::Image a = ddg::readImage(c.a);
  const ddg::Image b = ddg::readImage(c.b);
  const double p = ddg::psnr(a, b);
  const double s = ddg::ssim(a, b);
  const double emd = ddg::colorHistogramEMD(a, b);
  if (c.json)
  {
    std::printf(
      "{\"psnr\": %.4f, \"ssim\": %.6f, \"emd\": %.6f}\n", std::isinf(p) ? 999.0 : p, s, emd);
  }
  else
  {
    std::printf("PSNR %.2f dB  SSIM %.5f  EMD %.4f\n", std::isinf(p) ? 999.0 : p, s, emd);
  }
  if (c.minPsnr >= 0 && p < c.minPsnr)
  {
    std::fprintf(stderr, "ddg compare: PSNR %.2f dB is below the required %.2f dB\n", p, c.minPsnr);
    return 3;
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addCompareCommand(CLI::App& app)
{
  auto ca = std::make_shared<CompareArgs>();
  auto* compare = app.add_subcommand("compare",
    "Print PSNR (dB), SSIM and colour-histogram EMD (CIELAB, Berger et al.) of two images of the "
    "same size.");
  compare->add_option("a", ca->a, "First image")->required();
  compare->add_option("b", ca->b, "Second image")->required();
  compare->add_option("--min-psnr", ca->minPsnr, "Exit with status 3 when PSNR is below this (dB)");
  compare->add_flag("--json", ca->json, "Print {\"psnr\": ..., \"ssim\": ..., \"emd\": ...}");
  return { compare, [ca] { return runCompare(*ca); } };
}
