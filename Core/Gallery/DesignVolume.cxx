// DesignVolume.cxx: the volume in this process, and the table of a TF file.
#include "Gallery/DesignVolume.h"

#include "Common/Error.h"

namespace ddg
{

std::array<Image, 2> DesignVolume::renderLitAndUnlit(
  const DesignTable& table, const View& litView) const
{
  if (!litView.lighting.shade)
    throw Error("renderLitAndUnlit: the view must have Shade on");
  View unlitView = litView;
  unlitView.lighting.shade = false;
  const RayCaster* here = caster();
  if (!here)
    return { render(table, litView), render(table, unlitView) };
  RenderOptions options;
  options.unlitToo = true;
  const Image both = renderTable(*here, table, litView, options);
  std::array<Image, 2> out{ Image(both.width, both.height, 4), Image(both.width, both.height, 4) };
  for (size_t p = 0, n = static_cast<size_t>(both.width) * both.height; p < n; ++p)
    for (int c = 0; c < 4; ++c)
    {
      out[0].pixels[4 * p + c] = both.pixels[8 * p + c];
      out[1].pixels[4 * p + c] = both.pixels[8 * p + 4 + c];
    }
  return out;
}

LocalDesignVolume::LocalDesignVolume(const Volume& volume)
  : Vol(volume)
  , Caster(volume)
{
}

std::array<double, 2> LocalDesignVolume::range() const
{
  return Vol.range();
}

std::array<double, 2> LocalDesignVolume::gradientRange() const
{
  return Vol.gradientMagnitudeRange();
}

std::array<double, 6> LocalDesignVolume::bounds() const
{
  return Vol.bounds();
}

Image LocalDesignVolume::render(const DesignTable& table, const View& view) const
{
  return renderTable(Caster, table, view);
}

double LocalDesignVolume::opacityUnitDistance(const View& view) const
{
  return Caster.opacityUnitDistance(view);
}

ParaViewTransfer2DMapping LocalDesignVolume::paraviewMapping2D(const View& view) const
{
  return Caster.paraviewMapping2D(view);
}

DesignTable transferTable(const TransferFunctionFile& tf, const std::array<double, 2>& range)
{
  if (tf.isParaView2D)
    throw Error("ParaView's 2D boxes are mapped onto the volume: resolve them first");
  DesignTable t;
  t.dimensions = tf.is2D ? 2 : 1;
  if (tf.is2D)
    t.twoD = tf.tf2D.bake();
  else
    t.oneD =
      bakeTable(tf.tf1D, range[0], range[1], paraviewTableWidth(tf.tf1D, range[0], range[1]));
  return t;
}

} // namespace ddg
