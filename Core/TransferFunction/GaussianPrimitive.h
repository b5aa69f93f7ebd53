// GaussianPrimitive.h: Gaussian TF primitives (the paper's design elements) and their
// rasterization.
#pragma once

#include "TransferFunction/TransferFunction1D.h"

#include <array>
#include <vector>

namespace ddg
{

struct TransferTable2D;

/// One Gaussian bump in TF space. 1D uses mean[0], stddev[0] (data values); 2D adds
/// mean[1], stddev[1] along gradient magnitude. Colour rgb in [0, 1], peak opacity in [0, 1].
struct GaussianPrimitive
{
  std::array<double, 2> mean{ 0, 0 };
  std::array<double, 2> stddev{ 1, 1 };
  std::array<double, 3> rgb{ 1, 1, 1 };
  double opacity = 1.0;
};

/// Throws ddg::Error unless every number is finite, stddev > 0 and rgb/opacity in [0, 1].
void validatePrimitives(const std::vector<GaussianPrimitive>& primitives, bool twoD);

/// Rasterizes primitives into a 1D table over [min, max] with `width` entries:
///   w_i(x) = opacity_i * exp(-(x - mean_i)^2 / (2 stddev_i^2))
///   alpha(x) = min(1, sum_i w_i(x)),  rgb(x) = sum_i w_i rgb_i / sum_i w_i  (0 where sum is 0).
TransferTable1D rasterize1D(
  const std::vector<GaussianPrimitive>& primitives, double min, double max, int width);

/// The same in 2D over value x gradient magnitude, w_i a product of the two 1D Gaussians.
TransferTable2D rasterize2D(const std::vector<GaussianPrimitive>& primitives,
  std::array<double, 2> valueRange, std::array<double, 2> gradientRange, int width, int height);

/// Gradient of a loss with respect to every parameter of a primitive.
struct GaussianPrimitiveGradient
{
  std::array<double, 2> mean{ 0, 0 };
  std::array<double, 2> stddev{ 0, 0 };
  std::array<double, 3> rgb{ 0, 0, 0 };
  double opacity = 0;
};

/// Adjoint of rasterize1D / rasterize2D (chain rule through the blend above): given
/// dL/d(table entries) (RGBA per entry, same layout and ranges as the rasterized table; for 1D
/// height = 1 and gradientRange is ignored), OVERWRITES `gradients` (one per primitive).
/// Where alpha saturates (sum >= 1) the opacity path has zero gradient, as min() does.
void rasterizeAdjoint(const std::vector<GaussianPrimitive>& primitives, bool twoD,
  std::array<double, 2> valueRange, std::array<double, 2> gradientRange, int width, int height,
  const std::vector<double>& dL_dTable, std::vector<GaussianPrimitiveGradient>& gradients);

} // namespace ddg
