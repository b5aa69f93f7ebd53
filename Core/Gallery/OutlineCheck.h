// OutlineCheck.h: how many of a design space's outline designs show structure: a sample of the
// outline's designs, each with the explicit TF a user would apply, judged at the three canonical
// views (DesignCheck.h: empty, or a flat box — the volume's box painted, opaque or hazy).
#pragma once

#include "Design/DesignCheck.h"
#include "Gallery/Gallery.h"

namespace ddg
{

struct OutlineCheck
{
  std::vector<int> rows;               ///< the outline rows checked (ascending)
  std::vector<DesignVerdict> verdicts; ///< one per row
  int empty = 0, flatBox = 0;
  /// 1D designs whose mean opacity over the voxels of the volume's six boundary faces exceeds
  /// 0.01 (air made visible where it meets the box, though perhaps too faint to paint it;
  /// 2D designs are not counted)
  int hazyFaces = 0;
  double junkFraction() const
  {
    return rows.empty() ? 0.0 : static_cast<double>(empty + flatBox) / rows.size();
  }
  /// Every checked design at azimuth 0 (size px) over mid-grey, 8 per row; an empty design is
  /// framed blue, a flat box red.
  Image sheet;
};

/// Checks `count` outline rows drawn without replacement (deterministic from `seed`; all rows
/// when the outline has fewer), each design's TF the decoder's (DesignGallery::primitives) or,
/// for a model without explicit TFs, the design's own (DesignGallery::exemplar). Designs are
/// judged in parallel. Throws ddg::Error for count < 1.
OutlineCheck checkOutline(
  DesignGallery& gallery, int count, std::uint64_t seed = 1, int size = 64, int threads = 0);

} // namespace ddg
