// Edit.cxx: colour clusters and image-space edits of design renders.
#include "Gallery/Edit.h"

#include "Common/Error.h"
#include "TransferFunction/ColorSpace.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace ddg
{

namespace
{
constexpr float kVisible = 0.05f;

void checkRGBA(const Image& im)
{
  if (im.channels != 4 || im.width < 1 || im.height < 1)
    throw Error("an edit needs a premultiplied RGBA design image");
}

RGB straight(const Image& im, int x, int y)
{
  const double a = im.at(x, y, 3);
  RGB c{};
  for (int k = 0; k < 3; ++k)
    c[k] = a > 0 ? std::clamp(im.at(x, y, k) / a, 0.0, 1.0) : 0.0;
  return c;
}

double dist2(const RGB& a, const RGB& b)
{
  return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]);
}

/// Edit weight of pixel p: 1 in the cluster (or the mask's value), 0 elsewhere.
double weightOf(const ColorClusters& cl, const EditRegion& region, int x, int y)
{
  if (!region.mask.empty())
    return std::clamp(static_cast<double>(region.mask.at(x, y, 0)), 0.0, 1.0);
  return cl.labels[static_cast<size_t>(y) * cl.width + x] == region.cluster ? 1.0 : 0.0;
}

} // namespace

void checkEditRegion(const ColorClusters& cl, const EditRegion& region, const Image& im)
{
  checkRGBA(im);
  if (!region.mask.empty())
  {
    if (region.mask.width != im.width || region.mask.height != im.height ||
      region.mask.channels != 1)
      throw Error("the brushed mask must be one channel of the image's size");
    return;
  }
  if (cl.width != im.width || cl.height != im.height)
    throw Error("the colour clusters belong to another image");
  if (region.cluster < 0 || region.cluster >= cl.count())
    throw Error("colour cluster " + std::to_string(region.cluster) + " does not exist (0.." +
      std::to_string(cl.count() - 1) + ")");
}

int ColorClusters::at(int x, int y) const
{
  if (x < 0 || y < 0 || x >= width || y >= height)
    throw Error(
      "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the image");
  return labels[static_cast<size_t>(y) * width + x];
}

ColorClusters colorClusters(const Image& rgba, int k)
{
  checkRGBA(rgba);
  if (k < 1 || k > 16)
    throw Error("the number of colour clusters must be in [1, 16]");
  ColorClusters cl;
  cl.width = rgba.width;
  cl.height = rgba.height;
  cl.labels.assign(static_cast<size_t>(rgba.width) * rgba.height, -1);
  std::vector<RGB> lab;
  std::vector<size_t> where;
  for (int y = 0; y < rgba.height; ++y)
    for (int x = 0; x < rgba.width; ++x)
      if (rgba.at(x, y, 3) > kVisible)
      {
        lab.push_back(rgbToLab(straight(rgba, x, y)));
        where.push_back(static_cast<size_t>(y) * rgba.width + x);
      }
  if (lab.empty())
    throw Error("the design image shows nothing to edit (no visible pixel)");
  // k-means++ seeding
  std::mt19937_64 rng(12345);
  std::vector<RGB> centres{ lab[std::uniform_int_distribution<size_t>(0, lab.size() - 1)(rng)] };
  std::vector<double> d(lab.size());
  while (static_cast<int>(centres.size()) < k)
  {
    double total = 0;
    for (size_t i = 0; i < lab.size(); ++i)
    {
      d[i] = std::numeric_limits<double>::max();
      for (const auto& c : centres)
        d[i] = std::min(d[i], dist2(lab[i], c));
      total += d[i];
    }
    if (total <= 1e-9)
      break; // fewer distinct colours than k
    double pick = std::uniform_real_distribution<double>(0, total)(rng);
    size_t j = 0;
    for (; j + 1 < lab.size() && pick > d[j]; ++j)
      pick -= d[j];
    centres.push_back(lab[j]);
  }
  std::vector<int> label(lab.size(), 0);
  for (int it = 0; it < 20; ++it)
  {
    for (size_t i = 0; i < lab.size(); ++i)
    {
      double best = std::numeric_limits<double>::max();
      for (size_t c = 0; c < centres.size(); ++c)
        if (dist2(lab[i], centres[c]) < best)
        {
          best = dist2(lab[i], centres[c]);
          label[i] = static_cast<int>(c);
        }
    }
    std::vector<RGB> sum(centres.size(), RGB{ 0, 0, 0 });
    std::vector<int> n(centres.size(), 0);
    for (size_t i = 0; i < lab.size(); ++i)
    {
      for (int q = 0; q < 3; ++q)
        sum[label[i]][q] += lab[i][q];
      ++n[label[i]];
    }
    for (size_t c = 0; c < centres.size(); ++c)
      if (n[c] > 0)
        for (int q = 0; q < 3; ++q)
          centres[c][q] = sum[c][q] / n[c];
  }
  // keep non-empty clusters, largest first
  std::vector<int> n(centres.size(), 0);
  for (int l : label)
    ++n[l];
  std::vector<int> order;
  for (size_t c = 0; c < centres.size(); ++c)
    if (n[c] > 0)
      order.push_back(static_cast<int>(c));
  std::sort(order.begin(), order.end(), [&](int a, int b) { return n[a] > n[b]; });
  std::vector<int> remap(centres.size(), -1);
  for (size_t r = 0; r < order.size(); ++r)
  {
    remap[order[r]] = static_cast<int>(r);
    cl.lab.push_back(centres[order[r]]);
    cl.share.push_back(static_cast<double>(n[order[r]]) / lab.size());
  }
  cl.rgb.assign(order.size(), RGB{ 0, 0, 0 });
  for (size_t i = 0; i < lab.size(); ++i)
  {
    const int r = remap[label[i]];
    cl.labels[where[i]] = r;
    const RGB c = straight(
      rgba, static_cast<int>(where[i] % rgba.width), static_cast<int>(where[i] / rgba.width));
    for (int q = 0; q < 3; ++q)
      cl.rgb[r][q] += c[q] / n[order[r]];
  }
  return cl;
}

