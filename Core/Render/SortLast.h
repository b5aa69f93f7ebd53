// SortLast.h: sort-last compositing of the images the pieces of one volume render (RayCaster with
// a VolumeBrick): under `mpiexec -np N pvserver` every rank renders its own piece and the first
// rank puts the images together.
#pragma once

#include "Image/Image.h"

#include <vector>

namespace ddg
{

/// The whole volume's image from its pieces' images (five channels each: premultiplied C, A of
/// the piece's own samples, then the index of its first sample on the ray, +inf where none), all
/// of one view: per pixel, the pieces in the order of their first samples (front to back; the
/// pieces own disjoint runs of the ray's samples), composed "over": C += (1 - A) C_i,
/// A += (1 - A) A_i. The result is the four-channel image one RayCaster renders of the whole,
/// up to float rounding and each piece stopping its rays on its own opacity (ParaView's early
/// termination at 1 - 1/255: at most 1/255 per channel). `parts` point at width x height x 5
/// floats each (e.g. one gathered buffer). Throws ddg::Error for no parts or a bad size.
Image compositeBricks(const std::vector<const float*>& parts, int width, int height);
/// The same from images.
Image compositeBricks(const std::vector<Image>& parts);

} // namespace ddg
