// TestSelfConsistency.cxx: reconstruction recovers a TF from images our own renderer made.
//
// Compared: a random Gaussian-primitive TF (3 primitives, seeded) rendered by ddg::RayCaster at
// five views around the volume (RGBA targets, 160 x 160) against the reconstructed TF rendered
// the way ParaView would render the written preset (renderResult), both composed over the
// view's background in 8 bits, PSNR over RGB. On Tooth and Engine.
// Bars (named below): single-view reconstruction >= kSeenDb at its view and >= kOtherDb at the
// four others; 4-view reconstruction >= kUnseenMultiDb at the fifth, unseen view.
#include "DDGVolumeAdaptor.h"
#include "SelfConsistencyCase.h"

#include "Image/ImageMetrics.h"
#include "Reconstruct/Reconstruction.h"
#include "TransferFunction/GaussianPrimitive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

using namespace ddg;

namespace
{
constexpr double kSeenDb = 40.0;
constexpr double kOtherDb = 33.0;
constexpr double kUnseenMultiDb = 38.0;
constexpr int kSize = 160;

std::vector<View> orbitViews(const Volume& vol)
{
  std::vector<View> views;
  const double elevation[5] = { 20, -15, 35, 5, -30 };
  for (int i = 0; i < 5; ++i)
  {
    View v = defaultView(vol, kSize, kSize);
    const Eigen::Vector3d f = v.camera.focalPoint;
    const double dist = (v.camera.position - f).norm() * 0.85;
    const double az = (72.0 * i + 10) * M_PI / 180, el = elevation[i] * M_PI / 180;
    v.camera.position = f +
      dist *
        Eigen::Vector3d(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
    v.camera.viewUp = { 0, 1, 0 };
    views.push_back(v);
  }
  return views;
}

double viewPsnr(
  const RayCaster& caster, const ReconstructionResult& r, const Image& truth, const View& v)
{
  return psnr(compositeOverBackground(renderResult(caster, r, v), v.background),
    compositeOverBackground(truth, v.background));
}

void selfConsistency(const char* name, unsigned seed)
{
  const Volume vol = readVolumeFile(std::string(DDG_DATA_DIR) + "/Volumes/" + name + ".vti");
  const DifferentiableRenderer renderer(vol);
  const RayCaster& caster = renderer.caster();
  const auto range = vol.range();
  const TransferTable1D truthTable =
    rasterize1D(testcase::randomPrimitives(seed), range[0], range[1], 256);
  const auto views = orbitViews(vol);
  std::vector<Image> truth;
  for (const auto& v : views)
    truth.push_back(caster.render(truthTable, v));

  ReconstructionOptions opt;
  std::vector<ReconstructionTarget> single(1);
  single[0].image = testcase::straightAlpha(truth[0]);
  single[0].view = views[0];
  const auto one = reconstructTransferFunction(renderer, single, opt);
  std::printf("%s single view: %d steps, %.2f s%s\n", name, one.iterations, one.seconds,
    one.converged ? "" : " (not converged)");
  for (size_t i = 0; i < views.size(); ++i)
  {
    const double db = viewPsnr(caster, one, truth[i], views[i]);
    std::printf("  view %zu%s PSNR %.2f dB\n", i, i == 0 ? " (seen)" : "", db);
    EXPECT_GE(db, i == 0 ? kSeenDb : kOtherDb) << name << " view " << i;
  }

  std::vector<ReconstructionTarget> four;
  for (int i = 0; i < 4; ++i)
    four.push_back({ testcase::straightAlpha(truth[i]), views[i], {} });
  opt.raysPerIteration = 2048;
  const auto multi = reconstructTransferFunction(renderer, four, opt);
  const double unseen = viewPsnr(caster, multi, truth[4], views[4]);
  std::printf("%s four views: %d steps, %.2f s; unseen view PSNR %.2f dB\n", name, multi.iterations,
    multi.seconds, unseen);
  EXPECT_GE(unseen, kUnseenMultiDb) << name;
}

} // namespace

TEST(SelfConsistency, Tooth)
{
  selfConsistency("tooth", 11);
}

TEST(SelfConsistency, Engine)
{
  selfConsistency("engine", 12);
}
