// TestReconstructionApi.cxx: the reconstruction API on a small synthetic volume — it lowers the
// loss and recovers the image (PSNR >= kRecoveredDb on the target view), reports progress,
// cancels, and refuses unusable targets with ddg::Error.
#include "Image/ImageMetrics.h"
#include "Reconstruct/Reconstruction.h"

#include "TestVolumes.h"
#include <gtest/gtest.h>

#include <cmath>

using namespace ddg;

namespace
{
constexpr double kRecoveredDb = 35.0;

Volume sphereVolume()
{
  return ddg::testing::gridVolume(24, ScalarType::UInt8,
    [](double r, int, int, int) { return std::floor(std::clamp(255.0 - 18.0 * r, 0.0, 255.0)); });
}
} // namespace

TEST(ReconstructionApi, RecoversProgressesCancelsAndRefuses)
{
  const Volume vol = sphereVolume();
  const DifferentiableRenderer renderer(vol);
  View view = defaultView(vol, 48, 40);
  TransferFunction1D tf;
  tf.color = { { 0, 0.2, 0.3, 0.9 }, { 120, 0.9, 0.6, 0.2 }, { 255, 1, 1, 1 } };
  tf.opacity = { { 0, 0 }, { 60, 0 }, { 130, 0.15 }, { 200, 0.7 }, { 255, 0.9 } };
  const Image truth = compositeOverBackground(
    renderer.caster().render(renderer.caster().paraviewTable(tf), view), view.background);

  int calls = 0;
  ReconstructionOptions opt;
  opt.raysPerIteration = 0;
  const auto result = reconstructTransferFunction(renderer, { { truth, view, {} } }, opt,
    [&](int, double, const ReconstructionResult*) { return ++calls > 0; });
  EXPECT_EQ(calls, result.iterations);
  EXPECT_LT(result.loss.back(), 0.1 * result.loss.front());
  const double db = psnr(
    compositeOverBackground(renderResult(renderer.caster(), result, view), view.background), truth);
  EXPECT_GE(db, kRecoveredDb);

  EXPECT_THROW(reconstructTransferFunction(renderer, { { truth, view, {} } }, opt,
                 [](int step, double, const ReconstructionResult*) { return step < 3; }),
    Cancelled);

  View other = view;
  other.width = 50;
  EXPECT_THROW(reconstructTransferFunction(renderer, { { truth, other, {} } }, opt), Error); // size
  EXPECT_THROW(
    reconstructTransferFunction(renderer, { { toChannels(truth, 1), view, {} } }, opt), Error);
  Image background(48, 40, 3);
  for (size_t i = 0; i < background.pixels.size(); ++i)
    background.pixels[i] = static_cast<float>(view.background[i % 3]);
  EXPECT_THROW(reconstructTransferFunction(renderer, { { background, view, {} } }, opt), Error);
  Image nanImage = truth;
  nanImage.pixels[5] = std::nanf("");
  EXPECT_THROW(reconstructTransferFunction(renderer, { { nanImage, view, {} } }, opt), Error);
  EXPECT_THROW(reconstructTransferFunction(renderer, {}, opt), Error);
}

// The parametric fit: a target made by 2 known Gaussian primitives is recovered by a fit of 3
// (PSNR >= kRecoveredDb); the fitted primitives are returned, valid and rasterize to the table.
TEST(ReconstructionApi, FitsGaussianPrimitives)
{
  const Volume vol = sphereVolume();
  const DifferentiableRenderer renderer(vol);
  View view = defaultView(vol, 48, 40);
  GaussianPrimitive inner, shell;
  inner.mean[0] = 220;
  inner.stddev[0] = 12;
  inner.rgb = { 0.9, 0.8, 0.3 };
  inner.opacity = 0.8;
  shell.mean[0] = 110;
  shell.stddev[0] = 10;
  shell.rgb = { 0.2, 0.4, 0.9 };
  shell.opacity = 0.15;
  const TransferTable1D table = rasterize1D({ inner, shell }, 0, 255, 256);
  const Image truth =
    compositeOverBackground(renderer.caster().render(table, view), view.background);

  ReconstructionOptions opt;
  opt.raysPerIteration = 0;
  opt.primitives = 3;
  opt.iterations = 400;
  const auto result = reconstructTransferFunction(renderer, { { truth, view, {} } }, opt);
  ASSERT_EQ(result.primitives.size(), 3u);
  EXPECT_NO_THROW(validatePrimitives(result.primitives, false));
  const auto again =
    rasterize1D(result.primitives, result.table1D.min, result.table1D.max, result.table1D.width);
  for (size_t i = 0; i < again.rgba.size(); ++i)
    ASSERT_NEAR(again.rgba[i], result.table1D.rgba[i], 1e-6);
  EXPECT_LT(result.loss.back(), 0.1 * result.loss.front());
  const double db = psnr(
    compositeOverBackground(renderResult(renderer.caster(), result, view), view.background), truth);
  EXPECT_GE(db, kRecoveredDb);

  opt.primitives = 65;
  EXPECT_THROW(reconstructTransferFunction(renderer, { { truth, view, {} } }, opt), Error);
}
