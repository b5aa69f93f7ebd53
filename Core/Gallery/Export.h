// Export.h: a design's explicit TF as the files other tools read: ParaView preset JSON (1D),
// the DDG 2D TF JSON, and 3D Slicer's volume property JSON (.vp.json).
#pragma once

#include "TransferFunction/GaussianPrimitive.h"
#include "TransferFunction/ParaViewTransferFunction2D.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <array>
#include <ctime>
#include <string>
#include <vector>

namespace ddg
{
class RayCaster;
struct View;

/// The TF of Gaussian primitives as ParaView holds it. 1D: rasterized at 1024 entries over
/// valueRange and converted to control points (tableToTransferFunction, tolerance 1/512), so
/// ParaView reproduces the ray-cast design; 2D: the primitives over valueRange x gradientRange
/// (DDG 2D TF JSON, rasterized by its reader). Throws ddg::Error for invalid primitives or ranges.
TransferFunctionFile primitivesToTransferFunction(const std::vector<GaussianPrimitive>& primitives,
  int dimensions, std::array<double, 2> valueRange, std::array<double, 2> gradientRange,
  const std::string& name = "ddg design");

/// A unique, meaningful preset name for a TF file written at `path`: "DDG <volume> <origin>
/// <stem> <date> <time>", e.g. "DDG tooth query design 2026-11-24 05:12:07" (`volume`: a name or
/// a file path, its folders and extension dropped; `origin`: what made the TF, e.g. "outline
/// design", "query", "match", "reconstruction"; `stem`: the file's name without its extension;
/// `when`: local time to the second; empty parts and an origin equal to the stem left out).
/// ParaView keeps imported presets by name and refuses one whose name it holds already ("Cannot
/// find a unique name", ParaView 5.11 imports it nameless), so every exported file gets its own.
std::string exportName(const std::string& volume, const std::string& origin,
  const std::string& path, std::time_t when = std::time(nullptr));

/// The origin exportName gives a design whose history ends with `action`: "pick" -> "outline
/// design", "latent" -> "design", "axes" -> "edit"; any other word as it is.
std::string designOrigin(const std::string& action);

/// `tf` with its "Name" (1D preset or 2D TF) set to `name`.
TransferFunctionFile renamed(TransferFunctionFile tf, const std::string& name);

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

/// The JSON of ParaView 5.11's TransferFunction2D for a 2D TF (Boxes, Range, OutputDimensions
/// and the fit's errors under "Fit"): boxes fitted to `tf` for `caster`'s volume at `view`
/// (fitParaViewBoxes with ParaView's mapping of that volume and view). What the filters' field
/// "ParaViewTransferFunction2D" and `ddg export --format paraview-2d` hold.
std::string paraViewTransferFunction2DJson(const RayCaster& caster, const TransferFunction2D& tf,
  const View& view, const ParaViewBoxFitOptions& options = {},
  ParaViewBoxFitReport* report = nullptr);
/// The same for ParaView's mapping of a volume at a view (RayCaster::paraviewMapping2D,
/// DesignVolume::paraviewMapping2D).
std::string paraViewTransferFunction2DJson(const ParaViewTransfer2DMapping& mapping,
  const TransferFunction2D& tf, const ParaViewBoxFitOptions& options = {},
  ParaViewBoxFitReport* report = nullptr);

/// Exports `tf` for `caster`'s volume at `view` (its opacity unit distance, else ParaView's
/// default) as "paraview", "slicer" (as above) or "paraview-2d" (a 2D TF as ParaView's boxes,
/// fitted in `boxIterations` steps). Returns a short description of what was written (the
/// format, and the box count and fit errors for paraview-2d). Throws ddg::Error as above and
/// for a 1D TF to paraview-2d.
std::string exportTransferFunction(const TransferFunctionFile& tf, const std::string& path,
  const std::string& format, const RayCaster& caster, const View& view,
  int boxIterations = ParaViewBoxFitOptions().iterations);

} // namespace ddg
