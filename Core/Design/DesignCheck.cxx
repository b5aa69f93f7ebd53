// DesignCheck.cxx: the box's footprint and a design's coverage of it.
#include "Design/DesignCheck.h"

#include "Common/Error.h"

namespace ddg
{

Image boxFootprint(const RayCaster& caster, const View& view)
{
  // A table of full opacity: every ray that enters the box is opaque at its first sample.
  TransferTable1D opaque;
  opaque.min = caster.volume().range()[0];
  opaque.max = caster.volume().range()[1];
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

DesignLook lookOfPrimitives(const RayCaster& caster, const std::vector<GaussianPrimitive>& tf,
  int dimensions, const std::array<double, 2>& gradientRange, const View& view)
{
  RenderOptions options;
  options.threads = 1;
  return lookOfDesign(
    renderDesign(caster, tf, dimensions, gradientRange, view, options), boxFootprint(caster, view));
}

DesignVerdict judgeDesign(const RayCaster& caster, const std::vector<GaussianPrimitive>& tf,
  int dimensions, const std::array<double, 2>& gradientRange, int size)
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
  verdict.flatBox = !verdict.empty && boxes >= 2;
  return verdict;
}

bool regionShowsStructure(const RayCaster& caster, const FeatureRegion& region, int dimensions,
  const std::array<double, 2>& gradientRange)
{
  return !judgeDesign(caster, { basePrimitive(region) }, dimensions, gradientRange).junk();
}

std::vector<FeatureRegion> findDesignRegions(
  const Volume& volume, const DesignSpaceSpec& spec, int* left)
{
  if (left)
    *left = 0;
  if (!spec.regions.empty())
    return spec.regions;
  const bool twoD = spec.dimensions == 2;
  const RayCaster caster(volume);
  const auto gradientRange =
    twoD ? volume.gradientMagnitudeRange() : std::array<double, 2>{ 0.0, 1.0 };
  int refused = 0;
  const auto keep = [&](const FeatureRegion& r)
  {
    const bool shows = regionShowsStructure(caster, r, spec.dimensions, gradientRange);
    refused += !shows;
    return shows;
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
