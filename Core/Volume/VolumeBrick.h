// VolumeBrick.h: where a piece of a volume sits in the whole volume it was split from (ParaView's
// pieces under `mpiexec -np N pvserver`), which samples it owns, and whether a set of pieces tiles
// the whole.
#pragma once

#include "Volume/Volume.h"

#include <array>
#include <string>
#include <vector>

namespace ddg
{

/// A piece of a whole volume, in the whole's point indices (point (i, j, k) of the whole sits at
/// wholeOrigin + (i, j, k) * spacing; the piece's Volume holds points offset .. offset + dims - 1).
///
/// Ownership: the piece owns the cells [ownedMin, ownedMax) on every axis, i.e. the samples at
/// index positions x with ownedMin <= x < ownedMax, closed at the whole's last point plane
/// (x = wholeDims - 1 belongs to the piece whose ownedMax reaches it). ParaView's pieces share
/// their boundary point plane (vtkExtentTranslator), so the owned points of neighbours meet at
/// one plane and their cells tile the whole. Interpolation in an owned cell needs the points
/// ownedMin .. ownedMax (no ghost); the gradient (Shade, 2D tables) needs one more point on each
/// side that is not a face of the whole (one ghost level).
struct VolumeBrick
{
  std::array<int, 3> wholeDims{ 0, 0, 0 };      ///< points of the whole volume per axis
  std::array<double, 3> wholeOrigin{ 0, 0, 0 }; ///< world position of the whole's point 0
  std::array<double, 3> spacing{ 1, 1, 1 };     ///< the whole's spacing (every piece's)
  std::array<int, 3> offset{ 0, 0, 0 };         ///< whole index of the piece's point 0
  std::array<int, 3> ownedMin{ 0, 0, 0 };       ///< first owned point plane per axis
  std::array<int, 3> ownedMax{ 0, 0, 0 };       ///< last owned point plane per axis
  std::array<double, 2> wholeRange{ 0, 0 };     ///< data range of the whole volume
  /// The whole's Volume::gradientMagnitudeRange, the axis of 2D tables (the largest of the
  /// pieces' gradientMagnitudeMax); [0, 0] until the pieces agree on it (2D reconstruction).
  std::array<double, 2> wholeGradientRange{ 0, 0 };

  /// True when the piece owns no cell (an empty piece, or one point plane thick).
  bool ownsNothing() const;
  /// Owned cells (product of ownedMax - ownedMin).
  std::int64_t ownedCells() const;
  /// The piece's points cover its owned cells, and with `gradients` the ghost points beside them
  /// (one level, except at the whole's faces); the piece lies inside the whole and shares its
  /// spacing (`spacing`) and origin. Throws ddg::Error saying which axis and what is missing.
  void validate(const Volume& piece, bool gradients) const;
  /// The whole's bounds (xmin, xmax, ymin, ...), from wholeOrigin, spacing and wholeDims.
  std::array<double, 6> wholeBounds(const std::array<double, 3>& spacing) const;
  /// The largest gradient magnitude over the points this piece owns (Volume::gradientMagnitudeMax
  /// with the whole's scaling; the piece must hold its ghost points): the whole's is the largest
  /// over its pieces. 0 for a piece that owns nothing.
  double gradientMagnitudeMax(const Volume& piece) const;
};

/// Checks that the owned cells of `bricks` (all of one whole volume) are disjoint and cover the
/// whole's cells: what sort-last compositing needs to give the whole's image. Throws ddg::Error
/// naming the two pieces that overlap, or how many cells are not owned by any.
void checkBricksTile(const std::vector<VolumeBrick>& bricks);

} // namespace ddg
