// TransferFunction2D.cxx: 2D table lookup, validation and baking.
#include "TransferFunction/TransferFunction2D.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>

namespace ddg
{

std::array<float, 4> TransferTable2D::lookup(double value, double gradient) const
{
  auto coord = [](double x, const std::array<double, 2>& r, int n, int& i, double& f)
  {
    const double u = (x - r[0]) / (r[1] - r[0]);
    const double t = std::clamp(u * n - 0.5, 0.0, static_cast<double>(n - 1));
    i = std::min(static_cast<int>(t), n - 2);
    f = t - i;
  };
  int i, j;
  double fi, fj;
  coord(value, valueRange, width, i, fi);
  coord(gradient, gradientRange, height, j, fj);
  std::array<float, 4> out{};
  auto at = [&](int a, int b, int c) { return rgba[4 * (static_cast<size_t>(b) * width + a) + c]; };
  for (int c = 0; c < 4; ++c)
  {
    const double lo = at(i, j, c) * (1 - fi) + at(i + 1, j, c) * fi;
    const double hi = at(i, j + 1, c) * (1 - fi) + at(i + 1, j + 1, c) * fi;
    out[c] = static_cast<float>(lo * (1 - fj) + hi * fj);
  }
  return out;
}

void TransferTable2D::validate() const
{
  if (width < 2 || height < 2)
  {
    throw Error("2D transfer function table needs at least 2 x 2 entries");
  }
  if (rgba.size() != static_cast<size_t>(width) * height * 4)
  {
    throw Error("2D transfer function table: RGBA has the wrong number of values for its size");
  }
  if (!(valueRange[0] < valueRange[1]) || !(gradientRange[0] < gradientRange[1]) ||
    !std::isfinite(valueRange[0]) || !std::isfinite(valueRange[1]) ||
    !std::isfinite(gradientRange[0]) || !std::isfinite(gradientRange[1]))
  {
    throw Error("2D transfer function: ValueRange and GradientRange must be finite and increasing");
  }
  for (float v : rgba)
  {
    if (!std::isfinite(v) || v < 0.0f || v > 1.0f)
    {
      throw Error("2D transfer function table: RGBA values must lie in [0, 1]");
    }
  }
}

TransferTable2D TransferFunction2D::bake() const
{
  if (!table.rgba.empty())
  {
    table.validate();
    return table;
  }
  if (primitives.empty())
  {
    throw Error("2D transfer function has neither a table nor primitives");
  }
  const int w = table.width > 1 ? table.width : 256;
  const int h = table.height > 1 ? table.height : 128;
  return rasterize2D(primitives, table.valueRange, table.gradientRange, w, h);
}

} // namespace ddg
