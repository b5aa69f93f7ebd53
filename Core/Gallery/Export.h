// Export.h: a design's explicit TF as the files other tools read: ParaView preset JSON (1D),
// the DDG 2D TF JSON, and 3D Slicer's volume property JSON (.vp.json).
#pragma once

#include "TransferFunction/GaussianPrimitive.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <array>
#include <string>
#include <vector>

namespace ddg
{

/// The TF of Gaussian primitives as ParaView holds it. 1D: rasterized at 1024 entries over
/// valueRange and converted to control points (tableToTransferFunction, tolerance 1/512), so
/// ParaView reproduces the ray-cast design; 2D: the primitives over valueRange x gradientRange
/// (DDG 2D TF JSON, rasterized by its reader). Throws ddg::Error for invalid primitives or ranges.
TransferFunctionFile primitivesToTransferFunction(const std::vector<GaussianPrimitive>& primitives,
  int dimensions, std::array<double, 2> valueRange, std::array<double, 2> gradientRange,
  const std::string& name = "ddg design");

/// 3D Slicer's volume property JSON (schema volume-property-schema-v1.0.0: "@schema",
/// "volumeProperties": [{"effectiveRange", "interpolationType": "linear", "components":
/// [{"componentWeight", "shade": false, "scalarOpacityUnitDistance", "scalarOpacity": {"points":
/// [{x, y, midpoint, sharpness}]}, "rgbTransferFunction": {"points": [{x, color, midpoint,
/// sharpness}]}, "gradientOpacity" (constant 1), "disableGradientOpacity": true}]}]}) of a 1D TF.
/// Slicer's scalar opacity unit distance plays ParaView's role; pass the one the TF was designed
/// with (ParaView's default: the volume's mean voxel spacing).
std::string slicerVolumePropertyJson(
  const TransferFunction1D& tf, std::array<double, 2> effectiveRange, double opacityUnitDistance);

/// Export formats: "paraview" (preset JSON; 2D: the DDG 2D TF JSON) and "slicer" (1D only).
/// Writes atomically. Throws ddg::Error for an unknown format or a 2D TF to Slicer.
void exportTransferFunction(const TransferFunctionFile& tf, const std::string& path,
  const std::string& format, std::array<double, 2> valueRange, double opacityUnitDistance);

} // namespace ddg
