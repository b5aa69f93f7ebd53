// TestAdjoint.cxx: gradient checks of the differentiable ray caster, all in double precision.
//
// Compared:
//  1. each adjoint primitive (trilinear interpolation, table lookup, opacity correction, blend,
//     blend inversion, Gaussian rasterization) against central finite differences
//     (f(x + h v) - f(x - h v)) / 2h on unit and random directions;
//  2. the whole renderer's backward pass (1D and 2D tables) against central finite
//     differences of its forward pass, on a small analytic volume (early termination off, so
//     the loss is smooth in the table);
//  3. the backward pass (which inverts the compositing) against a naive reverse mode that
//     stores every sample (early termination on, opacities near 1);
//  4. the float forward pass against RayCaster::render;
//  5. the float backward pass from the sample values its forward pass stored against its replay
//     by re-interpolation (bit for bit) and against the double renderer.
// Tolerances: kFdTol (relative, finite differences, h = 1e-6), kExactTol (relative, two exact
// computations of the same gradient), kForwardTol (absolute, float images).
#include "ReferenceRayCaster.h"

#include "Render/Adjoint.h"
#include "Render/DifferentiableRenderer.h"
#include "TransferFunction/GaussianPrimitive.h"
#include "TransferFunction/TransferFunction2D.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

using namespace ddg;

