// TestRayCaster.cxx: the fast ray caster against the naive reference (values to 1e-5), exactness
// of block skipping and threading, ParaView's default distances, cancellation and bad input.
//
// Compared: ddg::RayCaster::render vs ddg::testing::referenceRender on small analytic volumes
// (anisotropic spacing, non-zero origin, uint8 and float types), perspective and parallel views,
// 1D and 2D tables. Tolerance kValueTol = 1e-5 on premultiplied RGBA for at least 99.9% of
// pixels, and kOutlierTol = 2e-3 for the rest (float vs double sample positions can move one
// sample across the exit face of the box).
#include "ReferenceRayCaster.h"
#include "VolumePieces.h"

#include "Common/Error.h"
#include "Render/Lighting.h"
#include "Render/RayCaster.h"
#include "Render/RayCasterSample.h"
#include "Render/SortLast.h"
#include "TransferFunction/GaussianPrimitive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

using namespace ddg;

namespace
{
constexpr double kValueTol = 1e-5;
constexpr double kOutlierTol = 2e-3;

using ddg::testing::blobVolume;
using ddg::testing::orbitView;

TransferFunction1D testTF()
{
  TransferFunction1D tf;
  tf.color = { { 0, 0.1, 0.2, 0.9 }, { 90, 0.2, 0.9, 0.3 }, { 180, 1.0, 0.6, 0.1 },
    { 255, 1, 1, 1 } };
  tf.opacity = { { 0, 0 }, { 40, 0 }, { 120, 0.3, 0.4, 0.2 }, { 200, 0.05 }, { 255, 0.9 } };
  return tf;
}

void expectClose(const Image& fast, const Image& ref)
{
  ASSERT_EQ(fast.width, ref.width);
  ASSERT_EQ(fast.height, ref.height);
  size_t outliers = 0;
  double worst = 0;
  for (size_t i = 0; i < fast.pixels.size(); ++i)
  {
    const double d = std::abs(fast.pixels[i] - ref.pixels[i]);
    worst = std::max(worst, d);
    outliers += d > kValueTol ? 1 : 0;
    ASSERT_LE(d, kOutlierTol) << "value " << i;
  }
  EXPECT_LE(outliers, fast.pixels.size() / 1000) << "worst difference " << worst;
}

// A uniform draw in [lo, hi) from a linear congruential generator: the same numbers on every
// platform, for the lane-by-lane comparisons below.
float lcgUniform(std::uint32_t& seed, float lo, float hi)
{
  seed = seed * 1664525u + 1013904223u;
  return lo + (hi - lo) * static_cast<float>(seed >> 8) / 16777216.0f;
}

// A 2D table of two Gaussian primitives over value [0, 255] x gradient [0, 60]; the first's
// colour and opacity as given.
TransferTable2D twoPrimitiveTable(std::array<double, 3> rgb0, double opacity0)
{
  std::vector<GaussianPrimitive> prims(2);
  prims[0].mean = { 120, 10 };
  prims[0].stddev = { 25, 8 };
  prims[0].rgb = rgb0;
  prims[0].opacity = opacity0;
  prims[1].mean = { 200, 30 };
  prims[1].stddev = { 20, 15 };
  prims[1].rgb = { 0.2, 0.5, 1.0 };
  prims[1].opacity = 0.8;
  return rasterize2D(prims, { 0, 255 }, { 0, 60 }, 64, 32);
}

// The largest difference of two images and how many values differ by more than 2e-3.
std::pair<double, size_t> looseDifference(const Image& a, const Image& b)
{
  double worst = 0;
  size_t over = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
  {
    const double dd = std::abs(a.pixels[i] - b.pixels[i]);
    worst = std::max(worst, dd);
    over += dd > 2e-3 ? 1 : 0;
  }
  return { worst, over };
}

} // namespace

TEST(RayCaster, MatchesReferencePerspectiveAndParallel)
{
  for (ScalarType type : { ScalarType::UInt8, ScalarType::Float32 })
  {
    const Volume vol = blobVolume(type);
    const RayCaster caster(vol);
    const auto table = caster.paraviewTable(testTF());
    for (bool parallel : { false, true })
    {
      for (double az : { 0.0, 63.0, 200.0 })
      {
        const View view = orbitView(vol, az, parallel);
        RenderOptions opt;
        const Image fast = caster.render(table, view, opt);
        const Image ref =
          reference::referenceRender(vol, table, view, caster.defaultSampleDistance(),
            caster.defaultOpacityUnitDistance(), opt.sampleOffset, opt.terminationOpacity);
        SCOPED_TRACE(::testing::Message()
          << "type " << scalarTypeName(type) << " parallel " << parallel << " az " << az);
        expectClose(fast, ref);
      }
    }
  }
}

