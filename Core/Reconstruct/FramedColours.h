// FramedColours.h: the square a picture's colours are taken from, shared by framedColours and
// the colour targets' term of the reconstruction (Reconstruction.cxx). Internal to Core.
#pragma once

#include "Render/View.h"

#include <cstdint>
#include <vector>

namespace ddg
{

/// The pixels (index y w + x; -1: beyond the image) of the square framedColours describes, for
/// an RGB image (3 floats per pixel) at `view`; those `leaveOut` sets are left out (of the
/// content's box too: an overlay in a corner does not widen the square). With `radii`: each
/// pixel's distance from the square's centre in half-sides.
std::vector<int> framedPixels(const float* rgb, int w, int h, const View& view,
  const std::vector<std::uint8_t>& leaveOut, std::vector<float>* radii = nullptr);

} // namespace ddg
