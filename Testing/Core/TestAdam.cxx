// TestAdam.cxx: ddg::Adam and the logistic functions (Core/Numerics).
//
// Compared: Adam's first three steps on two parameters with their own learning rates against
// the update written out by hand (values computed independently in double precision, 1e-15);
// against a naive re-implementation of the bias-corrected update (exact equality, so the fits
// that use Adam keep their numbers); convergence on a badly scaled quadratic (|x - x*| < 1e-3
// after 2000 steps); sigmoid/logit round trip (1e-12) and their clamping; misuse throws.
#include "Numerics/Adam.h"
#include "Numerics/Logistic.h"

#include "Common/Error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace ddg;

TEST(Adam, FirstStepsMatchTheHandComputedUpdate)
{
  // theta0 = (1, -2), lr = (0.1, 0.05), gradients (0.5, -3), (-0.2, -1), (0, 4).
  // Step 1, parameter 0: m = 0.05, v = 0.00025, m^ = 0.5, v^ = 0.25:
  //   theta = 1 - 0.1 * 0.5 / (0.5 + 1e-8) = 0.900000002 (to 1e-16).
  // Step 2, parameter 0: m = 0.9 * 0.05 + 0.1 * -0.2 = 0.025, v = 0.999 * 0.00025 + 0.001 * 0.04
  //   = 0.00028975, m^ = 0.025 / 0.19, v^ = 0.00028975 / 0.001999:
  //   theta = 0.900000002 - 0.1 * 0.131578947... / (0.380719... + 1e-8) = 0.86543941811651...
  std::vector<double> theta{ 1.0, -2.0 };
  const std::vector<double> rates{ 0.1, 0.05 };
  const std::vector<std::vector<double>> gradients{ { 0.5, -3.0 }, { -0.2, -1.0 }, { 0.0, 4.0 } };
  const double expected[3][2] = { { 0.900000002, -1.9500000001666666 },
    { 0.8654394181165108, -1.9064468028252646 }, { 0.8387239867651465, -1.9106452718357234 } };
  Adam adam;
  for (int t = 0; t < 3; ++t)
  {
    adam.step(theta, gradients[t], rates);
    EXPECT_EQ(adam.steps(), t + 1);
    for (int i = 0; i < 2; ++i)
      EXPECT_NEAR(theta[i], expected[t][i], 1e-15) << "step " << t + 1 << " parameter " << i;
  }
  // the first step moves every parameter by its learning rate (m^ / sqrt(v^) = sign(g))
  std::vector<double> one{ 0.0 };
  Adam fresh;
  fresh.step(one, { -7.0 }, 0.25);
  EXPECT_NEAR(one[0], 0.25, 1e-9);
}

TEST(Adam, EqualsTheNaiveUpdateExactly)
{
  // The fits' recorded figures depend on the order of operations: the class must compute
  // exactly what the hand-rolled loops did.
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  const size_t n = 17;
  const AdamOptions options{ 0.8, 0.99, 1e-12 };
  std::vector<double> theta(n), naive(n), m(n, 0.0), v(n, 0.0), rates(n);
  for (size_t i = 0; i < n; ++i)
  {
    theta[i] = naive[i] = normal(rng);
    rates[i] = 0.01 * (1 + i % 3);
  }
  Adam adam(options, n);
  for (int it = 1; it <= 50; ++it)
  {
    std::vector<double> g(n);
    for (auto& x : g)
      x = normal(rng);
    adam.step(theta, g, rates);
    for (size_t i = 0; i < n; ++i)
    {
      m[i] = options.beta1 * m[i] + (1 - options.beta1) * g[i];
      v[i] = options.beta2 * v[i] + (1 - options.beta2) * g[i] * g[i];
      const double mh = m[i] / (1 - std::pow(options.beta1, it)),
                   vh = v[i] / (1 - std::pow(options.beta2, it));
      naive[i] -= rates[i] * mh / (std::sqrt(vh) + options.epsilon);
    }
    for (size_t i = 0; i < n; ++i)
      ASSERT_EQ(theta[i], naive[i]) << "step " << it << " parameter " << i;
  }
  EXPECT_EQ(adam.firstMoment(), m);
  EXPECT_EQ(adam.secondMoment(), v);
}

TEST(Adam, MinimisesABadlyScaledQuadratic)
{
  // f(x) = sum_i a_i (x_i - c_i)^2 with curvatures over 6 orders of magnitude: Adam's steps
  // do not depend on the gradient's scale.
  const std::vector<double> a{ 1e-3, 1.0, 1e3 }, c{ 3.0, -1.0, 0.5 };
  std::vector<double> x{ 0.0, 0.0, 0.0 }, g(3);
  Adam adam;
  for (int it = 0; it < 2000; ++it)
  {
    const double lr = 0.05 * (1.0 - it / 2000.0) + 1e-4;
    for (int i = 0; i < 3; ++i)
      g[i] = 2 * a[i] * (x[i] - c[i]);
    adam.step(x, g, lr);
  }
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(x[i], c[i], 1e-3) << "parameter " << i;
}

TEST(Adam, RefusesMismatchedSizes)
{
  std::vector<double> theta(3, 0.0);
  Adam adam;
  EXPECT_THROW(adam.step(theta, std::vector<double>(2), 0.1), Error);
  EXPECT_THROW(adam.step(theta, std::vector<double>(3), std::vector<double>(2)), Error);
  adam.step(theta, std::vector<double>(3, 1.0), 0.1);
  std::vector<double> more(4, 0.0);
  EXPECT_THROW(adam.step(more, std::vector<double>(4), 0.1), Error);
  EXPECT_THROW(Adam(AdamOptions{ 1.0, 0.999, 1e-8 }), Error);
  // a zero gradient does not move the parameters
  const auto before = theta;
  Adam still;
  still.step(theta, std::vector<double>(3, 0.0), 0.1);
  EXPECT_EQ(theta, before);
}

TEST(Logistic, SigmoidAndLogitAreInverseAndClamped)
{
  for (double p : { 0.001, 0.02, 0.5, 0.7, 0.999 })
  {
    EXPECT_NEAR(sigmoid(logit(p, 1e-6)), p, 1e-12);
    EXPECT_NEAR(sigmoid(logit(p, 1e-4)), p, 1e-12);
  }
  EXPECT_EQ(sigmoid(0.0), 0.5);
  EXPECT_NEAR(sigmoid(-3.0), 1.0 / (1.0 + std::exp(3.0)), 1e-16);
  // 0 and 1 map to the margin's logit, not to infinity
  EXPECT_NEAR(logit(0.0, 1e-6), std::log(1e-6 / (1 - 1e-6)), 1e-12);
  EXPECT_NEAR(logit(1.0, 1e-4), -std::log(1e-4 / (1 - 1e-4)), 1e-12);
  EXPECT_NEAR(sigmoid(logit(0.0, 1e-4)), 1e-4, 1e-12);
}