// Shade on against the shader's own definitions in double (ReferenceRayCaster.h). The ray
// caster interpolates per-point differences where the shader differences two interpolated
// values N/(N-1) voxels apart: equal for fields linear over two cells, close on this smooth one.
// Tolerance: 2e-3 on 99 % of the premultiplied values, 5e-3 for all (measured: at most 1.6e-3).
TEST(RayCaster, ShadeMatchesLitReference)
{
  for (ScalarType type : { ScalarType::UInt8, ScalarType::Float32 })
  {
    const Volume vol = blobVolume(type);
    const RayCaster caster(vol);
    const auto table = caster.paraviewTable(testTF());
    for (bool parallel : { false, true })
    {
      for (const Lighting& lighting :
        { Lighting{ true, 0, 1, 0, 100 }, Lighting{ true, 0, 0.8, 0.5, 30 } })
      {
        View view = orbitView(vol, parallel ? 200.0 : 63.0, parallel);
        view.lighting = lighting;
        RenderOptions opt;
        const Image fast = caster.render(table, view, opt);
        const Image ref =
          reference::referenceRenderLit(vol, table, view, caster.defaultSampleDistance(),
            caster.defaultOpacityUnitDistance(), opt.sampleOffset, opt.terminationOpacity);
        view.lighting = Lighting{};
        const Image unlit = caster.render(table, view, opt);
        double worst = 0, unlitDiff = 0;
        size_t over = 0;
        for (size_t i = 0; i < fast.pixels.size(); ++i)
        {
          const double dd = std::abs(fast.pixels[i] - ref.pixels[i]);
          worst = std::max(worst, dd);
          over += dd > 2e-3 ? 1 : 0;
          unlitDiff = std::max<double>(unlitDiff, std::abs(unlit.pixels[i] - ref.pixels[i]));
        }
        SCOPED_TRACE(::testing::Message()
          << "type " << scalarTypeName(type) << " parallel " << parallel << " specular "
          << lighting.specular << " worst " << worst << " over 2e-3: " << over);
        EXPECT_LE(worst, 5e-3);
        EXPECT_LE(over, fast.pixels.size() / 100);
        EXPECT_GT(unlitDiff, 0.1); // the lighting shows: the unlit image is far from it
      }
    }
  }
}

// The specular power from the light kit's table (float) against std::pow (double), per light sum:
// within 1e-4 per light (5 lights, colours <= 0.75: 4e-4 in all) over ParaView's range of powers
// (0 to 100), normals all round and positions in front of the camera; where every lane's rho lies
// below the table's cutoff the term is skipped, and there the table holds 0 (below 1e-6).
TEST(RayCaster, SpecularPowerTableMatchesPow)
{
  for (double power : { 0.0, 1.0, 7.5, 30.0, 100.0 })
  {
    Lighting lighting;
    lighting.shade = true;
    lighting.specular = 0.5;
    lighting.specularPower = power;
    const LightKit kit = LightKit::paraview(lighting);
    for (int i = 0; i <= LightKit::kPowerSteps; ++i)
      if (static_cast<float>(i + 1) / LightKit::kPowerSteps <= kit.powerCutoff)
        ASSERT_EQ(kit.power[static_cast<size_t>(i)], 0.0f) << "power " << power << " entry " << i;
    double worst = 0;
    int highlights = 0;
    for (int t = 0; t < 20000; ++t)
    {
      const double a = 0.000314159 * 7 * t, b = 0.0021 * t; // normals over the sphere
      const double m[3] = { std::cos(a) * std::sin(b), std::sin(a) * std::sin(b), std::cos(b) };
      const double p[3] = { 0.3 * std::sin(0.01 * t), -0.2, -4.0 + std::cos(0.003 * t) };
      const float mf[3] = { float(m[0]), float(m[1]), float(m[2]) },
                  pf[3] = { float(p[0]), float(p[1]), float(p[2]) };
      double dd[3], sd[3];
      float df[3], sf[3];
      ASSERT_TRUE(lightSums(kit, m, p, dd, sd));
      ASSERT_TRUE(lightSums(kit, mf, pf, df, sf));
      for (int c = 0; c < 3; ++c)
      {
        worst = std::max(worst, std::abs(sf[c] - sd[c]));
        highlights += sd[c] > 0.1 ? 1 : 0;
      }
    }
    EXPECT_LE(worst, 4e-4) << "power " << power;
    EXPECT_GT(highlights, 0) << "power " << power; // some normals do face a highlight
  }
}

