// VolumeBrick.cxx: a piece's ownership, its validation and the tiling check of a decomposition.
#include "Volume/VolumeBrick.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ddg
{

namespace
{
const char* const kAxis[3] = { "x", "y", "z" };
}

bool VolumeBrick::ownsNothing() const
{
  return ownedCells() == 0;
}

std::int64_t VolumeBrick::ownedCells() const
{
  std::int64_t n = 1;
  for (int a = 0; a < 3; ++a)
    n *= std::max(0, ownedMax[a] - ownedMin[a]);
  return n;
}

std::array<double, 6> VolumeBrick::wholeBounds(const std::array<double, 3>& spacing) const
{
  std::array<double, 6> b{};
  for (int a = 0; a < 3; ++a)
  {
    b[2 * a] = wholeOrigin[a];
    b[2 * a + 1] = wholeOrigin[a] + (wholeDims[a] - 1) * spacing[a];
  }
  return b;
}

double VolumeBrick::gradientMagnitudeMax(const Volume& piece) const
{
  if (ownsNothing())
    return 0.0;
  validate(piece, true);
  std::array<int, 3> lo{}, hi{};
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = ownedMin[a] - offset[a];
    hi[a] = ownedMax[a] - offset[a];
  }
  return piece.gradientMagnitudeMax(lo, hi, wholeDims);
}

void VolumeBrick::validate(const Volume& piece, bool gradients) const
{
  const auto& d = piece.dims();
  for (int a = 0; a < 3; ++a)
  {
    std::ostringstream msg;
    msg << "volume piece along " << kAxis[a] << ": ";
    if (wholeDims[a] < 2)
      msg << "the whole volume has " << wholeDims[a] << " point(s); at least 2 are needed";
    else if (offset[a] < 0 || offset[a] + d[a] > wholeDims[a])
      msg << "points " << offset[a] << ".." << offset[a] + d[a] - 1
          << " lie outside the whole volume's 0.." << wholeDims[a] - 1;
    else if (ownedMin[a] < offset[a] || ownedMax[a] > offset[a] + d[a] - 1 ||
      ownedMax[a] < ownedMin[a])
      msg << "owns points " << ownedMin[a] << ".." << ownedMax[a] << " but holds " << offset[a]
          << ".." << offset[a] + d[a] - 1;
    else if (gradients && !ownsNothing() &&
      ((ownedMin[a] > 0 && offset[a] > ownedMin[a] - 1) ||
        (ownedMax[a] < wholeDims[a] - 1 && offset[a] + d[a] - 1 < ownedMax[a] + 1)))
      msg
        << "gradients (Shade, 2D transfer functions) need one ghost point beside the owned points "
        << ownedMin[a] << ".." << ownedMax[a] << " but the piece holds " << offset[a] << ".."
        << offset[a] + d[a] - 1 << " (mismatched ghost levels)";
    else if (std::abs(piece.spacing()[a] - spacing[a]) > 1e-9 * std::abs(spacing[a]))
      msg << "its spacing is " << piece.spacing()[a] << ", the whole volume's " << spacing[a];
    else
    {
      const double expected = wholeOrigin[a] + offset[a] * piece.spacing()[a];
      const double tolerance = 1e-6 * std::max(1.0, std::abs(piece.spacing()[a]) * wholeDims[a]);
      if (std::abs(piece.origin()[a] - expected) <= tolerance)
        continue;
      msg << "its first point sits at " << piece.origin()[a] << ", the whole volume's point "
          << offset[a] << " at " << expected;
    }
    throw Error(msg.str());
  }
}

void checkBricksTile(const std::vector<VolumeBrick>& bricks)
{
  if (bricks.empty())
    throw Error("no volume pieces");
  const auto& whole = bricks.front().wholeDims;
  std::int64_t wholeCells = 1, owned = 0;
  for (int a = 0; a < 3; ++a)
    wholeCells *= std::max(0, whole[a] - 1);
  for (size_t i = 0; i < bricks.size(); ++i)
  {
    const VolumeBrick& b = bricks[i];
    if (b.wholeDims != whole)
      throw Error(
        "volume pieces " + std::to_string(i) + " and 0 disagree on the whole volume's size");
    for (int a = 0; a < 3; ++a)
      if (!b.ownsNothing() && (b.ownedMin[a] < 0 || b.ownedMax[a] > whole[a] - 1))
        throw Error("volume piece " + std::to_string(i) + " owns points outside the whole volume");
    owned += b.ownedCells();
    for (size_t k = 0; k < i; ++k)
    {
      const VolumeBrick& c = bricks[k];
      bool overlap = !b.ownsNothing() && !c.ownsNothing();
      for (int a = 0; a < 3 && overlap; ++a)
        overlap = std::max(b.ownedMin[a], c.ownedMin[a]) < std::min(b.ownedMax[a], c.ownedMax[a]);
      if (overlap)
        throw Error("volume pieces " + std::to_string(k) + " and " + std::to_string(i) +
          " own the same cells (the split is not a partition)");
    }
  }
  if (owned != wholeCells)
  {
    std::ostringstream msg;
    msg << "the volume's pieces own " << owned << " of its " << wholeCells
        << " cells: every cell must belong to exactly one piece";
    throw Error(msg.str());
  }
}

} // namespace ddg
