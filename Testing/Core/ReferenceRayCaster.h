// ReferenceRayCaster.h: a deliberately naive ray caster, the oracle for the fast one.
#pragma once

#include "Image/Image.h"
#include "Render/RayCaster.h"

namespace ddg::reference
{

/// Same model as ddg::RayCaster (see RayCaster.h), written the obvious way: double precision,
/// world-space positions, Volume::sampleWorld, TransferTable lookup, no block skipping,
/// one thread. Slow. `offset` is the first sample's offset in steps.
Image referenceRender(const Volume& volume, const TransferTable1D& table, const View& view,
  double sampleDistance, double unitDistance, double offset, double terminationOpacity);

/// The same with Shade on (view.lighting), written from the shader's definitions in double: the
/// gradient as two trilinear samples N/(N-1) voxels either side per axis over the spacing, VTK's
/// eye-space normal, the light kit from its elevations, azimuths, intensities and warmth colours,
/// two-sided Phong, clamp (Documentation/Rendering.md, "Shade on").
Image referenceRenderLit(const Volume& volume, const TransferTable1D& table, const View& view,
  double sampleDistance, double unitDistance, double offset, double terminationOpacity);

/// The same with a 2D table (value x gradient magnitude): the gradient axis is half the norm of
/// the shader's gradient above (ParaView's |d| over the mean spacing); with Shade on, lit as
/// above without the clamp (ParaView does not clamp the lit colour of 2D tables).
Image referenceRender2D(const Volume& volume, const TransferTable2D& table, const View& view,
  double sampleDistance, double unitDistance, double offset, double terminationOpacity);

} // namespace ddg::reference

namespace ddg::reference
{

/// Reverse mode of the DifferentiableRenderer model the obvious way: every sample's state is
/// stored, then walked backwards (no inversion). dL_dRGBA per pixel (all pixels, row-major);
/// returns dL/d(raw table entries), width * 4. Double precision throughout. Shade on
/// (view.lighting): each sample's colour lit as referenceRenderLit does, but from the model's
/// per-point gradient (lightingGradients) interpolated per component, and its colour gradient
/// scaled by Diffuse x the light sum where the clamp does not cut.
std::vector<double> referenceGradient(const Volume& volume, const std::vector<double>& table,
  int width, double min, double max, const View& view, double sampleDistance, double unitDistance,
  double offset, double terminationOpacity, const std::vector<double>& dL_dRGBA);

} // namespace ddg::reference
