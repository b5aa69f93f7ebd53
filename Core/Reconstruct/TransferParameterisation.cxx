// TransferParameterisation.cxx: free bins (logits, smoothness prior) and Gaussian primitives
// (decode, rasterize, chain rule through rasterizeAdjoint).
#include "Reconstruct/TransferParameterisation.h"

#include "Common/Error.h"
#include "Numerics/Logistic.h"
#include "TransferFunction/TransferFunction2D.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ddg
{
namespace
{
// Starting values are clamped to [kLogitMargin, 1 - kLogitMargin] before the logit.
constexpr double kLogitMargin = 1e-6;
} // namespace

void TransferParameterisation::addPrior(
  const std::vector<double>&, double&, std::vector<double>&) const
{
}

std::vector<double> TransferParameterisation::learningRates(double base) const
{
  return std::vector<double>(size(), base);
}

// --- free bins ---------------------------------------------------------------------------

FreeBins::FreeBins(int bins, int gradientBins, double smoothness)
  : Smoothness(smoothness)
{
  const std::size_t entries = static_cast<std::size_t>(bins) * gradientBins;
  Start.resize(4 * entries);
  for (std::size_t b = 0; b < entries; ++b)
  {
    const double grey[4] = { 0.5, 0.5, 0.5, 0.02 };
    for (int c = 0; c < 4; ++c)
      Start[4 * b + c] = logit(grey[c], kLogitMargin);
  }
  for (int g = 0; g < gradientBins; ++g)
    for (int b = 0; b < bins; ++b)
    {
      const std::size_t i = static_cast<std::size_t>(g) * bins + b;
      if (b + 1 < bins)
        Neighbours.push_back({ i, i + 1 });
      if (g + 1 < gradientBins)
        Neighbours.push_back({ i, i + bins });
    }
}

FreeBins FreeBins::oneD(int bins, std::array<double, 2> range, double smoothness,
  const std::optional<TransferTable1D>& initial)
{
  FreeBins p(bins, 1, smoothness);
  if (initial)
  {
    for (int b = 0; b < bins; ++b)
    {
      const double x = range[0] + static_cast<double>(b) * (range[1] - range[0]) / (bins - 1);
      const auto v = initial->lookup(x);
      for (int c = 0; c < 4; ++c)
        p.Start[4 * static_cast<std::size_t>(b) + c] = logit(v[c], kLogitMargin);
    }
  }
  return p;
}

FreeBins FreeBins::twoD(int bins, int gradientBins, double smoothness)
{
  return FreeBins(bins, gradientBins, smoothness);
}

void FreeBins::forward(const std::vector<double>& theta, std::vector<double>& values)
{
  values.resize(theta.size());
  for (std::size_t i = 0; i < theta.size(); ++i)
    values[i] = sigmoid(theta[i]);
}

void FreeBins::backward(const std::vector<double>& values, const std::vector<double>& dL_dValues,
  std::vector<double>& dL_dTheta) const
{
  // values = sigmoid(theta)
  dL_dTheta.resize(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    dL_dTheta[i] = dL_dValues[i] * values[i] * (1.0 - values[i]);
}

void FreeBins::addPrior(
  const std::vector<double>& values, double& loss, std::vector<double>& dL_dValues) const
{
  if (!(Smoothness > 0) || Neighbours.empty())
    return;
  const double k = Smoothness / static_cast<double>(Neighbours.size());
  for (const auto& [a, b] : Neighbours)
    for (int c = 0; c < 4; ++c)
    {
      const double d = values[4 * b + c] - values[4 * a + c];
      loss += k * d * d;
      dL_dValues[4 * b + c] += 2 * k * d;
      dL_dValues[4 * a + c] -= 2 * k * d;
    }
}

// --- Gaussian primitives -----------------------------------------------------------------

GaussianPrimitiveParameters::GaussianPrimitiveParameters(int count, bool twoD,
  std::array<double, 2> valueRange, std::array<double, 2> gradientRange, int bins, int gradientBins)
  : Count(count)
  , TwoD(twoD)
  , ValueRange(valueRange)
  , GradientRange(gradientRange)
  , Bins(bins)
  , GradientBins(twoD ? gradientBins : 1)
  , Lo{ valueRange[0], gradientRange[0] }
  , Span{ valueRange[1] - valueRange[0], gradientRange[1] - gradientRange[0] }
{
}

std::size_t GaussianPrimitiveParameters::size() const
{
  return static_cast<std::size_t>(Count) * kPerPrimitive;
}

void GaussianPrimitiveParameters::startFrom(const std::vector<GaussianPrimitive>& primitives)
{
  if (static_cast<int>(primitives.size()) != Count)
    throw Error("the parametric fit starts from " + std::to_string(Count) + " primitives, not " +
      std::to_string(primitives.size()));
  Start.assign(size(), 0.0);
  for (int k = 0; k < Count; ++k)
  {
    const GaussianPrimitive& g = primitives[static_cast<std::size_t>(k)];
    double* t = &Start[static_cast<std::size_t>(k) * kPerPrimitive];
    for (int a = 0; a < 2; ++a)
    {
      const bool axis = a == 0 || TwoD; // 1D: the gradient-axis slots as initial() sets them
      t[a] = axis ? (g.mean[a] - Lo[a]) / Span[a] : 0.5;
      t[2 + a] = axis ? std::log(std::max(g.stddev[a] / Span[a], 1e-5)) : std::log(0.5);
    }
    for (int c = 0; c < 3; ++c)
      t[4 + c] = logit(g.rgb[c], kLogitMargin);
    t[7] = logit(g.opacity, kLogitMargin);
  }
}

std::vector<double> GaussianPrimitiveParameters::initial() const
{
  if (!Start.empty())
    return Start;
  std::vector<double> theta(size(), 0.0);
  for (int k = 0; k < Count; ++k)
  {
    double* t = &theta[static_cast<std::size_t>(k) * kPerPrimitive];
    t[0] = (k + 0.5) / Count;
    t[1] = 0.5;
    t[2] = std::log(0.5 / Count);
    t[3] = std::log(0.5);
    t[4] = t[5] = t[6] = logit(0.5, kLogitMargin);
    t[7] = logit(0.05, kLogitMargin);
  }
  return theta;
}

std::vector<GaussianPrimitive> GaussianPrimitiveParameters::decode(
  const std::vector<double>& theta) const
{
  std::vector<GaussianPrimitive> out(theta.size() / kPerPrimitive);
  for (std::size_t k = 0; k < out.size(); ++k)
  {
    const double* t = &theta[k * kPerPrimitive];
    for (int a = 0; a < 2; ++a)
    {
      out[k].mean[a] = Lo[a] + t[a] * Span[a];
      out[k].stddev[a] = std::exp(std::clamp(t[2 + a], -12.0, 3.0)) * Span[a];
    }
    for (int c = 0; c < 3; ++c)
      out[k].rgb[c] = sigmoid(t[4 + c]);
    out[k].opacity = sigmoid(t[7]);
  }
  return out;
}

void GaussianPrimitiveParameters::forward(
  const std::vector<double>& theta, std::vector<double>& values)
{
  Current = decode(theta);
  const std::vector<float> raster = TwoD
    ? rasterize2D(Current, ValueRange, GradientRange, Bins, GradientBins).rgba
    : rasterize1D(Current, ValueRange[0], ValueRange[1], Bins).rgba;
  values.resize(4 * static_cast<std::size_t>(Bins) * GradientBins);
  std::copy(raster.begin(), raster.end(), values.begin());
}

void GaussianPrimitiveParameters::backward(const std::vector<double>&,
  const std::vector<double>& dL_dValues, std::vector<double>& dL_dTheta) const
{
  std::vector<GaussianPrimitiveGradient> g;
  rasterizeAdjoint(Current, TwoD, ValueRange, GradientRange, Bins, GradientBins, dL_dValues, g);
  const auto& p = Current;
  dL_dTheta.assign(size(), 0.0); // 1D: the gradient-axis slots get no gradient
  for (std::size_t k = 0; k < p.size(); ++k)
  {
    double* d = &dL_dTheta[k * kPerPrimitive];
    for (int a = 0; a < (TwoD ? 2 : 1); ++a)
    {
      // mean = lo + t span;  stddev = exp(t) span
      d[a] = g[k].mean[a] * Span[a];
      d[2 + a] = g[k].stddev[a] * p[k].stddev[a];
    }
    // rgb = sigmoid(t), opacity = sigmoid(t)
    for (int c = 0; c < 3; ++c)
      d[4 + c] = g[k].rgb[c] * p[k].rgb[c] * (1 - p[k].rgb[c]);
    d[7] = g[k].opacity * p[k].opacity * (1 - p[k].opacity);
  }
}

std::vector<double> GaussianPrimitiveParameters::learningRates(double base) const
{
  std::vector<double> rates(size());
  for (std::size_t i = 0; i < rates.size(); ++i)
  {
    const std::size_t slot = i % kPerPrimitive;
    rates[i] = base * (slot < 2 ? 0.1 : slot < 4 ? 0.25 : 1.0);
  }
  return rates;
}

OpacityFloor::OpacityFloor(std::unique_ptr<TransferParameterisation> inner, int bins,
  std::array<double, 2> range, double lowest)
  : Inner(std::move(inner))
{
  if (!Inner || bins < 2)
    throw Error("an opacity floor needs a parameterisation and at least 2 bins");
  Transparent.resize(static_cast<size_t>(bins));
  for (int b = 0; b < bins; ++b)
    Transparent[static_cast<size_t>(b)] =
      range[0] + static_cast<double>(b) * (range[1] - range[0]) / (bins - 1) < lowest;
}

void OpacityFloor::forward(const std::vector<double>& theta, std::vector<double>& values)
{
  Inner->forward(theta, InnerValues);
  if (InnerValues.size() != 4 * Transparent.size())
    throw Error("an opacity floor is for 1D tables of its bins");
  values = InnerValues;
  for (size_t b = 0; b < Transparent.size(); ++b)
    if (Transparent[b])
      values[4 * b + 3] = 0;
}

void OpacityFloor::backward(const std::vector<double>&, const std::vector<double>& dL_dValues,
  std::vector<double>& dL_dTheta) const
{
  std::vector<double> d = dL_dValues;
  for (size_t b = 0; b < Transparent.size(); ++b)
    if (Transparent[b])
      d[4 * b + 3] = 0;
  Inner->backward(InnerValues, d, dL_dTheta);
}

} // namespace ddg