namespace
{
constexpr double kFdTol = 1e-5;
constexpr double kExactTol = 1e-8;
constexpr double kForwardTol = 2e-5;
constexpr double kH = 1e-6;

// Checks grad . v against the central difference of f along v for unit and random v.
void checkGradient(const std::function<double(const std::vector<double>&)>& f,
  const std::vector<double>& x, const std::vector<double>& grad, int randomDirections,
  const char* what, double tol = kFdTol)
{
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::vector<std::vector<double>> dirs;
  // unit directions: the 4 entries with the largest gradient and 2 arbitrary ones
  std::vector<size_t> order(x.size());
  for (size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::partial_sort(order.begin(), order.begin() + std::min<size_t>(4, order.size()), order.end(),
    [&](size_t a, size_t b) { return std::abs(grad[a]) > std::abs(grad[b]); });
  for (size_t q = 0; q < std::min<size_t>(4, x.size()); ++q)
  {
    std::vector<double> v(x.size(), 0.0);
    v[order[q]] = 1.0;
    dirs.push_back(v);
  }
  for (size_t idx : { x.size() / 3, x.size() / 2 })
  {
    std::vector<double> v(x.size(), 0.0);
    v[idx] = 1.0;
    dirs.push_back(v);
  }
  for (int r = 0; r < randomDirections; ++r)
  {
    std::vector<double> v(x.size());
    for (double& e : v)
      e = normal(rng);
    dirs.push_back(v);
  }
  double scale = 0;
  for (double g : grad)
    scale = std::max(scale, std::abs(g));
  for (const auto& v : dirs)
  {
    std::vector<double> xp = x, xm = x;
    double analytic = 0;
    for (size_t i = 0; i < x.size(); ++i)
    {
      xp[i] += kH * v[i];
      xm[i] -= kH * v[i];
      analytic += grad[i] * v[i];
    }
    const double numeric = (f(xp) - f(xm)) / (2 * kH);
    double vnorm = 0;
    for (double e : v)
      vnorm += std::abs(e);
    EXPECT_NEAR(analytic, numeric, tol * std::max(1.0, scale * vnorm)) << what;
  }
}

Volume testVolume()
{
  const std::array<int, 3> dims{ 10, 9, 11 };
  std::vector<float> v;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
      {
        const double x = (i - 4.5) / 4, y = (j - 4) / 3.5, z = (k - 5) / 4.5;
        v.push_back(static_cast<float>(100 * std::exp(-(x * x + y * y + z * z)) + 20 * x));
      }
  return Volume(dims, { 1, -2, 0.5 }, { 1.0, 1.2, 0.9 }, v, ScalarType::Float32);
}

View testView(const Volume& vol, int w = 7, int h = 5)
{
  View v = defaultView(vol, w, h);
  v.camera.position = v.camera.focalPoint + Eigen::Vector3d(14, 6, 25);
  v.camera.viewAngle = 25;
  return v;
}

std::vector<double> randomTable(int entries, double alphaLo, double alphaHi, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> colour(0.05, 0.95), alpha(alphaLo, alphaHi);
  std::vector<double> t(static_cast<size_t>(entries) * 4);
  for (int i = 0; i < entries; ++i)
  {
    t[4 * i] = colour(rng);
    t[4 * i + 1] = colour(rng);
    t[4 * i + 2] = colour(rng);
    t[4 * i + 3] = alpha(rng);
  }
  return t;
}

std::vector<double> randomWeights(size_t n, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> w(n);
  for (double& e : w)
    e = u(rng);
  return w;
}

} // namespace

TEST(AdjointPrimitives, Trilinear)
{
  std::vector<double> x = { 0.3, -1.2, 2.5, 0.7, 1.1, -0.4, 0.9, 2.0, 0.37, 0.61, 0.18 };
  auto f = [](const std::vector<double>& p)
  { return adjoint::trilinear(p.data(), p[8], p[9], p[10]); };
  std::vector<double> g(11, 0.0);
  adjoint::trilinearAdjoint(x.data(), x[8], x[9], x[10], 1.0, g.data(), g.data() + 8);
  checkGradient(f, x, g, 4, "trilinear");
}

TEST(AdjointPrimitives, TableLookupAndCorrection)
{
  const std::vector<double> table = randomTable(6, 0.1, 0.9, 3);
  const std::vector<double> w = { 0.3, -0.7, 1.1, 0.5 };
  for (double value : { -3.0, 0.2, 2.71, 9.9 })
  {
    int i;
    double fr;
    adjoint::tableCoordinate(value, 0.5, 0.25, 6, i, fr);
    auto f = [&](const std::vector<double>& t)
    {
      double out[4];
      adjoint::tableLookup<double, 4>(t.data(), i, fr, out);
      return w[0] * out[0] + w[1] * out[1] + w[2] * out[2] + w[3] * out[3];
    };
    std::vector<double> g(table.size(), 0.0);
    adjoint::tableLookupAdjoint<double, 4>(i, fr, w.data(), g.data());
    checkGradient(f, table, g, 3, "table lookup");
  }
  for (double a : { 0.001, 0.3, 0.95 })
  {
    const double e = 0.37;
    const double numeric =
      (adjoint::correctOpacity(a + kH, e) - adjoint::correctOpacity(a - kH, e)) / (2 * kH);
    EXPECT_NEAR(adjoint::correctOpacityDerivative(a, e), numeric, kFdTol);
  }
  EXPECT_EQ(adjoint::correctOpacityDerivative(5e-5, 0.37), 1.0); // below ParaView's threshold
}

TEST(AdjointPrimitives, BlendAndInversion)
{
  // x = (c0, c1, c2, a, A, C0, C1, C2); L = w . (C', A')
  const std::vector<double> x = { 0.2, 0.7, 0.4, 0.35, 0.45, 0.1, 0.3, 0.2 };
  const double w[4] = { 0.9, -0.4, 0.6, 1.3 };
  auto f = [&](const std::vector<double>& p)
  {
    double C[3] = { p[5], p[6], p[7] }, A = p[4];
    adjoint::blend(C, A, p.data(), p[3]);
    return w[0] * C[0] + w[1] * C[1] + w[2] * C[2] + w[3] * A;
  };
  double gA = w[3], g_c[3] = { 0, 0, 0 }, g_a = 0;
  adjoint::blendAdjoint(w, gA, x[4], x.data(), x[3], g_c, g_a);
  const std::vector<double> g = { g_c[0], g_c[1], g_c[2], g_a, gA, w[0], w[1], w[2] };
  checkGradient(f, x, g, 4, "blend");
  // inversion recovers the state before, also close to the guard
  for (double a : { 0.1, 0.9, 0.999, adjoint::kMaxOpacity })
  {
    double C[3] = { 0, 0, 0 }, A = 0.37;
    const double c[3] = { 1, 1, 1 };
    adjoint::blend(C, A, c, a);
    EXPECT_NEAR(adjoint::blendInvertAlpha(A, a), 0.37, 1e-15 / (1 - a) + 1e-12) << a;
  }
}

TEST(AdjointPrimitives, InversionWithReciprocalMatchesDivision)
{
  // The replay's inversion with 1 / (1 - a) computed apart: the same state as the division,
  // to a few ulps, up to the opacity guard kMaxOpacity.
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(0, 1);
  for (int n = 0; n < 1000; ++n)
  {
    const double a = n == 0 ? adjoint::kMaxOpacity : u(rng) * adjoint::kMaxOpacity;
    const double A = u(rng);
    double C[3] = { 0, 0, 0 }, Aafter = A;
    const double c[3] = { 0.2, 0.5, 0.7 };
    adjoint::blend(C, Aafter, c, a);
    const double byDivision = adjoint::blendInvertAlpha(Aafter, a);
    EXPECT_NEAR(adjoint::blendInvertAlphaReciprocal(Aafter, a, 1.0 / (1.0 - a)), byDivision, 1e-12)
      << "a " << a << " A " << A;
  }
}

TEST(AdjointPrimitives, GaussianRasterization)
{
  for (bool twoD : { false, true })
  {
    std::vector<GaussianPrimitive> prims(2);
    prims[0] = { { 40, 10 }, { 12, 6 }, { 0.8, 0.3, 0.2 }, 0.3 };
    prims[1] = { { 70, 25 }, { 9, 8 }, { 0.1, 0.6, 0.9 }, 0.25 };
    const int w = 12, h = twoD ? 5 : 1;
    const std::array<double, 2> vr{ 0, 100 }, gr{ 0, 40 };
    const std::vector<double> weights = randomWeights(static_cast<size_t>(w) * h * 4, 11);
    auto pack = [](const std::vector<GaussianPrimitive>& p)
    {
      std::vector<double> x;
      for (const auto& g : p)
        x.insert(x.end(),
          { g.mean[0], g.mean[1], g.stddev[0], g.stddev[1], g.rgb[0], g.rgb[1], g.rgb[2],
            g.opacity });
      return x;
    };
    auto unpack = [](const std::vector<double>& x)
    {
      std::vector<GaussianPrimitive> p(x.size() / 8);
      for (size_t i = 0; i < p.size(); ++i)
      {
        const double* q = &x[8 * i];
        p[i] = { { q[0], q[1] }, { q[2], q[3] }, { q[4], q[5], q[6] }, q[7] };
      }
      return p;
    };
    auto f = [&](const std::vector<double>& x)
    {
      std::vector<float> rgba;
      if (twoD)
        rgba = rasterize2D(unpack(x), vr, gr, w, h).rgba;
      else
        rgba = rasterize1D(unpack(x), vr[0], vr[1], w).rgba;
      double L = 0;
      for (size_t i = 0; i < rgba.size(); ++i)
        L += weights[i] * rgba[i];
      return L;
    };
    std::vector<GaussianPrimitiveGradient> grads;
    rasterizeAdjoint(prims, twoD, vr, gr, w, h, weights, grads);
    std::vector<double> g;
    for (const auto& q : grads)
      g.insert(g.end(),
        { q.mean[0], twoD ? q.mean[1] : 0.0, q.stddev[0], twoD ? q.stddev[1] : 0.0, q.rgb[0],
          q.rgb[1], q.rgb[2], q.opacity });
    // rasterize*D store float tables: finite differences need a larger step and tolerance
    auto fd = [&](const std::vector<double>& x) { return f(x); };
    std::vector<double> x = pack(prims);
    for (size_t i = 0; i < x.size(); ++i)
    {
      if (!twoD && (i % 8 == 1 || i % 8 == 3))
        continue;
      std::vector<double> xp = x, xm = x;
      const double h2 = 1e-3 * std::max(1.0, std::abs(x[i]));
      xp[i] += h2;
      xm[i] -= h2;
      const double numeric = (fd(xp) - fd(xm)) / (2 * h2);
      EXPECT_NEAR(g[i], numeric, 2e-3 * std::max(1.0, std::abs(numeric)))
        << "parameter " << i << " 2D " << twoD;
    }
  }
}

// The 1D renderer's gradient w.r.t. the table of a weighted sum of the image at `view`, checked
// against finite differences (termination off: the loss is smooth in the table); returned.
namespace
{
std::vector<double> checkRenderer1D(const Volume& vol, const View& view, const char* what)
{
  const DifferentiableRendererT<double> renderer(vol);
  RenderOptions opt;
  opt.terminationOpacity = 2.0;
  const int width = 16;
  const auto range = vol.range();
  const std::vector<double> table = randomTable(width, 0.01, 0.3, 5);
  const std::vector<double> weights =
    randomWeights(static_cast<size_t>(view.width) * view.height * 4, 9);
  auto loss = [&](const std::vector<double>& t)
  {
    std::vector<double> rgba;
    std::vector<RayRecord> rec;
    renderer.forward(t.data(), width, range[0], range[1], view, opt, {}, rgba, rec);
    double L = 0;
    for (size_t i = 0; i < rgba.size(); ++i)
      L += weights[i] * rgba[i];
    return L;
  };
  std::vector<double> rgba, grad(table.size(), 0.0);
  std::vector<RayRecord> rec;
  renderer.forward(table.data(), width, range[0], range[1], view, opt, {}, rgba, rec);
  renderer.backward(table.data(), width, range[0], range[1], view, opt, {}, rec, weights, grad);
  checkGradient(loss, table, grad, 6, what);
  return grad;
}
} // namespace

TEST(DifferentiableRenderer, BackwardMatchesFiniteDifferences1D)
{
  const Volume vol = testVolume();
  checkRenderer1D(vol, testView(vol), "renderer 1D");
}

// Shade on: the lighting scales the table colour per sample (and the specular term adds); the
// adjoint carries the scale into the colour entries. ParaView's defaults (the clamp at 1 cuts
// some samples) and a dimmer diffuse with specular.
TEST(DifferentiableRenderer, BackwardMatchesFiniteDifferencesShade)
{
  const Volume vol = testVolume();
  const std::vector<double> unlit = checkRenderer1D(vol, testView(vol), "renderer 1D");
  for (const Lighting& lighting :
    { Lighting{ true, 0, 1, 0, 100 }, Lighting{ true, 0, 0.5, 0.1, 20 } })
  {
    View view = testView(vol);
    view.lighting = lighting;
    const std::vector<double> lit = checkRenderer1D(vol, view, "renderer 1D, Shade on");
    double diff = 0; // the lighting changes the colour gradient
    for (size_t i = 0; i < lit.size(); ++i)
      diff = std::max(diff, std::abs(lit[i] - unlit[i]));
    EXPECT_GT(diff, 1e-3) << "specular " << lighting.specular;
  }
}

// 2D tables, unlit and Shade on (ParaView does not clamp the lit colour of 2D tables: the
// colour gradient is scaled by Diffuse x the light sum everywhere light reaches).
TEST(DifferentiableRenderer, BackwardMatchesFiniteDifferences2D)
{
  const Volume vol = testVolume();
  const DifferentiableRendererT<double> renderer(vol);
  RenderOptions opt;
  opt.terminationOpacity = 2.0;
  const int w = 8, h = 6;
  const std::array<double, 2> vr{ vol.range()[0], vol.range()[1] }, gr{ 0.0, 40.0 };
  const std::vector<double> table = randomTable(w * h, 0.01, 0.3, 6);
  for (const Lighting& lighting :
    { Lighting{}, Lighting{ true, 0, 1, 0, 100 }, Lighting{ true, 0, 0.5, 0.1, 20 } })
  {
    View view = testView(vol, 6, 5);
    view.lighting = lighting;
    const std::vector<double> weights =
      randomWeights(static_cast<size_t>(view.width) * view.height * 4, 10);
    auto loss = [&](const std::vector<double>& t)
    {
      std::vector<double> rgba;
      std::vector<RayRecord> rec;
      renderer.forward2D(t.data(), w, h, vr, gr, view, opt, {}, rgba, rec);
      double L = 0;
      for (size_t i = 0; i < rgba.size(); ++i)
        L += weights[i] * rgba[i];
      return L;
    };
    std::vector<double> rgba, grad(table.size(), 0.0);
    std::vector<RayRecord> rec;
    renderer.forward2D(table.data(), w, h, vr, gr, view, opt, {}, rgba, rec);
    renderer.backward2D(table.data(), w, h, vr, gr, view, opt, {}, rec, weights, grad);
    checkGradient(loss, table, grad, 6, lighting.shade ? "renderer 2D, Shade on" : "renderer 2D");
  }
}

// The float renderer's 2D forward pass against RayCaster's 2D render (the same per-sample
// gradient axis), unlit and lit.
TEST(DifferentiableRenderer, FloatForward2DMatchesRayCaster)
{
  const Volume vol = testVolume();
  const DifferentiableRenderer renderer(vol);
  TransferTable2D table;
  table.valueRange = { vol.range()[0], vol.range()[1] };
  table.gradientRange = { 0.0, 40.0 };
  table.width = 8;
  table.height = 6;
  const std::vector<double> entries = randomTable(table.width * table.height, 0.05, 0.6, 14);
  table.rgba.assign(entries.begin(), entries.end());
  for (const Lighting& lighting : { Lighting{}, Lighting{ true, 0, 0.7, 0.5, 30 } })
  {
    View view = testView(vol, 32, 24);
    view.lighting = lighting;
    const Image fast = renderer.caster().render(table, view);
    std::vector<float> rgba;
    std::vector<RayRecord> rec;
    renderer.forward2D(table.rgba.data(), table.width, table.height, table.valueRange,
      table.gradientRange, view, {}, {}, rgba, rec);
    double alpha = 0;
    for (size_t i = 0; i < rgba.size(); ++i)
    {
      ASSERT_NEAR(rgba[i], fast.pixels[i], kForwardTol) << i << " shade " << lighting.shade;
      alpha += i % 4 == 3 ? rgba[i] : 0.0;
    }
    EXPECT_GT(alpha, 1.0);
  }
}

// High opacities and early termination: the inversion runs close to its guard. Unlit, and
// Shade on (ParaView's defaults, and a dimmer diffuse with specular): the reference lights each
// stored sample and scales its colour gradient by Diffuse x the light sum itself.
TEST(DifferentiableRenderer, InvertedCompositingMatchesStoredReverseMode)
{
  const Volume vol = testVolume();
  const DifferentiableRendererT<double> renderer(vol);
  RenderOptions opt;
  const int width = 12;
  const auto range = vol.range();
  const std::vector<double> table = randomTable(width, 0.5, 0.999, 8);
  for (const Lighting& lighting :
    { Lighting{}, Lighting{ true, 0, 1, 0, 100 }, Lighting{ true, 0, 0.5, 0.3, 20 } })
  {
    View view = testView(vol, 9, 7);
    view.lighting = lighting;
    const std::vector<double> weights =
      randomWeights(static_cast<size_t>(view.width) * view.height * 4, 12);
    std::vector<double> rgba, grad(table.size(), 0.0);
    std::vector<RayRecord> rec;
    renderer.forward(table.data(), width, range[0], range[1], view, opt, {}, rgba, rec);
    renderer.backward(table.data(), width, range[0], range[1], view, opt, {}, rec, weights, grad);
    const auto ref = reference::referenceGradient(vol, table, width, range[0], range[1], view,
      renderer.caster().defaultSampleDistance(), renderer.caster().defaultOpacityUnitDistance(),
      opt.sampleOffset, opt.terminationOpacity, weights);
    double scale = 0;
    for (double g : ref)
      scale = std::max(scale, std::abs(g));
    ASSERT_GT(scale, 0.0);
    for (size_t i = 0; i < grad.size(); ++i)
    {
      // lit: the light kit's directions and colours are floats (as ParaView's uniforms), the
      // reference's doubles: agreement to float precision
      EXPECT_NEAR(grad[i], ref[i], (lighting.shade ? 1e-6 : kExactTol) * scale)
        << "entry " << i / 4 << " channel " << i % 4 << " shade " << lighting.shade << " specular "
        << lighting.specular;
    }
  }
}

TEST(DifferentiableRenderer, FloatForwardMatchesRayCaster)
{
  const Volume vol = testVolume();
  const DifferentiableRenderer renderer(vol);
  const View view = testView(vol, 32, 24);
  TransferFunction1D tf;
  tf.color = { { -10, 0.1, 0.2, 0.9 }, { 50, 0.9, 0.5, 0.1 }, { 120, 1, 1, 1 } };
  tf.opacity = { { -10, 0 }, { 40, 0.05 }, { 90, 0.6 }, { 120, 0.9 } };
  const TransferTable1D table = renderer.caster().paraviewTable(tf);
  const Image fast = renderer.caster().render(table, view);
  std::vector<float> rgba;
  std::vector<RayRecord> rec;
  renderer.forward(table.rgba.data(), table.width, table.min, table.max, view, {}, {}, rgba, rec);
  for (size_t i = 0; i < rgba.size(); ++i)
  {
    ASSERT_NEAR(rgba[i], fast.pixels[i], kForwardTol) << i;
  }
}

TEST(DifferentiableRenderer, FloatForwardMatchesRayCasterShade)
{
  const Volume vol = testVolume();
  const DifferentiableRenderer renderer(vol);
  TransferFunction1D tf;
  tf.color = { { -10, 0.1, 0.2, 0.9 }, { 50, 0.9, 0.5, 0.1 }, { 120, 1, 1, 1 } };
  tf.opacity = { { -10, 0 }, { 40, 0.05 }, { 90, 0.6 }, { 120, 0.9 } };
  const TransferTable1D table = renderer.caster().paraviewTable(tf);
  for (const Lighting& lighting :
    { Lighting{ true, 0, 1, 0, 100 }, Lighting{ true, 0, 0.7, 0.5, 30 } })
  {
    View view = testView(vol, 32, 24);
    view.lighting = lighting;
    const Image fast = renderer.caster().render(table, view);
    std::vector<float> rgba;
    std::vector<RayRecord> rec;
    renderer.forward(table.rgba.data(), table.width, table.min, table.max, view, {}, {}, rgba, rec);
    for (size_t i = 0; i < rgba.size(); ++i)
    {
      ASSERT_NEAR(rgba[i], fast.pixels[i], kForwardTol) << i << " specular " << lighting.specular;
    }
  }
}

TEST(DifferentiableRenderer, StoredSamplesGiveTheReplaysGradients)
{
  // The float renderer's forward pass keeps each sample's interpolated value(s) (and, Shade
  // on, its light sums) in the ray records and the backward pass reads them instead of
  // interpolating (and lighting) again. Compared, 1D and 2D, unlit and lit, early termination
  // on: the gradients from stored values against those from the same records emptied of them
  // (re-interpolation): equal bit for bit; and the float gradients against the double
  // renderer's (which always re-interpolates): relative 1e-4 of the largest. Lit: ParaView's
  // default coefficients and with Specular (the forward pass lights a batch's samples together,
  // the replay one by one: the same operations per sample).
  const Volume vol = testVolume();
  const DifferentiableRenderer renderer(vol);
  const DifferentiableRendererT<double> exact(vol);
  for (const int lighting : { 0, 1, 2 })
  {
    const bool lit = lighting > 0;
    View view = testView(vol, 16, 12);
    view.lighting.shade = lit;
    if (lighting == 2)
    {
      view.lighting.specular = 0.5;
      view.lighting.specularPower = 30;
    }
    RenderOptions opt;
    opt.threads = 2; // bit for bit: each worker sums the same rays in the same order
    const std::vector<double> weights =
      randomWeights(static_cast<size_t>(view.width) * view.height * 4, 22);
    const std::vector<float> weightsF(weights.begin(), weights.end());
    const std::array<double, 2> vr{ vol.range()[0], vol.range()[1] }, gr{ 0.0, 40.0 };
    for (const bool twoD : { false, true })
    {
      const int w = twoD ? 8 : 16, h = twoD ? 6 : 1;
      const std::vector<double> table = randomTable(w * h, 0.05, 0.9, 21);
      const std::vector<float> tableF(table.begin(), table.end());
      auto run = [&](auto& r, const auto& t, const auto& dRGBA, auto& rec, auto& grad, bool fwd)
      {
        std::vector<std::decay_t<decltype(t[0])>> rgba;
        if (fwd && twoD)
          r.forward2D(t.data(), w, h, vr, gr, view, opt, {}, rgba, rec);
        else if (fwd)
          r.forward(t.data(), w, vr[0], vr[1], view, opt, {}, rgba, rec);
        if (twoD)
          r.backward2D(t.data(), w, h, vr, gr, view, opt, {}, rec, dRGBA, grad);
        else
          r.backward(t.data(), w, vr[0], vr[1], view, opt, {}, rec, dRGBA, grad);
      };
      std::vector<RayRecord> rec;
      std::vector<float> stored(table.size(), 0.0f), replayed(table.size(), 0.0f);
      run(renderer, tableF, weightsF, rec, stored, true);
      int hits = 0;
      for (const auto& r : rec)
      {
        if (r.lastSample >= 0)
        {
          ++hits;
          ASSERT_EQ(r.samples.size(),
            static_cast<size_t>(r.lastSample + 1) * ((twoD ? 2 : 1) + (lit ? kLightFloats : 0)));
        }
        else
        {
          ASSERT_TRUE(r.samples.empty());
        }
      }
      ASSERT_GT(hits, 20);
      std::vector<RayRecord> bare = rec;
      for (auto& r : bare)
        r.samples.clear();
      run(renderer, tableF, weightsF, bare, replayed, false);
      for (size_t i = 0; i < stored.size(); ++i)
      {
        ASSERT_EQ(stored[i], replayed[i])
          << "2D " << twoD << " lit " << lit << " entry " << i / 4 << " channel " << i % 4;
      }
      std::vector<RayRecord> recD;
      std::vector<double> gradD(table.size(), 0.0);
      run(exact, table, weights, recD, gradD, true);
      double scale = 0;
      for (double g : gradD)
        scale = std::max(scale, std::abs(g));
      ASSERT_GT(scale, 0.0);
      for (size_t i = 0; i < stored.size(); ++i)
      {
        EXPECT_NEAR(stored[i], gradD[i], 1e-4 * scale)
          << "2D " << twoD << " lit " << lit << " entry " << i / 4;
      }
    }
  }
}

// The backward pass deals its chunks of rays to the workers in a fixed way, so its gradient is
// the same from run to run for a given thread count (a fit, a match, a carried look repeat
// themselves): two threads, 48 chunks of rays, 1D and 2D, unlit and lit, five runs equal bit for
// bit.
TEST(DifferentiableRenderer, BackwardIsTheSameEveryRun)
{
  const Volume vol = testVolume();
  const DifferentiableRenderer renderer(vol);
  for (const bool lit : { false, true })
    for (const bool twoD : { false, true })
    {
      View view = testView(vol, 64, 48);
      view.lighting.shade = lit;
      RenderOptions opt;
      opt.threads = 2;
      const std::vector<double> weights =
        randomWeights(static_cast<size_t>(view.width) * view.height * 4, 31);
      const std::vector<float> weightsF(weights.begin(), weights.end());
      const std::array<double, 2> vr{ vol.range()[0], vol.range()[1] }, gr{ 0.0, 40.0 };
      const int w = twoD ? 8 : 16, h = twoD ? 6 : 1;
      const std::vector<double> table = randomTable(w * h, 0.02, 0.4, 32);
      const std::vector<float> tableF(table.begin(), table.end());
      std::vector<float> first;
      for (int run = 0; run < 5; ++run)
      {
        std::vector<float> rgba, grad(tableF.size(), 0.0f);
        std::vector<RayRecord> rec;
        if (twoD)
        {
          renderer.forward2D(tableF.data(), w, h, vr, gr, view, opt, {}, rgba, rec);
          renderer.backward2D(tableF.data(), w, h, vr, gr, view, opt, {}, rec, weightsF, grad);
        }
        else
        {
          renderer.forward(tableF.data(), w, vr[0], vr[1], view, opt, {}, rgba, rec);
          renderer.backward(tableF.data(), w, vr[0], vr[1], view, opt, {}, rec, weightsF, grad);
        }
        if (run == 0)
        {
          first = grad;
          double largest = 0;
          for (float g : grad)
            largest = std::max(largest, std::abs(static_cast<double>(g)));
          ASSERT_GT(largest, 0.0);
        }
        else
          ASSERT_EQ(grad, first) << "run " << run << " 2D " << twoD << " lit " << lit;
      }
    }
}
