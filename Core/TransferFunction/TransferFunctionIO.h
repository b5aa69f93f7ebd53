// TransferFunctionIO.h: the TF file contract — ParaView preset JSON (1D), the ddg 2D JSON and
// ParaView's 2D transfer function boxes.
#pragma once

#include "TransferFunction/ParaViewTransferFunction2D.h"
#include "TransferFunction/TransferFunction1D.h"
#include "TransferFunction/TransferFunction2D.h"

#include <string>

namespace ddg
{

/// 1D TF file = a ParaView colour-map preset, exactly what ParaView's "Export" writes and
/// "Import" reads: a JSON list whose first object has
///   "Name": string, "ColorSpace": "RGB" | "HSV" | "Lab" | "Diverging" | "Step" (default RGB),
///   "RGBPoints": [x, r, g, b, ...], "Points": [x, alpha, midpoint, sharpness, ...],
/// x in data values (a single object instead of a list is accepted too). The TF is validated
/// (TransferFunction1D::validate). `origin` names the source in error messages.
TransferFunction1D parsePreset(const std::string& jsonText, const std::string& origin = "preset");
TransferFunction1D readPreset(const std::string& path);
/// Serialises as a one-element preset list (ColorSpace, RGBPoints, Points, Name, Creator).
std::string presetToJson(const TransferFunction1D& tf);
void writePreset(const TransferFunction1D& tf, const std::string& path);

/// 2D TF file (the project's own format):
///   { "Format": "ddg-transfer-function-2d", "Version": 1, "Name": string,
///     "ValueRange": [vmin, vmax], "GradientRange": [gmin, gmax],   (data units; gradient
///                                                          magnitude in value per world unit)
///     "Size": [width, height],                  (table entries along value, gradient)
///     "Primitives": [ { "mean": [v, g], "stddev": [sv, sg], "rgb": [r, g, b],
///                       "opacity": a }, ... ]   (optional)
///     "RGBA": [r, g, b, a, ...] }               (optional, width*height*4, value fastest)
/// One of Primitives or RGBA is required; RGBA wins when both are present.
TransferFunction2D parseTransferFunction2D(
  const std::string& jsonText, const std::string& origin = "2D transfer function");
TransferFunction2D readTransferFunction2D(const std::string& path);
std::string transferFunction2DToJson(const TransferFunction2D& tf);
void writeTransferFunction2D(const TransferFunction2D& tf, const std::string& path);

/// Any TF file: a 1D preset, the DDG 2D JSON (told apart by its "Format" key) or ParaView's
/// 2D transfer function as `ddg export --format paraview-2d` writes it (an object with
/// "Boxes": ParaViewTransferFunction2D::fromJson). The last is defined over a volume's data and
/// gradient ranges, so it becomes a 2D table only with a volume (RayCaster::resolve).
struct TransferFunctionFile
{
  bool is2D = false;         ///< tf2D holds the TF (the DDG 2D JSON, or resolved boxes)
  bool isParaView2D = false; ///< paraview2D holds the TF, not resolved yet
  TransferFunction1D tf1D;
  TransferFunction2D tf2D;
  ParaViewTransferFunction2D paraview2D;
};
TransferFunctionFile readTransferFunctionFile(const std::string& path);
TransferFunctionFile parseTransferFunctionFile(
  const std::string& jsonText, const std::string& origin);

} // namespace ddg