Image recolour(const Image& rgba, const ColorClusters& clusters, const EditRegion& region,
  double dHue, double satScale, double dLightness)
{
  checkEditRegion(clusters, region, rgba);
  if (!std::isfinite(dHue) || !(satScale >= 0) || !std::isfinite(satScale) ||
    !std::isfinite(dLightness))
    throw Error(
      "a recolour needs a finite hue shift and lightness shift and a saturation scale >= 0");
  Image out = rgba;
  for (int y = 0; y < rgba.height; ++y)
    for (int x = 0; x < rgba.width; ++x)
    {
      const double w = weightOf(clusters, region, x, y);
      const double a = rgba.at(x, y, 3);
      if (w <= 0 || a <= 0)
        continue;
      const RGB c = straight(rgba, x, y);
      RGB hsv = rgbToHsv(c);
      hsv[0] = std::fmod(hsv[0] + dHue / 360.0 + 10.0, 1.0);
      hsv[1] = std::clamp(hsv[1] * satScale, 0.0, 1.0);
      RGB lab = rgbToLab(hsvToRgb(hsv));
      lab[0] = std::clamp(lab[0] + dLightness, 0.0, 100.0);
      const RGB edited = labToRgb(lab);
      for (int k = 0; k < 3; ++k)
        out.at(x, y, k) =
          static_cast<float>(a * ((1 - w) * c[k] + w * std::clamp(edited[k], 0.0, 1.0)));
    }
  return out;
}

Image changeVisibility(
  const Image& rgba, const ColorClusters& clusters, const EditRegion& region, double factor)
{
  checkEditRegion(clusters, region, rgba);
  if (!(factor >= 0) || !std::isfinite(factor))
    throw Error("a visibility factor must be finite and >= 0");
  Image out = rgba;
  for (int y = 0; y < rgba.height; ++y)
    for (int x = 0; x < rgba.width; ++x)
    {
      const double w = weightOf(clusters, region, x, y);
      const double a = rgba.at(x, y, 3);
      if (w <= 0 || a <= 0)
        continue;
      const double scaled = std::min(1.0, a * factor);
      const double na = (1 - w) * a + w * scaled;
      const RGB c = straight(rgba, x, y);
      for (int k = 0; k < 3; ++k)
        out.at(x, y, k) = static_cast<float>(na * c[k]);
      out.at(x, y, 3) = static_cast<float>(na);
    }
  return out;
}

} // namespace ddg