// The lit queue's two builds (shadeBatch and its AVX2 build, Render/RayCasterSample.h) give the
// same bits: partial and full queues, zero gradients, diffuse only and with highlights, clamped
// (1D) and not (2D), at a view's lighting frame.
TEST(RayCaster, ShadeQueueBuildsAgree)
{
  const Volume vol = blobVolume(ScalarType::Float32);
  std::uint32_t seed = 12345;
  auto uniform = [&seed](float lo, float hi) { return lcgUniform(seed, lo, hi); };
  int highlights = 0;
  for (const auto& [specular, power] :
    { std::pair{ 0.0, 100.0 }, std::pair{ 0.5, 30.0 }, std::pair{ 1.0, 7.5 } })
  {
    View view = orbitView(vol, 35, false);
    view.lighting.shade = true;
    view.lighting.specular = specular;
    view.lighting.specularPower = power;
    raycast::SampleLighting light;
    const double offset[3] = { 0, 0, 0 };
    light.setup(LightingFrame::of(vol, view), view, offset);
    const auto& d = vol.dims();
    for (int trial = 0; trial < 400; ++trial)
    {
      const int count = 1 + trial % raycast::kBatch;
      const bool clamp = trial % 2 == 0;
      float g[3][raycast::kBatch], k[raycast::kBatch], base[3][raycast::kBatch];
      const float e[3] = { uniform(0, d[0] - 1.0f), uniform(0, d[1] - 1.0f),
        uniform(0, d[2] - 1.0f) };
      const float s[3] = { uniform(-0.5f, 0.5f), uniform(-0.5f, 0.5f), uniform(-0.5f, 0.5f) };
      for (int l = 0; l < raycast::kBatch; ++l)
      {
        const bool zero = l == 3 && trial % 5 == 0; // a constant region: black
        for (int a = 0; a < 3; ++a)
        {
          g[a][l] = zero ? 0.0f : uniform(-40.0f, 40.0f);
          base[a][l] = uniform(0.0f, 1.0f);
        }
        k[l] = static_cast<float>(l) + uniform(0.0f, 0.5f);
      }
      float wide[3][raycast::kBatch], narrow[3][raycast::kBatch];
      std::memcpy(wide, base, sizeof(base));
      std::memcpy(narrow, base, sizeof(base));
      if (!raycast::shadeQueueAvx2(light, count, g, e, s, k, clamp, wide))
        GTEST_SKIP() << "this CPU (or compiler) has no AVX2: one build only";
      light.shadeBatch(count, g, e, s, k, clamp, narrow);
      ASSERT_EQ(std::memcmp(wide, narrow, sizeof(wide)), 0)
        << "specular " << specular << " trial " << trial;
      if (specular > 0)
      {
        float unlit[3][raycast::kBatch];
        std::memcpy(unlit, base, sizeof(base));
        raycast::SampleLighting diffuseOnly = light;
        diffuseOnly.kit.specular = 0;
        diffuseOnly.shadeBatch(count, g, e, s, k, false, unlit);
        for (int l = 0; l < count; ++l)
          highlights += narrow[0][l] > unlit[0][l] + 1e-3f ? 1 : 0;
      }
    }
  }
  EXPECT_GT(highlights, 0); // the specular term ran in both builds
}

// The 2D classification of a batch (the lanes' gradient magnitudes and table coordinates
// together, Render/RayCasterClassify.h) gives the bits of one sample's: values and gradients
// inside the table, on its edges and beyond them (clamped), partial and full batches.
TEST(RayCaster, TwoDLookupBatchAgrees)
{
  const TransferTable2D table = twoPrimitiveTable({ 0.9, 0.5, 0.2 }, 0.6);
  raycast::Classify2D classify;
  classify.prepare(table, 1.0, 1.25);
  std::uint32_t seed = 777;
  auto uniform = [&seed](float lo, float hi) { return lcgUniform(seed, lo, hi); };
  int clamped = 0;
  for (int trial = 0; trial < 500; ++trial)
  {
    const int count = 1 + trial % raycast::kBatch;
    float g[3][raycast::kBatch], v[raycast::kBatch], magnitude[raycast::kBatch];
    for (int l = 0; l < raycast::kBatch; ++l)
    {
      v[l] = l == 2 && trial % 3 == 0 ? 255.0f : uniform(-30.0f, 285.0f); // an edge, beyond
      for (int a = 0; a < 3; ++a)
        g[a][l] = l == 5 && trial % 4 == 0 ? 0.0f : uniform(-80.0f, 80.0f);
    }
    transferGradientBatch(g, magnitude);
    raycast::RGBA batch[raycast::kBatch];
    classify.lookupBatch(count, v, magnitude, batch);
    for (int l = 0; l < count; ++l)
    {
      const float gl[3] = { g[0][l], g[1][l], g[2][l] };
      const float m = transferGradient(gl);
      ASSERT_EQ(std::memcmp(&m, &magnitude[l], sizeof(m)), 0) << "trial " << trial;
      const raycast::RGBA one = classify.lookup(v[l], m);
      ASSERT_EQ(std::memcmp(&one, &batch[l], sizeof(one)), 0) << "trial " << trial << " lane " << l;
      clamped += v[l] < 0.0f || v[l] > 255.0f || m > 60.0f ? 1 : 0;
    }
  }
  EXPECT_GT(clamped, 100); // the clamps ran
}

// A constant region has no gradient: ParaView's normal is NaN there and the sample is black
// with its opacity (no NaN in the image).
TEST(RayCaster, ShadeOfAConstantRegionIsBlack)
{
  const std::array<int, 3> dims{ 12, 12, 12 };
  std::vector<float> v(12 * 12 * 12, 100.0f);
  v[0] = 0; // not constant overall (a constant volume is refused), constant where the ray looks
  const Volume vol(dims, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::Float32);
  const RayCaster caster(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 1, 1, 1 }, { 100, 1, 1, 1 } };
  tf.opacity = { { 0, 0.5 }, { 100, 0.5 } };
  View view = defaultView(vol, 8, 8);
  view.camera.position = view.camera.focalPoint + Eigen::Vector3d(0, 0, -30); // the far side
  view.lighting.shade = true;
  const Image img = caster.render(caster.paraviewTable(tf), view);
  EXPECT_EQ(img.at(4, 4, 0), 0.0f);
  EXPECT_EQ(img.at(4, 4, 1), 0.0f);
  EXPECT_GT(img.at(4, 4, 3), 0.9f);
  for (float x : img.pixels)
    ASSERT_TRUE(std::isfinite(x));
}

