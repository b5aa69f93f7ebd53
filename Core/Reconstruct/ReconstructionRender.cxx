// ReconstructionRender.cxx: a reconstruction's TF rendered as ParaView applies it, on a whole
// volume or over the pieces of one (Reconstruction.h: renderResult, renderTable).
#include "Reconstruct/Reconstruction.h"

#include "Render/RayCaster.h"

#include <algorithm>

namespace ddg
{

Image renderResult(const RayCaster& caster, const ReconstructionResult& result, const View& view,
  const RenderOptions& options)
{
  if (result.twoD)
  {
    return caster.render(result.table2D, view, options);
  }
  // Exactly what ParaView will do with the preset: nodes at the bins, its own table.
  return caster.render(
    caster.paraviewTable(tableToTransferFunction(result.table1D, 0.0)), view, options);
}

namespace
{
// The forward pass's premultiplied RGBA of every pixel as an image.
Image imageOf(const std::vector<float>& rgba, const View& view)
{
  Image out(view.width, view.height, 4);
  std::copy(rgba.begin(), rgba.end(), out.pixels.begin());
  return out;
}
} // namespace

Image renderTable(const DifferentiableRenderer& renderer, const TransferTable1D& table,
  const View& view, const RenderOptions& options)
{
  if (!renderer.exchange())
    return renderer.caster().render(table, view, options);
  std::vector<float> rgba;
  std::vector<RayRecord> records;
  renderer.forward(
    table.rgba.data(), table.width, table.min, table.max, view, options, {}, rgba, records);
  return imageOf(rgba, view);
}

Image renderResult(const DifferentiableRenderer& renderer, const ReconstructionResult& result,
  const View& view, const RenderOptions& options)
{
  if (!renderer.exchange())
    return renderResult(renderer.caster(), result, view, options);
  if (!result.twoD)
  {
    const auto tf = tableToTransferFunction(result.table1D, 0.0);
    const auto r = renderer.dataRange();
    return renderTable(
      renderer, bakeTable(tf, r[0], r[1], paraviewTableWidth(tf, r[0], r[1])), view, options);
  }
  const auto& t = result.table2D;
  std::vector<float> rgba;
  std::vector<RayRecord> records;
  renderer.forward2D(t.rgba.data(), t.width, t.height, t.valueRange, t.gradientRange, view, options,
    {}, rgba, records);
  return imageOf(rgba, view);
}

} // namespace ddg
