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

void blend(const std::vector<GaussianPrimitive>& primitives,
  double x,
  double y,
  bool twoD,
  float* out)
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

TransferTable1D rasterize1D(const std::vector<GaussianPrimitive>& primitives,
  double min,
  double max,
  int width)
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
  std::array<double, 2> valueRange,
  std::array<double, 2> gradientRange,
  int width,
  int height)
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

} // namespace ddg
