// TransferFunction2D.h: dense 2D (value x gradient magnitude) transfer function tables.
#pragma once

#include "TransferFunction/GaussianPrimitive.h"

#include <array>
#include <string>
#include <vector>

namespace ddg
{

/// A dense RGBA table over value x gradient magnitude. Entry (i, j), i along value (fastest),
/// j along gradient magnitude, holds the TF at
///   (valueRange[0] + i * dv / (width - 1), gradientRange[0] + j * dg / (height - 1)).
/// Lookup uses the same texel convention per axis as TransferTable1D, then bilinear filtering.
/// Opacity is not corrected for the sample distance.
struct TransferTable2D
{
  std::array<double, 2> valueRange{ 0, 1 };
  std::array<double, 2> gradientRange{ 0, 1 };
  int width = 0;           ///< entries along value
  int height = 0;          ///< entries along gradient magnitude
  std::vector<float> rgba; ///< width * height * 4

  std::array<float, 4> lookup(double value, double gradient) const;
  /// Throws ddg::Error on sizes < 2, mismatched rgba, empty ranges or values outside [0, 1].
  void validate() const;
};

/// A 2D transfer function as the project's 2D JSON holds it: either Gaussian primitives
/// (rasterized on demand) or an explicit table, plus the ranges it is defined over.
struct TransferFunction2D
{
  std::string name;
  std::vector<GaussianPrimitive> primitives; ///< used when table is empty
  TransferTable2D table;                     ///< explicit table (width > 0) wins over primitives

  /// The table to render with: the explicit table, or primitives rasterized at
  /// table.width x table.height (default 256 x 128) over table's ranges.
  TransferTable2D bake() const;
};

} // namespace ddg