// Two points thin along z (the shader's offset is then two voxels, clamped): finite, lit.
TEST(RayCaster, ShadeOfATwoPointThinVolumeIsFinite)
{
  const Volume thick = blobVolume(ScalarType::Float32);
  const auto& d = thick.dims();
  std::vector<float> v(static_cast<size_t>(d[0]) * d[1] * 2);
  const std::vector<float> all = thick.floatValues();
  std::copy(all.begin() + static_cast<std::ptrdiff_t>(d[0]) * d[1] * 12,
    all.begin() + static_cast<std::ptrdiff_t>(d[0]) * d[1] * 14, v.begin());
  const Volume thin({ d[0], d[1], 2 }, thick.origin(), thick.spacing(), v, ScalarType::Float32);
  const RayCaster caster(thin);
  View view = orbitView(thin, 30.0, false);
  view.lighting.shade = true;
  const Image img = caster.render(caster.paraviewTable(testTF()), view);
  double sum = 0;
  for (float x : img.pixels)
  {
    ASSERT_TRUE(std::isfinite(x));
    sum += x;
  }
  EXPECT_GT(sum, 0.0);
}

// The renderers' gradient at a sample, computed from the scalars around its cell (no per-voxel
// buffer), equals the per-point gradients (lightingGradients) interpolated there, inside, on the
// faces and outside (clamped), for 8-bit and float volumes and one two points thin.
TEST(RayCaster, GradientStencilEqualsInterpolatedPointGradients)
{
  const Volume thick = blobVolume(ScalarType::Float32);
  const auto& d0 = thick.dims();
  const std::vector<float> all = thick.floatValues();
  const Volume thin({ d0[0], d0[1], 2 }, thick.origin(), thick.spacing(),
    std::vector<float>(all.begin() + static_cast<std::ptrdiff_t>(d0[0]) * d0[1] * 12,
      all.begin() + static_cast<std::ptrdiff_t>(d0[0]) * d0[1] * 14),
    ScalarType::Float32);
  for (const Volume& vol : { blobVolume(ScalarType::UInt8), thick, thin })
  {
    const auto& n = vol.dims();
    const std::vector<float> g = lightingGradients(vol);
    const GradientStencil stencil = GradientStencil::of(vol);
    double top = 0;
    for (float x : g)
      top = std::max(top, std::abs(static_cast<double>(x)));
    std::uint32_t state = 12345;
    auto uniform = [&](double lo, double hi)
    {
      state = state * 1664525u + 1013904223u;
      return lo + (hi - lo) * (state >> 8) / double(1u << 24);
    };
    for (int trial = 0; trial < 400; ++trial)
    {
      double x[3];
      for (int a = 0; a < 3; ++a)
        x[a] = trial % 4 == 0 ? (trial / 4 % 2 ? n[a] - 1.0 : 0.0) : uniform(-0.5, n[a] - 0.5);
      // the reference: trilinear interpolation of the per-point gradients
      double ref[3] = { 0, 0, 0 }, f[3];
      int i[3];
      for (int a = 0; a < 3; ++a)
      {
        const double c = std::clamp(x[a], 0.0, n[a] - 1.0);
        i[a] = std::min(static_cast<int>(c), n[a] - 2);
        f[a] = c - i[a];
      }
      for (int corner = 0; corner < 8; ++corner)
      {
        const int p[3] = { i[0] + (corner & 1), i[1] + ((corner >> 1) & 1), i[2] + (corner >> 2) };
        const double w = (corner & 1 ? f[0] : 1 - f[0]) * ((corner >> 1) & 1 ? f[1] : 1 - f[1]) *
          (corner >> 2 ? f[2] : 1 - f[2]);
        const size_t at =
          3 * (p[0] + static_cast<size_t>(n[0]) * (p[1] + static_cast<size_t>(n[1]) * p[2]));
        for (int a = 0; a < 3; ++a)
          ref[a] += w * g[at + a];
      }
      double got[3];
      float gotF[3];
      const float xf[3] = { static_cast<float>(x[0]), static_cast<float>(x[1]),
        static_cast<float>(x[2]) };
      vol.visit(
        [&](const auto* v)
        {
          stencil.at(v, x, got);
          stencil.at(v, xf, gotF);
        });
      for (int a = 0; a < 3; ++a)
      {
        EXPECT_NEAR(got[a], ref[a], 1e-6 * top) << "trial " << trial << " axis " << a;
        EXPECT_NEAR(gotF[a], ref[a], 1e-4 * top) << "trial " << trial << " axis " << a;
      }
    }
  }
}

