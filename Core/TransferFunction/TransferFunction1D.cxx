// TransferFunction1D.cxx: evaluation of ParaView colour/opacity functions, tables, simplification.
#include "TransferFunction/TransferFunction1D.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace ddg
{
namespace
{

// --- vtkPiecewiseFunction / vtkColorTransferFunction segment shaping -------------------------

// Remaps s by the midpoint (midpoint clamped to [1e-5, 0.99999]), as both VTK functions do.
double applyMidpoint(double s, double midpoint)
{
  const double m = std::clamp(midpoint, 0.00001, 0.99999);
  return s < m ? 0.5 * s / m : 0.5 + 0.5 * (s - m) / (1.0 - m);
}

// Hermite curve of VTK for 0.01 <= sharpness <= 0.99 on an already midpoint-remapped s.
double hermite(double s, double y1, double y2, double sharpness)
{
  if (s < 0.5)
  {
    s = 0.5 * std::pow(s * 2.0, 1.0 + 10.0 * sharpness);
  }
  else if (s > 0.5)
  {
    s = 1.0 - 0.5 * std::pow((1.0 - s) * 2.0, 1.0 + 10.0 * sharpness);
  }
  const double ss = s * s;
  const double sss = ss * s;
  const double h1 = 2 * sss - 3 * ss + 1;
  const double h2 = -2 * sss + 3 * ss;
  const double h3 = sss - 2 * ss + s;
  const double h4 = sss - ss;
  const double slope = y2 - y1;
  const double t = (1.0 - sharpness) * slope;
  const double v = h1 * y1 + h2 * y2 + h3 * t + h4 * t;
  return std::clamp(v, std::min(y1, y2), std::max(y1, y2));
}

// Index of the segment [i, i+1] holding x, for x strictly inside the node range.
template <typename Node>
size_t findSegment(const std::vector<Node>& nodes, double x)
{
  // first node with X >= x (vtk semantics), the segment ends there
  auto it = std::lower_bound(
    nodes.begin(), nodes.end(), x, [](const Node& n, double v) { return n.x < v; });
  const size_t hi = static_cast<size_t>(it - nodes.begin());
  return hi == 0 ? 0 : hi - 1;
}

void checkUnit(double v, const char* what, size_t index)
{
  if (!std::isfinite(v) || v < 0.0 || v > 1.0)
  {
    std::ostringstream msg;
    msg << what << " of node " << index << " is " << v << ", outside [0, 1]";
    throw Error(msg.str());
  }
}

template <typename Node>
void checkOrder(const std::vector<Node>& nodes, const char* list)
{
  for (size_t i = 0; i < nodes.size(); ++i)
  {
    if (!std::isfinite(nodes[i].x))
    {
      std::ostringstream msg;
      msg << list << ": x of node " << i << " is not a finite number";
      throw Error(msg.str());
    }
    if (i > 0 && !(nodes[i].x > nodes[i - 1].x))
    {
      std::ostringstream msg;
      msg << list << " are not sorted: node " << i << " at x = " << nodes[i].x
          << " does not come after x = " << nodes[i - 1].x << " (x must strictly increase)";
      throw Error(msg.str());
    }
  }
}

} // namespace

double piecewiseSegment(double s, double y1, double y2, double midpoint, double sharpness)
{
  s = applyMidpoint(s, midpoint);
  if (sharpness > 0.99)
  {
    return s < 0.5 ? y1 : y2;
  }
  if (sharpness < 0.01)
  {
    return y1 + s * (y2 - y1);
  }
  return hermite(s, y1, y2, sharpness);
}

void TransferFunction1D::validate() const
{
  if (color.empty())
  {
    throw Error("transfer function has no colour nodes (RGBPoints is empty)");
  }
  if (opacity.empty())
  {
    throw Error("transfer function has no opacity nodes (Points is empty)");
  }
  checkOrder(color, "RGBPoints");
  checkOrder(opacity, "Points");
  for (size_t i = 0; i < color.size(); ++i)
  {
    checkUnit(color[i].r, "RGBPoints: red", i);
    checkUnit(color[i].g, "RGBPoints: green", i);
    checkUnit(color[i].b, "RGBPoints: blue", i);
    checkUnit(color[i].midpoint, "RGBPoints: midpoint", i);
    checkUnit(color[i].sharpness, "RGBPoints: sharpness", i);
  }
  for (size_t i = 0; i < opacity.size(); ++i)
  {
    checkUnit(opacity[i].alpha, "Points: opacity", i);
    checkUnit(opacity[i].midpoint, "Points: midpoint", i);
    checkUnit(opacity[i].sharpness, "Points: sharpness", i);
  }
}

std::array<double, 3> TransferFunction1D::evaluateColor(double x) const
{
  if (color.empty())
  {
    return { 0, 0, 0 };
  }
  const ColorNode& first = color.front();
  const ColorNode& last = color.back();
  if (color.size() == 1 || x <= first.x)
  {
    return { first.r, first.g, first.b };
  }
  if (x >= last.x)
  {
    return { last.r, last.g, last.b };
  }
  const size_t i = findSegment(color, x);
  const ColorNode& a = color[i];
  const ColorNode& b = color[i + 1];
  double s = (x - a.x) / (b.x - a.x);
  const RGB ca{ a.r, a.g, a.b };
  const RGB cb{ b.r, b.g, b.b };
  s = applyMidpoint(s, a.midpoint);
  if (a.sharpness > 0.99)
  {
    return s < 0.5 ? ca : cb;
  }
  if (a.sharpness < 0.01)
  {
    return interpolateColor(colorSpace, hsvWrap, s, ca, cb); // VTK does not clamp this path
  }
  // 0.01 <= sharpness <= 0.99: warp s, then Hermite per component in the colour space's
  // coordinates (Diverging and Step take the warped s without the Hermite blend).
  if (s < 0.5)
  {
    s = 0.5 * std::pow(s * 2.0, 1.0 + 10.0 * a.sharpness);
  }
  else if (s > 0.5)
  {
    s = 1.0 - 0.5 * std::pow((1.0 - s) * 2.0, 1.0 + 10.0 * a.sharpness);
  }
  RGB out{};
  if (colorSpace == ColorSpace::Diverging || colorSpace == ColorSpace::Step)
  {
    out = interpolateColor(colorSpace, hsvWrap, s, ca, cb);
  }
  else
  {
    RGB pa = ca, pb = cb;
    if (colorSpace == ColorSpace::HSV)
    {
      pa = rgbToHsv(ca);
      pb = rgbToHsv(cb);
      if (hsvWrap && std::abs(pa[0] - pb[0]) > 0.5)
      {
        (pa[0] > pb[0] ? pa[0] : pb[0]) -= 1.0;
      }
    }
    else if (colorSpace == ColorSpace::Lab)
    {
      pa = rgbToLab(ca);
      pb = rgbToLab(cb);
    }
    const double ss = s * s, sss = ss * s;
    const double h1 = 2 * sss - 3 * ss + 1, h2 = -2 * sss + 3 * ss, h3 = sss - 2 * ss + s,
                 h4 = sss - ss;
    for (int c = 0; c < 3; ++c)
    {
      const double t = (1.0 - a.sharpness) * (pb[c] - pa[c]);
      out[c] = h1 * pa[c] + h2 * pb[c] + h3 * t + h4 * t;
    }
    if (colorSpace == ColorSpace::HSV)
    {
      if (out[0] < 0)
        out[0] += 1.0;
      out = hsvToRgb(out);
    }
    else if (colorSpace == ColorSpace::Lab)
    {
      out = labToRgb(out);
    }
  }
  for (double& c : out)
  {
    c = std::clamp(c, 0.0, 1.0);
  }
  return out;
}

double TransferFunction1D::evaluateOpacity(double x) const
{
  if (opacity.empty())
  {
    return 0.0;
  }
  if (opacity.size() == 1 || x <= opacity.front().x)
  {
    return opacity.front().alpha;
  }
  if (x >= opacity.back().x)
  {
    return opacity.back().alpha;
  }
  const size_t i = findSegment(opacity, x);
  const OpacityNode& a = opacity[i];
  const OpacityNode& b = opacity[i + 1];
  return piecewiseSegment((x - a.x) / (b.x - a.x), a.alpha, b.alpha, a.midpoint, a.sharpness);
}

double TransferFunction1D::smallestNodeGap() const
{
  double gap = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < color.size(); ++i)
  {
    gap = std::min(gap, color[i].x - color[i - 1].x);
  }
  for (size_t i = 1; i < opacity.size(); ++i)
  {
    gap = std::min(gap, opacity[i].x - opacity[i - 1].x);
  }
  return gap;
}

