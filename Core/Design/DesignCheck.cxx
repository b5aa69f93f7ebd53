// DesignCheck.cxx: the box's footprint and a design's coverage of it.
#include "Design/DesignCheck.h"

#include "Common/Error.h"
#include "TransferFunction/TransferFunction2D.h"

#include <cmath>

namespace ddg
{

Image boxFootprint(const RayCaster& caster, const View& view)
{
  // A table of full opacity: every ray that enters the box is opaque at its first sample.
  TransferTable1D opaque;
  opaque.min = caster.dataRange()[0];
  opaque.max = caster.dataRange()[1];
  opaque.width = 2;
  opaque.rgba.assign(8, 1.0f);
  RenderOptions options;
  options.threads = 1;
  const Image rgba = caster.render(opaque, view, options);
  Image mask(rgba.width, rgba.height, 1);
  for (size_t i = 0; i < mask.pixels.size(); ++i)
    mask.pixels[i] = rgba.pixels[4 * i + 3] > 0.5f ? 1.0f : 0.0f;
  return mask;
}

DesignLook lookOfDesign(const Image& rgba, const Image& footprint)
{
  if (rgba.channels != 4 || footprint.channels != 1 || rgba.width != footprint.width ||
    rgba.height != footprint.height)
    throw Error("a design's look needs its premultiplied RGBA render and the box's footprint at "
                "the same size");
  const int w = rgba.width, h = rgba.height;
  auto inside = [&](int x, int y)
  { return x >= 0 && y >= 0 && x < w && y < h && footprint.at(x, y, 0) > 0.5f; };
  DesignLook look;
  int shown = 0, ring = 0, ringShown = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      if (!inside(x, y))
        continue;
      const bool visible = rgba.at(x, y, 3) >= kDesignVisibleAlpha;
      ++look.footprint;
      shown += visible;
      if (!inside(x - 1, y) || !inside(x + 1, y) || !inside(x, y - 1) || !inside(x, y + 1))
      {
        ++ring;
        ringShown += visible;
      }
    }
  if (look.footprint > 0)
    look.coverage = static_cast<double>(shown) / look.footprint;
  if (ring > 0)
    look.ringCoverage = static_cast<double>(ringShown) / ring;
  return look;
}

BoxCorners::BoxCorners(const Volume& volume, int dimensions, double opacityUnitDistance)
  : Range(volume.range())
  , Dimensions(dimensions)
{
  const auto& n = volume.dims();
  const auto& sp = volume.spacing();
  std::vector<float> gradient;
  if (dimensions == 2)
  {
    gradient = volume.gradientMagnitude();
    GradientRange = volume.gradientMagnitudeRange();
  }
  std::array<int, 3> side{};
  double shortest = 1e300;
  for (int a = 0; a < 3; ++a)
  {
    side[a] = std::min(n[a], std::max(2, n[a] / 16));
    shortest = std::min(shortest, (n[a] - 1) * sp[a]);
  }
  for (int c = 0; c < 8; ++c)
    for (int k = 0; k < side[2]; ++k)
      for (int j = 0; j < side[1]; ++j)
        for (int i = 0; i < side[0]; ++i)
        {
          const int x = (c & 1) ? n[0] - 1 - i : i, y = (c & 2) ? n[1] - 1 - j : j,
                    z = (c & 4) ? n[2] - 1 - k : k;
          const size_t at = (static_cast<size_t>(z) * n[1] + y) * n[0] + x;
          Values[c].push_back(volume.value(static_cast<std::int64_t>(at)));
          if (dimensions == 2)
            Gradients[c].push_back(gradient[at]);
        }
  // alpha across the shortest side from a mean opacity a: 1 - (1 - a)^(shortest / unit)
  const double steps = shortest / std::max(1e-12, opacityUnitDistance);
  Threshold = steps > 0 ? 1 - std::pow(1.0 - kDesignVisibleAlpha, 1 / steps) : 1;
}

