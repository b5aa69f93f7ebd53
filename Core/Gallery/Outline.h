// Outline.h: the design-space outline (paper §5.1): a PCA plane of design latents, the
// thumbnails that cover a region of it, nearest neighbours, principal-axis moves, and the
// outline view's navigation state as plain data.
#pragma once

#include "Gallery/QueryKey.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddg
{

/// Latents of many designs: count x dim floats, row-major, each with the index of the design
/// it came from (sampleExemplar(volume, spec, regions, seed, index)), so a design's TF and views
/// are regenerated from (seed, index) instead of being stored.
struct LatentSet
{
  int dim = 0;
  std::uint64_t seed = 1;
  std::vector<float> values;          ///< count x dim
  std::vector<std::uint64_t> indices; ///< count
  int count() const { return static_cast<int>(indices.size()); }
  const float* row(int i) const { return values.data() + static_cast<size_t>(i) * dim; }
  /// Throws ddg::Error unless values.size() == count * dim, dim >= 1 and every value is finite.
  void validate() const;
};

/// Writes a latent set (outline.bin): "DDGLATNT", uint32 version 1, dim, count, 0, uint64 seed,
/// count uint64 indices, then count x dim IEEE half floats (the latents' spread is ~1, half
/// keeps ~3 significant digits and halves the file). Atomic. Throws ddg::Error on failure.
void writeLatentSet(const LatentSet& set, const std::string& path);
/// Reads it back; throws ddg::Error naming the file for a missing, truncated or corrupt file.
LatentSet readLatentSet(const std::string& path);

/// A rectangle on the outline plane (PCA coordinates), x0 < x1, y0 < y1.
struct OutlineBox
{
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
  bool valid() const; ///< finite, x0 < x1, y0 < y1
};

/// One nearest neighbour: a row of the latent set and its Euclidean distance in latent space.
struct Neighbour
{
  int row = -1;
  double distance = 0;
};

/// The k rows of `set` nearest to `latent` (Euclidean, nearest first, ties by row; k clamped to
/// the set's size).
std::vector<Neighbour> nearestLatents(const LatentSet& set, const float* latent, int k);

/// PCA of a latent set. The components are the eigenvectors of the latents' covariance
/// (dim x dim, Eigen's self-adjoint solver), largest eigenvalue first; the outline plane is
/// the first two, a latent z lands at ((z - mean) . e0, (z - mean) . e1).
class DesignOutline
{
public:
  /// Throws ddg::Error for fewer than 3 latents or dim < 2 (no plane), or non-finite values.
  explicit DesignOutline(LatentSet latents);

  const LatentSet& latents() const { return Latents; }
  int count() const { return Latents.count(); }
  /// Plane coordinates of every latent: count x 2, row-major.
  const std::vector<float>& points() const { return Points; }
  std::array<double, 2> point(int row) const;
  std::array<double, 2> project(const float* latent) const;
  /// The box holding every point, with a 2 % margin.
  OutlineBox bounds() const;
  /// Rows whose points lie in `box`.
  std::vector<int> inside(const OutlineBox& box) const;

  /// Standard deviation of the latents along principal axis k (sqrt of its eigenvalue) and the
  /// fraction of the total variance it explains. k in [0, dim).
  double axisStddev(int k) const;
  double explainedVariance(int k) const;
  /// latent + sum_k steps[k] * axisStddev(k) * e_k: sliders along the principal axes, steps in
  /// standard deviations (steps may be shorter than dim).
  std::vector<float> moveAlongAxes(
    const std::vector<float>& latent, const std::vector<double>& steps) const;

  /// The k rows nearest to `latent` (nearestLatents over its latents, or over their keys when
  /// the outline has a query key: distances are then the keys').
  std::vector<Neighbour> nearest(const float* latent, int k) const;
  /// Finds nearest rows by this key from now on (an empty key: by the latents). Throws
  /// ddg::Error when the key is for another latent size.
  void setQueryKey(QueryKey key);
  const QueryKey& queryKey() const { return Key; }

private:
  LatentSet Latents;
  std::vector<double> Mean;        ///< dim
  std::vector<double> Axes;        ///< dim x dim, row k = e_k
  std::vector<double> Eigenvalues; ///< dim, descending
  std::vector<float> Points;
  QueryKey Key;
  LatentSet Keys; ///< the latents' keys (Key not empty)
};

/// K thumbnails that cover `box` well: farthest-point sampling over the points inside it,
/// starting from a point drawn with `seed` (another seed = "resample"), so that every point of
/// the box is near a thumbnail (small dispersion), not only the dense middle. Returns rows,
/// min(k, points inside) of them; k = 0 gives none. Throws ddg::Error for k < 0 or an invalid box.
std::vector<int> selectThumbnails(
  const DesignOutline& outline, const OutlineBox& box, int k, std::uint64_t seed = 1);

/// Dispersion of a selection: the largest plane distance from a point inside `box` to its
/// nearest selected point (lower = better coverage; infinity when nothing is selected).
double dispersion(
  const DesignOutline& outline, const OutlineBox& box, const std::vector<int>& rows);

/// The outline view's state as plain data (what a panel saves and restores): the stack of boxes
/// (the first is the whole outline; drill-in pushes, back pops), the thumbnail count and the
/// sampling seed. JSON: {"boxes": [[x0, y0, x1, y1], ...], "count": K, "seed": S}.
struct OutlineViewState
{
  std::vector<OutlineBox> boxes;
  int count = 64;
  std::uint64_t seed = 1;

  /// The box shown now (the last one). Throws ddg::Error when there is none.
  const OutlineBox& current() const;
  /// Pushes a sub-box (clipped to the current one; throws when it lies outside it).
  void drillIn(const OutlineBox& box);
  /// Pops back out (no-op at the whole outline).
  void back();
  /// Zooms the current box about (cx, cy) by `factor` (> 1 zooms in) and pans it by (dx, dy)
  /// in plane units; replaces the current box (not a drill-in).
  void zoom(double factor, double cx, double cy);
  void pan(double dx, double dy);
  /// Another sample of thumbnails for the same box.
  void resample() { ++seed; }

  std::string toJson() const;
  static OutlineViewState fromJson(const std::string& text);
};

} // namespace ddg
