// SortLast.h: sort-last compositing of the images the pieces of one volume render (RayCaster with
// a VolumeBrick): under `mpiexec -np N pvserver` every rank renders its own piece and the first
// rank puts the images together.
#pragma once

#include "Image/Image.h"

#include <cstdint>
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

/// A rectangle of an image's pixels: columns x .. x + width - 1, rows y .. y + height - 1.
struct PixelRect
{
  int x = 0, y = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
  std::int64_t pixels() const { return empty() ? 0 : static_cast<std::int64_t>(width) * height; }
};

/// Where a piece's image (five channels, as compositeBricks reads them) adds anything to the
/// composite: the smallest rectangle holding its pixels with opacity A > 0 (their premultiplied
/// colour is 0 where A is 0, and "over" with nothing leaves the composite as it is). Empty when
/// the piece shows nowhere.
PixelRect footprint(const Image& part);
/// The pixels of `part` in `rect`, row by row (rect.pixels() x channels floats).
std::vector<float> cropPixels(const Image& part, const PixelRect& rect);
/// compositeBricks of cropped parts: parts[p] holds the five-channel pixels of rects[p] of a
/// width x height image (cropPixels); a pixel outside a part's rectangle gets nothing from that
/// part. The same image as compositing the uncropped parts when each rectangle holds its part's
/// footprint.
Image compositeBricks(const std::vector<const float*>& parts, const std::vector<PixelRect>& rects,
  int width, int height);

/// Sort-last compositing of a list of pixels and what its adjoint needs, for the differentiable
/// renderer over pieces (DifferentiableRendererT with a PieceExchange). rgba[p] points at piece
/// p's n x 4 floats (premultiplied C, A of its own samples), keys[p] at its n first-sample
/// indices (+inf where it has none). Per pixel, as compositeBricks (in double): out gets the
/// composite (n x 4); for piece `mine`, front gets the opacity A_F of the pieces in front of it
/// (n) and back the composite (C_B, A_B) of the pieces behind it (n x 4).
void compositePixels(const std::vector<const float*>& rgba, const std::vector<const float*>& keys,
  std::int64_t n, int mine, float* out, float* front, float* back);

/// The adjoint for piece `mine`: from g = dL/d(composite) (n x 4) and that piece's front and back
/// (compositePixels), dL/d(its C) = (1 - A_F) g_C and dL/d(its A) = (1 - A_F) (g_A (1 - A_B) -
/// g_C . C_B), into dPiece (n x 4): out = F over (piece over B).
void compositePixelsAdjoint(
  const float* g, const float* front, const float* back, std::int64_t n, float* dPiece);

} // namespace ddg
