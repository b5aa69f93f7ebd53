// ImageMetrics.h: PSNR and SSIM between two images of the same size, and the colour-histogram
// EMD between any two images.
#pragma once

#include "Image/Image.h"

#include <array>
#include <cstddef>
#include <random>
#include <vector>

namespace ddg
{

/// PSNR in dB over the first 3 channels (RGB) of two images with values in [0, 1]:
/// 10 log10(1 / MSE). Returns +infinity for identical images. Throws ddg::Error when the
/// sizes differ or an image has fewer than 3 channels (grey images are expanded first).
double psnr(const Image& a, const Image& b);
/// The same over the pixels `ignore` (one channel, the same size; empty: none) leaves: those
/// where it is at most 0.5 (e.g. a picture's overlays left out). Infinite when nothing differs.
double psnr(const Image& a, const Image& b, const Image& ignore);

/// Mean SSIM (Wang et al. 2004) over RGB: 11 x 11 Gaussian window (sigma 1.5), K1 = 0.01,
/// K2 = 0.03, dynamic range 1, computed per channel on the "valid" window positions
/// (windows fully inside the image) and averaged. Images smaller than 11 px use the largest
/// odd window that fits.
double ssim(const Image& a, const Image& b);

/// SSIM of two RGB images given as raw arrays (w * h * 3, interleaved) with its gradient with
/// respect to the first: the same definition as ssim() (mean over channels and valid windows).
/// OVERWRITES dS_dx (w * h * 3). Used as a loss term (1 - SSIM) by the reconstruction.
double ssimWithGradient(const float* x, const float* y, int width, int height, double* dS_dx);

/// Colour-histogram earth mover's distance (Berger et al. 2019): CIELAB histograms of the RGB
/// pixels (sRGB, D65; vtkMath's conversion) with 8 x 12 x 12 bins over L in [0, 100],
/// a in [-86.185, 98.254], b in [-107.863, 94.482] (values outside clamp to the edge bins),
/// normalised by the pixel count; ground distance = Euclidean distance between bin centres in
/// Lab units; exact EMD (min-cost flow: LEMON's network simplex on integer pixel masses, ground
/// distances rounded to 2^-40 for the solver, so within ~1e-12 of the exact optimum). 0 for
/// identical colour distributions. Images may differ in size.
double colorHistogramEMD(const Image& a, const Image& b);

/// Sliced Wasserstein distance between two sets of points in 3D (e.g. colours in CIELAB): the
/// mean over `directions` unit vectors (drawn uniformly on the sphere from `rng`) of the mean
/// squared difference between a's projections, sorted, and b's projections at the same ranks
/// (b's quantile (i + 0.5) / n, linear between its order statistics), so the sets may differ in
/// size. With `gradient`: OVERWRITES it with the derivative with respect to a's points (each
/// rank's partner held fixed: exact wherever no two projections of a tie). The directions are
/// shared among `threads` workers (0: all cores); the result does not depend on their number.
/// Throws ddg::Error for an empty set or directions < 1.
double slicedWasserstein(const std::vector<std::array<float, 3>>& a,
  const std::vector<std::array<float, 3>>& b, int directions, std::mt19937_64& rng,
  std::vector<std::array<float, 3>>* gradient = nullptr, int threads = 1);
/// The same in 2D (e.g. a colour's lightness and where it lies in the picture): the directions
/// drawn on the circle.
double slicedWasserstein(const std::vector<std::array<float, 2>>& a,
  const std::vector<std::array<float, 2>>& b, int directions, std::mt19937_64& rng,
  std::vector<std::array<float, 2>>* gradient = nullptr, int threads = 1);

/// A set of points b (e.g. a picture's colours) projected on a fixed pool of directions, each
/// projection sorted once: the sliced Wasserstein distance against it draws its directions from
/// the pool, so that b is not sorted again at every call (a fit compares its renders with the
/// same picture hundreds of times; sorting the picture had taken 60 % of the carried look).
template <size_t D>
struct SortedProjections
{
  std::vector<std::array<double, D>> directions; ///< unit vectors, drawn as slicedWasserstein's
  std::vector<float> sorted; ///< per direction, b's `count` projections ascending
  size_t count = 0;
};
/// b on `pool` directions drawn from `rng` (sorted by `threads` workers, 0: all cores). Throws
/// ddg::Error for an empty set or pool < 1.
SortedProjections<3> sortedProjections(
  const std::vector<std::array<float, 3>>& b, int pool, std::mt19937_64& rng, int threads = 1);
SortedProjections<2> sortedProjections(
  const std::vector<std::array<float, 2>>& b, int pool, std::mt19937_64& rng, int threads = 1);
/// slicedWasserstein against b's pooled projections: `directions` distinct directions of the
/// pool drawn from `rng` (all of them when the pool has no more), b's quantiles read from its
/// sorted projections; otherwise the same definition, gradient and thread independence.
double slicedWasserstein(const std::vector<std::array<float, 3>>& a, const SortedProjections<3>& b,
  int directions, std::mt19937_64& rng, std::vector<std::array<float, 3>>* gradient = nullptr,
  int threads = 1);
double slicedWasserstein(const std::vector<std::array<float, 2>>& a, const SortedProjections<2>& b,
  int directions, std::mt19937_64& rng, std::vector<std::array<float, 2>>* gradient = nullptr,
  int threads = 1);

} // namespace ddg
