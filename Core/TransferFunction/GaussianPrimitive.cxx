// GaussianPrimitive.cxx: validation and rasterization of Gaussian TF primitives.
#include "TransferFunction/GaussianPrimitive.h"

#include "Common/Error.h"
#include "TransferFunction/TransferFunction2D.h"

#include <cmath>
#include <sstream>

namespace ddg
{
namespace
{

void blend(
  const std::vector<GaussianPrimitive>& primitives, double x, double y, bool twoD, float* out)
{
  double sum = 0, r = 0, g = 0, b = 0;
  for (const auto& p : primitives)
  {
    double e = (x - p.mean[0]) / p.stddev[0];
    double q = e * e;
    if (twoD)
    {
      e = (y - p.mean[1]) / p.stddev[1];
      q += e * e;
    }
    const double w = p.opacity * std::exp(-0.5 * q);
    sum += w;
    r += w * p.rgb[0];
    g += w * p.rgb[1];
    b += w * p.rgb[2];
  }
  if (sum > 0)
  {
    out[0] = static_cast<float>(r / sum);
    out[1] = static_cast<float>(g / sum);
    out[2] = static_cast<float>(b / sum);
  }
  else
  {
    out[0] = out[1] = out[2] = 0.0f;
  }
  out[3] = static_cast<float>(std::min(1.0, sum));
}

} // namespace

void validatePrimitives(const std::vector<GaussianPrimitive>& primitives, bool twoD)
{
  for (size_t i = 0; i < primitives.size(); ++i)
  {
    const auto& p = primitives[i];
    auto bad = [&](const std::string& what)
    {
      std::ostringstream msg;
      msg << "Gaussian primitive " << i << ": " << what;
      throw Error(msg.str());
    };
    for (int a = 0; a < (twoD ? 2 : 1); ++a)
    {
      if (!std::isfinite(p.mean[a]))
        bad("mean is not finite");
      if (!std::isfinite(p.stddev[a]) || p.stddev[a] <= 0)
        bad("stddev must be finite and > 0");
    }
    for (double c : p.rgb)
    {
      if (!std::isfinite(c) || c < 0 || c > 1)
        bad("rgb must lie in [0, 1]");
    }
    if (!std::isfinite(p.opacity) || p.opacity < 0 || p.opacity > 1)
      bad("opacity must lie in [0, 1]");
  }
}

TransferTable1D rasterize1D(
  const std::vector<GaussianPrimitive>& primitives, double min, double max, int width)
{
  validatePrimitives(primitives, false);
  if (width < 2 || !(min < max))
  {
    throw Error("rasterize1D needs width >= 2 and min < max");
  }
  TransferTable1D t;
  t.min = min;
  t.max = max;
  t.width = width;
  t.rgba.resize(static_cast<size_t>(width) * 4);
  for (int i = 0; i < width; ++i)
  {
    blend(primitives, min + i * (max - min) / (width - 1), 0.0, false, &t.rgba[4 * i]);
  }
  return t;
}

TransferTable2D rasterize2D(const std::vector<GaussianPrimitive>& primitives,
  std::array<double, 2> valueRange, std::array<double, 2> gradientRange, int width, int height)
{
  validatePrimitives(primitives, true);
  TransferTable2D t;
  t.valueRange = valueRange;
  t.gradientRange = gradientRange;
  t.width = width;
  t.height = height;
  if (width < 2 || height < 2 || !(valueRange[0] < valueRange[1]) ||
    !(gradientRange[0] < gradientRange[1]))
  {
    throw Error("rasterize2D needs sizes >= 2 and non-empty ranges");
  }
  t.rgba.resize(static_cast<size_t>(width) * height * 4);
  for (int j = 0; j < height; ++j)
  {
    const double g = gradientRange[0] + j * (gradientRange[1] - gradientRange[0]) / (height - 1);
    for (int i = 0; i < width; ++i)
    {
      const double v = valueRange[0] + i * (valueRange[1] - valueRange[0]) / (width - 1);
      blend(primitives, v, g, true, &t.rgba[4 * (static_cast<size_t>(j) * width + i)]);
    }
  }
  return t;
}

void rasterizeAdjoint(const std::vector<GaussianPrimitive>& primitives, bool twoD,
  std::array<double, 2> valueRange, std::array<double, 2> gradientRange, int width, int height,
  const std::vector<double>& dL_dTable, std::vector<GaussianPrimitiveGradient>& gradients)
{
  validatePrimitives(primitives, twoD);
  if (!twoD)
  {
    height = 1;
  }
  if (dL_dTable.size() != static_cast<size_t>(width) * height * 4 || width < 2 ||
    (twoD && height < 2))
  {
    throw Error("rasterizeAdjoint: dL_dTable does not match the table size");
  }
  gradients.assign(primitives.size(), GaussianPrimitiveGradient{});
  std::vector<double> w(primitives.size());
  for (int j = 0; j < height; ++j)
  {
    const double y =
      twoD ? gradientRange[0] + j * (gradientRange[1] - gradientRange[0]) / (height - 1) : 0.0;
    for (int i = 0; i < width; ++i)
    {
      const double x = valueRange[0] + i * (valueRange[1] - valueRange[0]) / (width - 1);
      // forward: w_p, sum, rgb = sum_p w_p c_p / sum, alpha = min(1, sum)
      double sum = 0, rgb[3] = { 0, 0, 0 };
      for (size_t p = 0; p < primitives.size(); ++p)
      {
        const auto& g = primitives[p];
        double q = (x - g.mean[0]) / g.stddev[0];
        q *= q;
        if (twoD)
        {
          const double e = (y - g.mean[1]) / g.stddev[1];
          q += e * e;
        }
        w[p] = g.opacity * std::exp(-0.5 * q);
        sum += w[p];
        for (int c = 0; c < 3; ++c)
          rgb[c] += w[p] * g.rgb[c];
      }
      if (sum <= 0)
      {
        continue;
      }
      for (double& c : rgb)
        c /= sum;
      const double* d = &dL_dTable[4 * (static_cast<size_t>(j) * width + i)];
      for (size_t p = 0; p < primitives.size(); ++p)
      {
        const auto& g = primitives[p];
        auto& out = gradients[p];
        // dL/dw_p through rgb = sum_q w_q c_q / sum and alpha = min(1, sum)
        double dw = sum < 1.0 ? d[3] : 0.0;
        for (int c = 0; c < 3; ++c)
        {
          dw += d[c] * (g.rgb[c] - rgb[c]) / sum;
          out.rgb[c] += d[c] * w[p] / sum;
        }
        if (w[p] == 0.0)
        {
          continue;
        }
        // w_p = o exp(-((x - m0)^2 / s0^2 + (y - m1)^2 / s1^2) / 2)
        out.opacity += dw * w[p] / g.opacity;
        const double dx = x - g.mean[0];
        out.mean[0] += dw * w[p] * dx / (g.stddev[0] * g.stddev[0]);
        out.stddev[0] += dw * w[p] * dx * dx / (g.stddev[0] * g.stddev[0] * g.stddev[0]);
        if (twoD)
        {
          const double dy = y - g.mean[1];
          out.mean[1] += dw * w[p] * dy / (g.stddev[1] * g.stddev[1]);
          out.stddev[1] += dw * w[p] * dy * dy / (g.stddev[1] * g.stddev[1] * g.stddev[1]);
        }
      }
    }
  }
}

} // namespace ddg