TEST(RayCaster, MatchesReferenceWith2DTable)
{
  const Volume vol = blobVolume(ScalarType::Float32);
  const RayCaster caster(vol);
  const auto table = twoPrimitiveTable({ 0.9, 0.3, 0.2 }, 0.4);
  const View view = orbitView(vol, 30, false);
  const Image fast = caster.render(table, view);
  const Image ref = reference::referenceRender2D(vol, table, view, caster.defaultSampleDistance(),
    caster.defaultOpacityUnitDistance(), 0.5, 1.0 - 1.0 / 255.0);
  // The reference takes the gradient axis as the shader does (two interpolated values N/(N-1)
  // voxels apart); the ray caster interpolates per-point differences: they differ by O(1/N)
  // where the field is not linear over the two cells (N = 20..28 here), as in the lit tests.
  const auto [worst, over] = looseDifference(fast, ref);
  EXPECT_LE(worst, 5e-3);
  EXPECT_LE(over, fast.pixels.size() / 100) << "worst " << worst;
  double alpha = 0;
  for (size_t i = 3; i < fast.pixels.size(); i += 4)
    alpha += fast.pixels[i];
  EXPECT_GT(alpha, 1.0) << "the 2D table should make something visible";
}

// Shade on with a 2D table: lit as in 1D from the same gradient, the lit colour not clamped
// (ParaView's 2D path); the gradient axis and the lighting from the shader's definitions in the
// reference. Default coefficients, and specular with a white table so that lit colours pass 1.
TEST(RayCaster, Shade2DMatchesLitReference)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const RayCaster caster(vol);
  const auto table = twoPrimitiveTable({ 1, 1, 1 }, 0.5);
  for (const Lighting& lighting :
    { Lighting{ true, 0, 1, 0, 100 }, Lighting{ true, 0, 1, 0.8, 10 } })
  {
    View view = orbitView(vol, 63, false);
    view.lighting = lighting;
    const Image fast = caster.render(table, view);
    const Image ref = reference::referenceRender2D(vol, table, view, caster.defaultSampleDistance(),
      caster.defaultOpacityUnitDistance(), 0.5, 1.0 - 1.0 / 255.0);
    const auto [worst, over] = looseDifference(fast, ref);
    double brightest = 0;
    for (size_t i = 0; i < fast.pixels.size(); ++i)
      if (i % 4 != 3)
        brightest = std::max<double>(brightest, fast.pixels[i]);
    SCOPED_TRACE(::testing::Message() << "specular " << lighting.specular << " worst " << worst
                                      << " over 2e-3: " << over << " brightest " << brightest);
    EXPECT_LE(worst, 1e-2);
    EXPECT_LE(over, fast.pixels.size() / 50);
    if (lighting.specular > 0)
      EXPECT_GT(brightest, 1.0); // not clamped: premultiplied colour past 1 where it is bright
  }
}

// The 2D table's empty-space skipping bounds the per-sample gradient by block maxima: skipping
// on or off gives the same image.
TEST(RayCaster, SkippingDoesNotChangeThe2DImage)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const RayCaster caster(vol);
  std::vector<GaussianPrimitive> prims(1);
  prims[0].mean = { 160, 40 };
  prims[0].stddev = { 8, 6 };
  prims[0].rgb = { 0.9, 0.6, 0.2 };
  prims[0].opacity = 0.9;
  const auto table = rasterize2D(prims, { 0, 255 }, { 0, 60 }, 64, 32);
  const View view = orbitView(vol, 40, false, 64, 64);
  RenderOptions a, b;
  b.emptySpaceSkipping = false;
  RenderStats sa;
  const Image ia = caster.render(table, view, a, {}, &sa);
  const Image ib = caster.render(table, view, b);
  EXPECT_EQ(ia.pixels, ib.pixels);
  EXPECT_GT(sa.skippedSamples, 0);
}

TEST(RayCaster, SkippingAndThreadsDoNotChangeTheImage)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const RayCaster caster(vol);
  // Narrow opacity band: most blocks are empty and get skipped.
  TransferFunction1D tf = testTF();
  tf.opacity = { { 0, 0 }, { 150, 0 }, { 160, 0.8 }, { 170, 0 }, { 255, 0 } };
  const auto table = caster.paraviewTable(tf);
  const View view = orbitView(vol, 40, false, 64, 64);
  RenderOptions a, b, c;
  b.emptySpaceSkipping = false;
  c.threads = 1;
  const Image ia = caster.render(table, view, a);
  const Image ib = caster.render(table, view, b);
  const Image ic = caster.render(table, view, c);
  EXPECT_EQ(ia.pixels, ib.pixels);
  EXPECT_EQ(ia.pixels, ic.pixels);
}

