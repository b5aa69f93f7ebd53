// TestViewEstimation.cxx: --estimate-view finds a camera it was not given.
//
// Compared: the Tooth rendered (RayCaster, shipped preset) from a view orbited by azimuth 75°,
// elevation 20° from Data/Views/tooth_oblique.json; estimateView starts from the unrotated view
// and must return angles within kAngleTol degrees and zoom within kZoomTol of the truth; the TF
// reconstructed at the estimate must render the target at >= kPsnrDb.
#include "DDGVolumeAdaptor.h"

#include "Image/ImageMetrics.h"
#include "Reconstruct/ViewEstimation.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace ddg;

namespace
{
constexpr double kAngleTol = 10.0;
constexpr double kZoomTol = 0.1;
constexpr double kPsnrDb = 27.0;
} // namespace

TEST(ViewEstimation, RecoversAnOrbitedToothView)
{
  const std::string data = DDG_DATA_DIR;
  const Volume vol = readVolumeFile(data + "/Volumes/tooth.vti");
  const DifferentiableRenderer renderer(vol);
  const View base = readView(data + "/Views/tooth_oblique.json");
  const View truthView = orbitView(base, 75, 20, 1.0);
  const auto table = renderer.caster().paraviewTable(
    readPreset(data + "/TransferFunctions/tooth_dentin_enamel.json"));
  const Image truth =
    compositeOverBackground(renderer.caster().render(table, truthView), base.background);
  ViewEstimationReport report;
  const View estimate = estimateView(renderer, { truth, base, {} }, {}, &report);
  std::printf(
    "estimated azimuth %.1f (75), elevation %.1f (20), zoom %.3f (1) with %d fits in %.1f s\n",
    report.azimuth, report.elevation, report.zoom, report.evaluations, report.seconds);
  EXPECT_NEAR(report.azimuth, 75.0, kAngleTol);
  EXPECT_NEAR(report.elevation, 20.0, kAngleTol);
  EXPECT_NEAR(report.zoom, 1.0, kZoomTol);
  const auto result = reconstructTransferFunction(renderer, { { truth, estimate, {} } }, {});
  const double db = psnr(
    compositeOverBackground(renderResult(renderer.caster(), result, estimate), base.background),
    truth);
  std::printf("PSNR at the estimated view %.2f dB\n", db);
  EXPECT_GE(db, kPsnrDb);
}
