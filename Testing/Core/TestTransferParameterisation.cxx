// TestTransferParameterisation.cxx: the reconstruction's parameterisations (free bins in 1D and
// 2D, Gaussian primitives in 1D and 2D).
//
// Compared: backward (dL/dtheta from dL/dvalues) against central finite differences in double
// precision of L(theta) = sum_i w_i values_i(theta) with random weights w, at the starting
// parameters and at a random perturbation of them (relative tolerance kRelTol on the largest
// gradient, h = kStep; the primitives rasterize into float tables: kPrimitiveRelTol,
// kPrimitiveStep); the smoothness prior's gradient against finite differences of its loss;
// the starting TF (grey, opacity 0.02; the initial 1D TF; primitives spread over the range).
#include "Reconstruct/TransferParameterisation.h"

#include "Common/Error.h"
#include "TransferFunction/TransferFunction1D.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace ddg;

namespace
{
constexpr double kStep = 1e-6;
constexpr double kRelTol = 1e-5;
// The primitives rasterize into float tables: a larger step and tolerance.
constexpr double kPrimitiveStep = 1e-3;
constexpr double kPrimitiveRelTol = 2e-3;

double weighted(
  TransferParameterisation& p, const std::vector<double>& theta, const std::vector<double>& w)
{
  std::vector<double> v;
  p.forward(theta, v);
  double L = 0;
  for (size_t i = 0; i < v.size(); ++i)
    L += w[i] * v[i];
  return L;
}

void checkBackward(TransferParameterisation& p, const std::vector<double>& theta, unsigned seed,
  double h = kStep, double relTol = kRelTol)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> values;
  p.forward(theta, values);
  std::vector<double> w(values.size());
  for (auto& x : w)
    x = u(rng);
  p.forward(theta, values);
  std::vector<double> grad;
  p.backward(values, w, grad);
  ASSERT_EQ(grad.size(), theta.size());
  std::vector<double> fd(theta.size());
  double scale = 1e-12;
  for (size_t i = 0; i < theta.size(); ++i)
  {
    auto plus = theta, minus = theta;
    plus[i] += h;
    minus[i] -= h;
    fd[i] = (weighted(p, plus, w) - weighted(p, minus, w)) / (2 * h);
    scale = std::max({ scale, std::abs(fd[i]), std::abs(grad[i]) });
  }
  for (size_t i = 0; i < theta.size(); ++i)
    EXPECT_NEAR(grad[i], fd[i], relTol * scale) << "parameter " << i;
}

std::vector<double> perturbed(std::vector<double> theta, unsigned seed, double amount)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, amount);
  for (auto& t : theta)
    t += n(rng);
  return theta;
}
} // namespace

TEST(TransferParameterisation, FreeBinsStartGreyAndPullBackThroughTheSigmoid)
{
  auto p = FreeBins::oneD(6, { 0, 10 }, 0.0);
  ASSERT_EQ(p.size(), 24u);
  std::vector<double> v;
  p.forward(p.initial(), v);
  for (size_t b = 0; b < 6; ++b)
  {
    EXPECT_NEAR(v[4 * b], 0.5, 1e-12);
    EXPECT_NEAR(v[4 * b + 3], 0.02, 1e-12);
  }
  checkBackward(p, p.initial(), 1);
  checkBackward(p, perturbed(p.initial(), 2, 1.0), 3);
  auto q = FreeBins::twoD(5, 3, 0.0);
  ASSERT_EQ(q.size(), 60u);
  checkBackward(q, perturbed(q.initial(), 4, 1.0), 5);
  EXPECT_EQ(p.learningRates(0.2), std::vector<double>(24, 0.2));
  EXPECT_TRUE(p.primitives().empty());
}

TEST(TransferParameterisation, FreeBinsStartFromTheInitialTF)
{
  TransferTable1D initial;
  initial.min = 0;
  initial.max = 10;
  initial.width = 2;
  initial.rgba = { 0, 0.2f, 1, 0, 1, 0.6f, 0, 1 }; // linear from (0, .2, 1, 0) to (1, .6, 0, 1)
  auto p = FreeBins::oneD(3, { 0, 10 }, 0.0, initial);
  std::vector<double> v;
  p.forward(p.initial(), v);
  const double expected[3][4] = { { 1e-6, 0.2, 1 - 1e-6, 1e-6 }, { 0.5, 0.4, 0.5, 0.5 },
    { 1 - 1e-6, 0.6, 1e-6, 1 - 1e-6 } }; // clamped to [1e-6, 1 - 1e-6]
  for (int b = 0; b < 3; ++b)
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(v[4 * b + c], expected[b][c], 1e-6) << "bin " << b << " channel " << c;
}