// With Shade on, `unlitToo` composites the march's samples unlit as well: channels 0..3 are the
// lit render and 4..7 the render with Shade off, value for value (1D and 2D tables, jitter, one
// thread or two, rays ended early at half opacity without skipping); with Shade off it changes
// nothing; a piece is refused.
TEST(RayCaster, UnlitTooIsTheUnlitRender)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const RayCaster caster(vol);
  const TransferTable1D table1 = caster.paraviewTable(testTF());
  const TransferTable2D table2 = twoPrimitiveTable({ 0.9, 0.5, 0.2 }, 0.6);
  for (int kind = 0; kind < 2; ++kind)
    for (int pass = 0; pass < 3; ++pass)
    {
      const bool jitter = pass == 1, early = pass == 2;
      View lit = orbitView(vol, 63, false, 48, 40);
      lit.lighting = Lighting{ true, 0.1, 0.8, 0.5, 30 };
      View unlit = lit;
      unlit.lighting.shade = false;
      RenderOptions plain, both;
      plain.jitter = both.jitter = jitter;
      if (early) // rays stop at half opacity; every block marched
      {
        plain.terminationOpacity = both.terminationOpacity = 0.5;
        plain.emptySpaceSkipping = both.emptySpaceSkipping = false;
      }
      both.unlitToo = true;
      both.threads = jitter ? 1 : 0;
      auto render = [&](const View& v, const RenderOptions& o)
      { return kind == 0 ? caster.render(table1, v, o) : caster.render(table2, v, o); };
      const Image litImage = render(lit, plain), unlitImage = render(unlit, plain);
      const Image two = render(lit, both);
      ASSERT_EQ(two.channels, 8);
      size_t differ = 0, shown = 0, stopped = 0;
      for (size_t p = 0, n = static_cast<size_t>(two.width) * two.height; p < n; ++p)
        for (int c = 0; c < 4; ++c)
        {
          differ += two.pixels[8 * p + c] != litImage.pixels[4 * p + c];
          differ += two.pixels[8 * p + 4 + c] != unlitImage.pixels[4 * p + c];
          shown += c == 3 && unlitImage.pixels[4 * p + 3] > 0.1f;
          stopped += c == 3 && unlitImage.pixels[4 * p + 3] > 0.5f;
        }
      EXPECT_EQ(differ, 0u) << "table " << kind + 1 << "D, pass " << pass;
      EXPECT_GT(shown, 100u);
      if (early)
        EXPECT_GT(stopped, 20u); // rays that ended early, at the same sample in both
      EXPECT_NE(litImage.pixels, unlitImage.pixels);            // the lighting shows
      EXPECT_EQ(render(unlit, both).pixels, unlitImage.pixels); // Shade off: one image
    }
  const auto& d = vol.dims();
  const auto [piece, brick] =
    ddg::testing::pieceOf(vol, ddg::testing::Box{ 0, d[0] / 2, 0, d[1] - 1, 0, d[2] - 1 }, 1);
  View lit = orbitView(vol, 63, false, 32, 32);
  lit.lighting.shade = true;
  RenderOptions both;
  both.unlitToo = true;
  EXPECT_THROW(RayCaster(piece, brick).render(table1, lit, both), Error);
}

TEST(RayCaster, ParaViewDefaultDistances)
{
  // NOTES-paraview-rendering: 64^3 unit spacing -> d = 0.3155606, unit distance = sqrt(3);
  // 128^3 and larger -> mean spacing / 2.
  const Volume small(
    { 64, 64, 64 }, { 0, 0, 0 }, { 1, 1, 1 }, std::vector<float>(64 * 64 * 64, 0.0f));
  std::vector<float> v(64 * 64 * 64, 0.0f);
  v[5] = 1.0f;
  const RayCaster c64(Volume({ 64, 64, 64 }, { 0, 0, 0 }, { 1, 1, 1 }, v));
  EXPECT_NEAR(c64.defaultSampleDistance(), 0.3155606, 1e-6);
  EXPECT_NEAR(c64.defaultOpacityUnitDistance(), std::sqrt(3.0), 1e-12);
  std::vector<float> big(static_cast<size_t>(130) * 130 * 130, 0.0f);
  big[7] = 2.0f;
  const RayCaster c130(Volume({ 130, 130, 130 }, { 0, 0, 0 }, { 1, 2, 3 }, big));
  EXPECT_NEAR(c130.defaultSampleDistance(), 1.0, 1e-12);
}

TEST(RayCaster, ConstantAndFlatVolumesAreRejected)
{
  const Volume constant({ 4, 4, 4 }, { 0, 0, 0 }, { 1, 1, 1 }, std::vector<float>(64, 7.0f));
  EXPECT_THROW({ RayCaster c(constant); }, Error);
  std::vector<float> flat(16, 0.0f);
  flat[3] = 1.0f;
  const Volume slice({ 4, 4, 1 }, { 0, 0, 0 }, { 1, 1, 1 }, flat);
  EXPECT_THROW({ RayCaster c(slice); }, Error);
}

TEST(RayCaster, ProgressCanCancel)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const RayCaster caster(vol);
  const auto table = caster.paraviewTable(testTF());
  const View view = orbitView(vol, 10, false, 128, 128);
  double last = -1;
  caster.render(table, view, {},
    [&](double f)
    {
      EXPECT_GE(f, last);
      last = f;
      return true;
    });
  EXPECT_DOUBLE_EQ(last, 1.0);
  EXPECT_THROW(caster.render(table, view, {}, [](double) { return false; }), Cancelled);
}

TEST(RayCaster, EmptyTableRangeOrBadOffsetIsAnError)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const RayCaster caster(vol);
  TransferTable1D bad;
  EXPECT_THROW(caster.render(bad, orbitView(vol, 0, false)), Error);
  RenderOptions opt;
  opt.sampleOffset = 2.0;
  EXPECT_THROW(caster.render(caster.paraviewTable(testTF()), orbitView(vol, 0, false), opt), Error);
}

