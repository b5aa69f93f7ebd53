// DesignVolume.h: what a design gallery needs of its volume — its ranges and bounds, ray casts
// of design tables, ParaView's mapping — whether the volume is in this process (a ray caster)
// or split over the ranks of `mpiexec -np N pvserver` (the plugin's, which renders over the
// pieces).
#pragma once

#include "Design/DesignSpace.h"
#include "Render/RayCaster.h"
#include "TransferFunction/ParaViewTransferFunction2D.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <array>
#include <memory>

namespace ddg
{

class DesignVolume
{
public:
  virtual ~DesignVolume() = default;
  /// The whole volume's data range, and its gradient-magnitude range (Volume::
  /// gradientMagnitudeRange: the axis of 2D tables).
  virtual std::array<double, 2> range() const = 0;
  virtual std::array<double, 2> gradientRange() const = 0;
  /// The whole volume's bounds (xmin, xmax, ymin, ...).
  virtual std::array<double, 6> bounds() const = 0;
  /// `table` ray cast at `view`: premultiplied RGBA at the view's size (RayCaster::render).
  virtual Image render(const DesignTable& table, const View& view) const = 0;
  /// The whole volume's opacity unit distance at `view` and ParaView's 2D mapping
  /// (RayCaster::opacityUnitDistance, paraviewMapping2D).
  virtual double opacityUnitDistance(const View& view) const = 0;
  virtual ParaViewTransfer2DMapping paraviewMapping2D(const View& view) const = 0;
  /// The ray caster of the whole volume when it is in this process; null when it is split
  /// (what needs every voxel in one place — exemplars, a U-Net's reconstructed TF — is refused).
  virtual const RayCaster* caster() const { return nullptr; }
  /// `table` at `litView` (Shade on) and at the same view with Shade off: { lit, unlit }, each
  /// as render() gives it. From one march when the caster is here (RenderOptions::unlitToo: the
  /// cost of the lit image alone), else two renders.
  std::array<Image, 2> renderLitAndUnlit(const DesignTable& table, const View& litView) const;
};

/// The volume in this process.
class LocalDesignVolume : public DesignVolume
{
public:
  /// `volume` must outlive this.
  explicit LocalDesignVolume(const Volume& volume);
  std::array<double, 2> range() const override;
  std::array<double, 2> gradientRange() const override;
  std::array<double, 6> bounds() const override;
  Image render(const DesignTable& table, const View& view) const override;
  double opacityUnitDistance(const View& view) const override;
  ParaViewTransfer2DMapping paraviewMapping2D(const View& view) const override;
  const RayCaster* caster() const override { return &Caster; }

private:
  const Volume& Vol;
  RayCaster Caster;
};

/// The table RayCaster::render(tf) ray casts for a TF over the data range `range` (1D:
/// ParaView's table of the preset; 2D: the TF's own table). ParaView's 2D boxes need the volume
/// (RayCaster::resolve) and are refused.
DesignTable transferTable(const TransferFunctionFile& tf, const std::array<double, 2>& range);

} // namespace ddg
