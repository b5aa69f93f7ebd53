// Edit.h: edits of a design without TF widgets (paper §1): image-space operations on a design's
// render — recolour a feature, make it more or less visible — that are then re-analyzed to a
// latent (DesignGallery::analyzeEdit).
#pragma once

#include "Image/Image.h"

#include <array>
#include <cstdint>
#include <vector>

namespace ddg
{

/// The colour clusters of a design image: k-means in CIELAB over its visible pixels (alpha >
/// 0.05; colour = premultiplied / alpha), k-means++ seeding from a fixed seed, 20 iterations.
/// labels: one per pixel, -1 for pixels that are not visible.
struct ColorClusters
{
  std::vector<std::array<double, 3>> lab; ///< cluster centres
  std::vector<std::array<double, 3>> rgb; ///< mean straight sRGB of each cluster's pixels
  std::vector<double> share;              ///< fraction of the visible pixels in each
  std::vector<int> labels;                ///< width x height
  int width = 0, height = 0;
  int count() const { return static_cast<int>(lab.size()); }
  /// The cluster under pixel (x, y) (-1 when that pixel is not visible). Throws outside the image.
  int at(int x, int y) const;
};

/// Throws ddg::Error unless `rgba` is premultiplied RGBA, k in [1, 16] and some pixel is visible.
/// Fewer clusters than k when there are fewer distinct colours.
ColorClusters colorClusters(const Image& rgba, int k = 4);

/// Which pixels an edit touches: a cluster's pixels, or a brushed mask (1 channel, the image's
/// size, weights in [0, 1]).
struct EditRegion
{
  int cluster = -1; ///< used when mask is empty
  Image mask;
};

/// Throws ddg::Error unless `region` can be edited in `rgba` (premultiplied RGBA): a one-channel
/// mask of the image's size, or a cluster that exists among `clusters` (of this image).
void checkEditRegion(const ColorClusters& clusters, const EditRegion& region, const Image& rgba);

/// Recolours the region: hue rotated by dHue degrees and saturation scaled by satScale (HSV),
/// lightness shifted by dLightness in CIELAB L* units; alpha kept. Returns premultiplied RGBA.
Image recolour(const Image& rgba, const ColorClusters& clusters, const EditRegion& region,
  double dHue, double satScale = 1.0, double dLightness = 0.0);

/// Makes the region more (factor > 1) or less (factor < 1) visible: its alpha scaled by
/// `factor` (clamped to 1), the colour kept. Returns premultiplied RGBA.
Image changeVisibility(
  const Image& rgba, const ColorClusters& clusters, const EditRegion& region, double factor);

} // namespace ddg