TEST(RayCaster, OpacityCorrectionFollowsUnitDistance)
{
  // A thin slab of constant alpha: with unit distance == sample distance the per-sample alpha
  // is the table alpha; with twice the unit distance it is 1 - (1 - a)^(1/2).
  std::vector<float> v(static_cast<size_t>(8) * 8 * 8, 100.0f);
  v[0] = 0.0f; // non-constant range [0, 100]
  const Volume vol({ 8, 8, 8 }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::Float32);
  const RayCaster caster(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 1, 1, 1 } };
  tf.opacity = { { 0, 0.2 }, { 100, 0.2 } };
  View view;
  view.width = view.height = 3;
  view.camera.focalPoint = { 3.5, 3.5, 3.5 };
  view.camera.position = { 3.5, 3.5, 50 };
  view.camera.parallelProjection = true;
  view.camera.parallelScale = 0.5;
  RenderOptions opt;
  opt.sampleDistance = 7.0 / 4.0; // samples at 0.5, 1.5, 2.5, 3.5 steps: 4 samples in 7 units
  view.opacityUnitDistance = opt.sampleDistance;
  const Image a = caster.render(caster.paraviewTable(tf), view, opt);
  EXPECT_NEAR(a.at(1, 1, 3), 1.0 - std::pow(0.8, 4), 1e-5);
  view.opacityUnitDistance = 2 * opt.sampleDistance;
  const Image b = caster.render(caster.paraviewTable(tf), view, opt);
  EXPECT_NEAR(b.at(1, 1, 3), 1.0 - std::pow(0.8, 2), 1e-5);
}

namespace
{
using ddg::testing::bisect;
using ddg::testing::Box;
using ddg::testing::pieceOf;

// The largest difference between the whole's image and its pieces' images composited.
template <typename Table>
double pieceDifference(const Volume& whole, const std::vector<Box>& boxes, const Table& table,
  const View& view, const RenderOptions& opt)
{
  const Image ref = RayCaster(whole).render(table, view, opt);
  std::vector<Image> parts;
  for (const Box& box : boxes)
  {
    const auto [piece, brick] = pieceOf(whole, box, 1);
    if (brick.ownsNothing())
      continue;
    parts.push_back(RayCaster(piece, brick).render(table, view, opt));
    EXPECT_EQ(parts.back().channels, 5);
  }
  const Image got = compositeBricks(parts);
  // each part cut to its footprint (what a rank sends) composites to the same image, bit for bit
  std::vector<std::vector<float>> cropped;
  std::vector<ddg::PixelRect> rects;
  std::vector<const float*> data;
  for (const Image& part : parts)
  {
    rects.push_back(ddg::footprint(part));
    cropped.push_back(ddg::cropPixels(part, rects.back()));
  }
  for (const auto& c : cropped)
    data.push_back(c.data());
  EXPECT_EQ(compositeBricks(data, rects, view.width, view.height).pixels, got.pixels);
  double worst = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i)
    worst = std::max(worst, static_cast<double>(std::abs(got.pixels[i] - ref.pixels[i])));
  return worst;
}
} // namespace

// The pieces of a volume (ParaView's pieces under MPI, one ghost level) rendered each on its own
// and composited sort-last give the whole's image: 1D, Shade (with specular), 2D with Shade;
// perspective, parallel, camera inside the volume, jitter; bisection into 2, 3 and 4 pieces and
// an uneven split; float rounding only (1e-5) without early termination, within ParaView's
// termination threshold (1/255) with it.
TEST(RayCaster, PiecesCompositeToTheWholeImage)
{
  for (ScalarType type : { ScalarType::UInt8, ScalarType::Float32 })
  {
    const Volume vol = blobVolume(type);
    const auto& d = vol.dims();
    const Box whole{ 0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1 };
    std::vector<std::vector<Box>> splits;
    for (int n : { 2, 3, 4 })
    {
      splits.emplace_back();
      bisect(whole, n, splits.back());
    }
    splits.push_back({ { 0, 5, 0, d[1] - 1, 0, 20 }, { 5, d[0] - 1, 0, d[1] - 1, 0, 20 },
      { 0, d[0] - 1, 0, 3, 20, d[2] - 1 }, { 0, d[0] - 1, 3, d[1] - 1, 20, d[2] - 1 } });
    std::vector<View> views{ orbitView(vol, 30, false), orbitView(vol, 200, true) };
    View inside = orbitView(vol, 75, false);
    inside.camera.position = inside.camera.focalPoint +
      0.2 * (inside.camera.position - inside.camera.focalPoint); // in the volume's box
    views.push_back(inside);
    const TransferTable1D table1 = RayCaster(vol).paraviewTable(testTF());
    const TransferTable2D table2 = twoPrimitiveTable({ 0.9, 0.5, 0.2 }, 0.6);
    for (size_t s = 0; s < splits.size(); ++s)
      for (size_t v = 0; v < views.size(); ++v)
      {
        View lit = views[v];
        lit.lighting.shade = true;
        lit.lighting.specular = 0.5;
        lit.lighting.specularPower = 30;
        RenderOptions exact;
        exact.terminationOpacity = 1.0;
        exact.jitter = v == 1;
        const std::string where = "split " + std::to_string(s) + " view " + std::to_string(v);
        EXPECT_LE(pieceDifference(vol, splits[s], table1, views[v], exact), 1e-5) << where;
        EXPECT_LE(pieceDifference(vol, splits[s], table1, lit, exact), 1e-5) << where << " lit";
        EXPECT_LE(pieceDifference(vol, splits[s], table2, lit, exact), 1e-5) << where << " 2D";
        EXPECT_LE(pieceDifference(vol, splits[s], table1, lit, RenderOptions{}), 1.0 / 255 + 1e-5)
          << where << " early termination";
      }
  }
}