std::array<float, 4> TransferTable1D::lookup(double value) const
{
  const double u = (value - min) / (max - min);
  const double t = std::clamp(u * width - 0.5, 0.0, static_cast<double>(width - 1));
  const int i = std::min(static_cast<int>(t), width - 2);
  const double f = t - i;
  std::array<float, 4> out{};
  for (int c = 0; c < 4; ++c)
  {
    out[c] = static_cast<float>(rgba[4 * i + c] * (1 - f) + rgba[4 * (i + 1) + c] * f);
  }
  return out;
}

TransferTable1D bakeTable(const TransferFunction1D& tf, double min, double max, int width)
{
  if (width < 2)
  {
    throw Error("transfer function table needs at least 2 entries");
  }
  if (!(min < max) || !std::isfinite(min) || !std::isfinite(max))
  {
    std::ostringstream msg;
    msg << "transfer function table range [" << min << ", " << max << "] is empty or not finite";
    throw Error(msg.str());
  }
  TransferTable1D table;
  table.min = min;
  table.max = max;
  table.width = width;
  table.rgba.resize(static_cast<size_t>(width) * 4);
  for (int i = 0; i < width; ++i)
  {
    const double x = min + i * (max - min) / (width - 1);
    const auto c = tf.evaluateColor(x);
    table.rgba[4 * i + 0] = static_cast<float>(c[0]);
    table.rgba[4 * i + 1] = static_cast<float>(c[1]);
    table.rgba[4 * i + 2] = static_cast<float>(c[2]);
    table.rgba[4 * i + 3] = static_cast<float>(tf.evaluateOpacity(x));
  }
  return table;
}

