// TransferFunction1D.h: ParaView's 1D colour and opacity transfer functions and their dense tables.
#pragma once

#include "TransferFunction/ColorSpace.h"

#include <array>
#include <string>
#include <vector>

namespace ddg
{

/// A colour node of a vtkColorTransferFunction: x in data values, rgb in [0, 1].
/// midpoint and sharpness shape the segment to the next node as ParaView does (defaults 0.5, 0).
struct ColorNode
{
  double x = 0;
  double r = 0, g = 0, b = 0;
  double midpoint = 0.5;
  double sharpness = 0.0;
};

/// An opacity node of a vtkPiecewiseFunction: x in data values, alpha in [0, 1].
struct OpacityNode
{
  double x = 0;
  double alpha = 0;
  double midpoint = 0.5;
  double sharpness = 0.0;
};

/// A 1D transfer function as ParaView holds it: a colour map (RGBPoints, ColorSpace) and a
/// scalar opacity function (Points). Evaluation follows vtkColorTransferFunction and
/// vtkPiecewiseFunction exactly, including midpoint/sharpness and clamping outside the nodes.
class TransferFunction1D
{
public:
  std::string name;
  ColorSpace colorSpace = ColorSpace::RGB;
  bool hsvWrap = false;
  std::vector<ColorNode> color;
  std::vector<OpacityNode> opacity;

  /// Throws ddg::Error unless there is at least one colour and one opacity node, every number
  /// is finite, x is strictly increasing, and rgb/alpha/midpoint/sharpness lie in [0, 1].
  void validate() const;

  /// Colour at data value x (rgb in [0, 1]).
  std::array<double, 3> evaluateColor(double x) const;
  /// Opacity at data value x, before any opacity-unit-distance correction.
  double evaluateOpacity(double x) const;

  /// Smallest distance between consecutive nodes of either function (infinity with < 2 nodes).
  double smallestNodeGap() const;
};

/// vtkPiecewiseFunction's interpolation between (x1, y1) and (x2, y2) with the left node's
/// midpoint and sharpness, at the normalised position s in [0, 1]. Exposed for tests.
double piecewiseSegment(double s, double y1, double y2, double midpoint, double sharpness);

/// A dense RGBA table over [min, max] (data values): entry i holds the TF at
/// min + i * (max - min) / (width - 1). Opacity is NOT corrected for the sample distance.
/// Lookup (ParaView's texture convention): t = clamp(u * width - 0.5, 0, width - 1) with
/// u = (value - min) / (max - min), then linear interpolation between entries floor(t), floor(t)+1.
struct TransferTable1D
{
  double min = 0, max = 1;
  int width = 0;
  std::vector<float> rgba; ///< width * 4 floats, rgb then alpha per entry

  /// Linear lookup as described above (values outside [min, max] clamp).
  std::array<float, 4> lookup(double value) const;
};

/// Samples `tf` into a table of `width` entries over [min, max]. Throws on width < 2 or min >= max.
TransferTable1D bakeTable(const TransferFunction1D& tf, double min, double max, int width);

/// The table width ParaView's GPU mapper uses for `tf` over a data range [min, max]:
/// max(1024, next power of two of ceil((max - min) / smallest node gap)), capped at 65536.
int paraviewTableWidth(const TransferFunction1D& tf, double min, double max);

/// Converts a dense table back to a ParaView transfer function: colour and opacity control
/// points chosen (Douglas-Peucker on the table) so that re-evaluating them differs from every
/// table entry by at most `tolerance` (per channel, in [0, 1] units). Colour space RGB.
TransferFunction1D tableToTransferFunction(
  const TransferTable1D& table, double tolerance = 1.0 / 512.0, const std::string& name = "ddg");

} // namespace ddg