TEST(TransferParameterisation, SmoothnessPriorGradientMatchesFiniteDifferences)
{
  for (const bool twoD : { false, true })
  {
    auto p = twoD ? FreeBins::twoD(4, 3, 0.3) : FreeBins::oneD(7, { 0, 1 }, 0.3);
    std::vector<double> values;
    p.forward(perturbed(p.initial(), 6, 1.0), values);
    auto prior = [&](const std::vector<double>& v)
    {
      double L = 0;
      std::vector<double> g(v.size(), 0.0);
      p.addPrior(v, L, g);
      return L;
    };
    double L = 1.0; // accumulates
    std::vector<double> g(values.size(), 0.5);
    p.addPrior(values, L, g);
    EXPECT_NEAR(L - 1.0, prior(values), 1e-15);
    for (size_t i = 0; i < values.size(); ++i)
    {
      auto plus = values, minus = values;
      plus[i] += kStep;
      minus[i] -= kStep;
      EXPECT_NEAR(g[i] - 0.5, (prior(plus) - prior(minus)) / (2 * kStep), 1e-7)
        << (twoD ? "2D" : "1D") << " entry " << i;
    }
  }
  // no prior without smoothness
  auto p = FreeBins::oneD(4, { 0, 1 }, 0.0);
  std::vector<double> v(16, 0.0), g(16, 0.0);
  v[0] = 1;
  double L = 0;
  p.addPrior(v, L, g);
  EXPECT_EQ(L, 0.0);
}

TEST(TransferParameterisation, GaussianPrimitivesDecodeAndPullBackThroughTheRasterization)
{
  GaussianPrimitiveParameters p(3, false, { 10, 50 }, { 0, 1 }, 32, 1);
  ASSERT_EQ(p.size(), 24u);
  const auto start = p.decode(p.initial());
  ASSERT_EQ(start.size(), 3u);
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_NEAR(start[k].mean[0], 10 + (k + 0.5) / 3 * 40, 1e-12);
    EXPECT_NEAR(start[k].stddev[0], 40 / 6.0, 1e-12);
    EXPECT_NEAR(start[k].opacity, 0.05, 1e-12);
    EXPECT_NEAR(start[k].rgb[1], 0.5, 1e-12);
  }
  const auto rates = p.learningRates(0.2);
  EXPECT_NEAR(rates[0], 0.02, 1e-15); // mean
  EXPECT_NEAR(rates[2], 0.05, 1e-15); // width
  EXPECT_NEAR(rates[13], 0.2, 1e-15); // colour logit of the second primitive
  checkBackward(p, perturbed(p.initial(), 7, 0.05), 8, kPrimitiveStep, kPrimitiveRelTol);
  std::vector<double> v, g;
  p.forward(p.initial(), v);
  EXPECT_EQ(p.primitives().size(), 3u);
  p.backward(v, std::vector<double>(v.size(), 1.0), g);
  EXPECT_EQ(g[1], 0.0); // 1D: the gradient-axis mean and width get no gradient
  EXPECT_EQ(g[3], 0.0);

  GaussianPrimitiveParameters q(2, true, { 0, 1 }, { 0, 2 }, 16, 8);
  checkBackward(q, perturbed(q.initial(), 9, 0.05), 10, kPrimitiveStep, kPrimitiveRelTol);
}

TEST(TransferParameterisation, OpacityFloorHoldsTheAirTransparentAndPullsBackTheRest)
{
  // free bins over [0, 100] under a floor at 30: entries at 0 .. 28.6 (b < 5 of 15) transparent
  const std::array<double, 2> range{ 0, 100 };
  OpacityFloor floor(std::make_unique<FreeBins>(FreeBins::oneD(15, range, 0.0)), 15, range, 30.0);
  const auto theta = perturbed(floor.initial(), 3, 0.5);
  std::vector<double> values;
  floor.forward(theta, values);
  ASSERT_EQ(values.size(), 60u);
  for (int b = 0; b < 15; ++b)
    if (b * 100.0 / 14 < 30.0)
      EXPECT_EQ(values[static_cast<size_t>(4 * b + 3)], 0.0) << "entry " << b;
    else
      EXPECT_GT(values[static_cast<size_t>(4 * b + 3)], 0.0) << "entry " << b;
  checkBackward(floor, theta, 11);
  // and over Gaussian primitives (their rasterization in float)
  OpacityFloor primitives(std::make_unique<GaussianPrimitiveParameters>(
                            3, false, range, std::array<double, 2>{ 0, 1 }, 32, 1),
    32, range, 30.0);
  checkBackward(
    primitives, perturbed(primitives.initial(), 5, 0.3), 13, kPrimitiveStep, kPrimitiveRelTol);
  // a table of another size than its bins is refused
  OpacityFloor wrong(std::make_unique<FreeBins>(FreeBins::oneD(15, range, 0.0)), 16, range, 30.0);
  EXPECT_THROW(wrong.forward(theta, values), Error);
}