int paraviewTableWidth(const TransferFunction1D& tf, double min, double max)
{
  const double gap = tf.smallestNodeGap();
  int width = 1024;
  if (std::isfinite(gap) && gap > 0 && max > min)
  {
    const double needed = std::ceil((max - min) / gap);
    while (width < needed && width < 65536)
    {
      width *= 2;
    }
  }
  return width;
}

// --- dense table -> control points -------------------------------------------------------

namespace
{

// Douglas-Peucker on a polyline of `channels` values per entry: keeps the entries needed so
// linear interpolation between kept entries is within tol of every entry (max over channels).
std::vector<int> simplify(
  const std::vector<float>& rgba, int width, int firstChannel, int channels, double tol)
{
  std::vector<char> keep(static_cast<size_t>(width), 0);
  keep.front() = keep.back() = 1;
  std::vector<std::pair<int, int>> stack{ { 0, width - 1 } };
  while (!stack.empty())
  {
    auto [a, b] = stack.back();
    stack.pop_back();
    double worst = 0;
    int worstIndex = -1;
    for (int i = a + 1; i < b; ++i)
    {
      const double s = static_cast<double>(i - a) / (b - a);
      for (int c = firstChannel; c < firstChannel + channels; ++c)
      {
        const double ya = rgba[4 * a + c], yb = rgba[4 * b + c];
        const double err = std::abs(ya + s * (yb - ya) - rgba[4 * i + c]);
        if (err > worst)
        {
          worst = err;
          worstIndex = i;
        }
      }
    }
    if (worst > tol && worstIndex > 0)
    {
      keep[worstIndex] = 1;
      stack.push_back({ a, worstIndex });
      stack.push_back({ worstIndex, b });
    }
  }
  std::vector<int> kept;
  for (int i = 0; i < width; ++i)
  {
    if (keep[i])
    {
      kept.push_back(i);
    }
  }
  return kept;
}

} // namespace

TransferFunction1D tableToTransferFunction(
  const TransferTable1D& table, double tolerance, const std::string& name)
{
  if (table.width < 2 || table.rgba.size() != static_cast<size_t>(table.width) * 4)
  {
    throw Error("transfer function table is empty or its size does not match its width");
  }
  TransferFunction1D tf;
  tf.name = name;
  tf.colorSpace = ColorSpace::RGB;
  auto xOf = [&](int i) { return table.min + i * (table.max - table.min) / (table.width - 1); };
  auto unit = [](float v) { return std::clamp(static_cast<double>(v), 0.0, 1.0); };
  for (int i : simplify(table.rgba, table.width, 0, 3, tolerance))
  {
    tf.color.push_back({ xOf(i), unit(table.rgba[4 * i]), unit(table.rgba[4 * i + 1]),
      unit(table.rgba[4 * i + 2]), 0.5, 0.0 });
  }
  for (int i : simplify(table.rgba, table.width, 3, 1, tolerance))
  {
    tf.opacity.push_back({ xOf(i), unit(table.rgba[4 * i + 3]), 0.5, 0.0 });
  }
  return tf;
}

} // namespace ddg