double meanOpacity(const TransferTable1D& table, const std::vector<float>& values)
{
  double sum = 0;
  for (float v : values)
    sum += table.lookup(v)[3];
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

bool BoxCorners::hazy(const std::vector<GaussianPrimitive>& tf) const
{
  if (tf.empty())
    return false;
  int hazed = 0;
  if (Dimensions == 2)
  {
    const TransferTable2D table = rasterize2D(tf, Range, GradientRange, 256, 64);
    for (int c = 0; c < 8; ++c)
    {
      double sum = 0;
      for (size_t q = 0; q < Values[c].size(); ++q)
        sum += table.lookup(Values[c][q], Gradients[c][q])[3];
      hazed += sum >= Threshold * Values[c].size();
    }
  }
  else
  {
    const TransferTable1D table = rasterize1D(tf, Range[0], Range[1], 256);
    for (int c = 0; c < 8; ++c)
      hazed += meanOpacity(table, Values[c]) >= Threshold;
  }
  return hazed >= 6;
}

DesignLook lookOfPrimitives(const RayCaster& caster, const std::vector<GaussianPrimitive>& tf,
  int dimensions, const std::array<double, 2>& gradientRange, const View& view)
{
  RenderOptions options;
  options.threads = 1;
  return lookOfDesign(
    renderDesign(caster, tf, dimensions, gradientRange, view, options), boxFootprint(caster, view));
}

DesignVerdict judgeDesign(const RayCaster& caster, const BoxCorners& corners,
  const std::vector<GaussianPrimitive>& tf, int dimensions,
  const std::array<double, 2>& gradientRange, int size)
{
  int boxes = 0, empties = 0;
  for (double azimuth : { 0.0, 120.0, 240.0 })
  {
    const View view = orbitView(caster.volume(), size, azimuth, 20, 1);
    const DesignLook look = lookOfPrimitives(caster, tf, dimensions, gradientRange, view);
    boxes += look.flatBox();
    empties += look.empty();
  }
  DesignVerdict verdict;
  verdict.empty = empties == 3;
  verdict.flatBox = !verdict.empty && (boxes >= 2 || corners.hazy(tf));
  return verdict;
}

bool regionShowsStructure(const RayCaster& caster, const BoxCorners& corners,
  const FeatureRegion& region, int dimensions, const std::array<double, 2>& gradientRange)
{
  return !judgeDesign(caster, corners, { basePrimitive(region) }, dimensions, gradientRange).junk();
}

DesignVerdict screenDesign(const RayCaster& caster, const BoxCorners& corners,
  const std::vector<GaussianPrimitive>& tf, const Image& rgbaExp, const View& viewExp)
{
  const DesignLook look = lookOfDesign(rgbaExp, boxFootprint(caster, viewExp));
  DesignVerdict v;
  v.empty = look.empty();
  v.flatBox = !v.empty && (look.flatBox() || corners.hazy(tf));
  return v;
}

std::vector<FeatureRegion> findDesignRegions(const Volume& volume, const RayCaster& caster,
  const BoxCorners& corners, const DesignSpaceSpec& spec, int* left)
{
  if (left)
    *left = 0;
  if (!spec.regions.empty())
    return spec.regions;
  const bool twoD = spec.dimensions == 2;
  const auto gradientRange =
    twoD ? volume.gradientMagnitudeRange() : std::array<double, 2>{ 0.0, 1.0 };
  int refused = 0;
  const auto keep = [&](FeatureRegion& r)
  {
    FeatureRegion tried = r;
    for (int narrowed = 0; narrowed <= 3; ++narrowed)
    {
      if (regionShowsStructure(caster, corners, tried, spec.dimensions, gradientRange))
      {
        r = tried;
        return true;
      }
      tried.lo = tried.peak - (tried.peak - tried.lo) / 2;
      tried.hi = tried.peak + (tried.hi - tried.peak) / 2;
      if (tried.twoD())
      {
        tried.gradientLo = tried.gradientPeak - (tried.gradientPeak - tried.gradientLo) / 2;
        tried.gradientHi = tried.gradientPeak + (tried.gradientHi - tried.gradientPeak) / 2;
      }
    }
    ++refused;
    return false;
  };
  try
  {
    auto regions = twoD ? findFeatureRegions2D(volume, spec.maxRegions, keep)
                        : findFeatureRegions(volume, spec.maxRegions, keep);
    if (left)
      *left = refused;
    return regions;
  }
  catch (const Error&)
  {
    if (refused == 0)
      throw; // no peak at all: the histogram's own message
  }
  return twoD ? findFeatureRegions2D(volume, spec.maxRegions)
              : findFeatureRegions(volume, spec.maxRegions);
}

} // namespace ddg
