// FramedColours.cxx: the square on a picture's content and its colours (Reconstruction.h:
// framedColours; FramedColours.h: framedPixels).
#include "Reconstruct/FramedColours.h"

#include "Common/Error.h"
#include "Reconstruct/Reconstruction.h"

#include <algorithm>
#include <cmath>

namespace ddg
{

std::vector<int> framedPixels(const float* rgb, int w, int h, const View& view,
  const std::vector<std::uint8_t>& leaveOut, std::vector<float>* radii)
{
  int x0 = w, y0 = h, x1 = -1, y1 = -1;
  for (int y = 0; y < h; ++y)
  {
    const auto bg = view.backgroundAt(y);
    for (int x = 0; x < w; ++x)
    {
      if (!leaveOut.empty() && leaveOut[static_cast<size_t>(y) * w + x])
        continue;
      const float* c = rgb + 3 * (static_cast<size_t>(y) * w + x);
      if (std::abs(c[0] - bg[0]) > 0.04 || std::abs(c[1] - bg[1]) > 0.04 ||
        std::abs(c[2] - bg[2]) > 0.04)
      {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
    }
  }
  int sx = 0, sy = 0, sw = w, sh = h; // nothing differs: the whole image
  if (x1 >= 0)
  {
    sw = sh = std::max(4, static_cast<int>(std::lround(1.1 * std::max(x1 - x0 + 1, y1 - y0 + 1))));
    sx = (x0 + x1 + 1 - sw) / 2;
    sy = (y0 + y1 + 1 - sh) / 2;
  }
  std::vector<int> pixels;
  if (radii)
    radii->clear();
  for (int y = sy; y < sy + sh; ++y)
    for (int x = sx; x < sx + sw; ++x)
    {
      const bool in = x >= 0 && y >= 0 && x < w && y < h;
      const int p = in ? y * w + x : -1;
      if (p >= 0 && !leaveOut.empty() && leaveOut[static_cast<size_t>(p)])
        continue;
      pixels.push_back(p);
      if (radii)
        radii->push_back(static_cast<float>(
          std::hypot(x - sx + 0.5 - 0.5 * sw, y - sy + 0.5 - 0.5 * sh) / (0.5 * sw)));
    }
  return pixels;
}

std::vector<std::array<float, 3>> framedColours(
  const Image& picture, const View& view, const Image& leaveOut, std::vector<float>* radii)
{
  if (picture.channels != 3 || picture.width != view.width || picture.height != view.height)
    throw Error("framedColours needs an RGB picture of its view's size");
  std::vector<std::uint8_t> out;
  if (!leaveOut.empty())
  {
    if (leaveOut.width != picture.width || leaveOut.height != picture.height)
      throw Error("framedColours: the mask's size differs from the picture's");
    for (size_t i = 0; i < static_cast<size_t>(picture.width) * picture.height; ++i)
      out.push_back(leaveOut.pixels[i * leaveOut.channels] > 0.5f);
  }
  std::vector<std::array<float, 3>> colours;
  for (const int p :
    framedPixels(picture.pixels.data(), picture.width, picture.height, view, out, radii))
  {
    if (p < 0)
      colours.push_back({ static_cast<float>(view.background[0]),
        static_cast<float>(view.background[1]), static_cast<float>(view.background[2]) });
    else
      colours.push_back({ picture.pixels[3 * static_cast<size_t>(p)],
        picture.pixels[3 * static_cast<size_t>(p) + 1],
        picture.pixels[3 * static_cast<size_t>(p) + 2] });
  }
  return colours;
}

} // namespace ddg