// A piece that lacks the ghost points gradients need, owns nothing or lies outside its whole is
// refused with the reason; a decomposition with overlaps or holes is refused by checkBricksTile.
// A piece's footprint is the smallest rectangle of its pixels with opacity; a piece that shows
// nowhere has an empty one and adds nothing; a rectangle outside the image is refused.
TEST(SortLast, FootprintsCropWhatAPieceShows)
{
  Image part(6, 4, 5, 0.0f);
  for (size_t p = 4; p < part.pixels.size(); p += 5)
    part.pixels[p] = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(ddg::footprint(part).empty());
  // a sample on the ray but no opacity (the key set, A = 0) is nothing to send
  part.at(0, 0, 4) = 3;
  EXPECT_TRUE(ddg::footprint(part).empty());
  part.at(1, 2, 3) = 0.5f;
  part.at(1, 2, 0) = 0.25f;
  part.at(1, 2, 4) = 7;
  part.at(4, 1, 3) = 0.125f;
  part.at(4, 1, 4) = 2;
  const ddg::PixelRect r = ddg::footprint(part);
  EXPECT_EQ(r.x, 1);
  EXPECT_EQ(r.y, 1);
  EXPECT_EQ(r.width, 4);
  EXPECT_EQ(r.height, 2);
  const std::vector<float> crop = ddg::cropPixels(part, r);
  ASSERT_EQ(crop.size(), 8u * 5u);
  EXPECT_EQ(crop[5 * (1 * 4 + 0) + 3], 0.5f); // (1, 2) is (0, 1) in the crop
  EXPECT_EQ(crop[5 * (0 * 4 + 3) + 3], 0.125f);
  // with a piece that shows nowhere (empty rectangle, no pixels): the one piece's image
  Image other(6, 4, 5, 0.0f);
  const std::vector<float> none;
  const Image got = compositeBricks(
    { crop.data(), none.data() }, { r, ddg::footprint(other) }, part.width, part.height);
  EXPECT_FLOAT_EQ(got.at(1, 2, 0), 0.25f);
  EXPECT_FLOAT_EQ(got.at(1, 2, 3), 0.5f);
  EXPECT_FLOAT_EQ(got.at(4, 1, 3), 0.125f);
  EXPECT_EQ(got.at(0, 0, 3), 0.0f);
  EXPECT_THROW(
    compositeBricks({ crop.data() }, { ddg::PixelRect{ 3, 1, 4, 2 } }, 6, 4), ddg::Error);
  EXPECT_THROW(ddg::cropPixels(part, ddg::PixelRect{ 0, 3, 2, 2 }), ddg::Error);
  EXPECT_THROW(compositeBricks({ crop.data() }, {}, 6, 4), ddg::Error);
}

TEST(RayCaster, PiecesThatCannotRenderTheirPartAreRefused)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const auto& d = vol.dims();
  const Box low{ 0, d[0] - 1, 0, d[1] - 1, 0, 10 }, high{ 0, d[0] - 1, 0, d[1] - 1, 10, d[2] - 1 };
  const auto [bare, bareBrick] = pieceOf(vol, high, 0);
  const RayCaster caster(bare, bareBrick); // enough for 1D tables without Shade
  View lit = orbitView(vol, 30, false);
  EXPECT_EQ(caster.render(caster.paraviewTable(testTF()), lit).channels, 5);
  lit.lighting.shade = true;
  try
  {
    caster.render(caster.paraviewTable(testTF()), lit);
    ADD_FAILURE() << "Shade without ghost points rendered";
  }
  catch (const Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("ghost"), std::string::npos) << e.what();
  }
  auto [thin, thinBrick] = pieceOf(vol, { 0, d[0] - 1, 0, d[1] - 1, 10, 10 }, 0);
  EXPECT_THROW(RayCaster(thin, thinBrick), Error); // one plane: owns no cell
  auto [moved, movedBrick] = pieceOf(vol, high, 1);
  movedBrick.offset[2] += 1; // says it starts a plane later than its points do
  EXPECT_THROW(RayCaster(moved, movedBrick), Error);

  const VolumeBrick a = pieceOf(vol, low, 1).second, b = pieceOf(vol, high, 1).second;
  EXPECT_NO_THROW(checkBricksTile({ a, b }));
  EXPECT_NO_THROW(checkBricksTile({ a, thinBrick, b })); // a piece that owns nothing is harmless
  EXPECT_THROW(checkBricksTile({ a }), Error);           // a hole
  VolumeBrick over = b;
  over.ownedMin[2] = 9; // overlaps `a` by one cell
  EXPECT_THROW(checkBricksTile({ a, over }), Error);
}
