// QueryImage.cxx: query images to analyzer inputs.
#include "Gallery/QueryImage.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ddg
{

Image prepareQueryImage(const Image& image, int size)
{
  if (size < 8)
    throw Error("the analyzer input must be at least 8 pixels");
  if (image.width < 8 || image.height < 8)
    throw Error("the query image is " + std::to_string(image.width) + " x " +
      std::to_string(image.height) + " pixels: too small (at least 8 x 8)");
  if (image.width > 16384 || image.height > 16384)
    throw Error("the query image is " + std::to_string(image.width) + " x " +
      std::to_string(image.height) + " pixels: too large (at most 16384 on a side)");
  if (image.channels < 1 || image.channels > 4)
    throw Error("the query image has " + std::to_string(image.channels) +
      " channels (gray, gray+alpha, RGB or RGBA expected)");
  for (float v : image.pixels)
    if (!std::isfinite(v))
      throw Error("the query image holds non-finite values");
  // 1. RGB over black
  const int w = image.width, h = image.height;
  Image rgb(w, h, 3);
  const bool alpha = image.channels == 2 || image.channels == 4;
  bool anyAlpha = !alpha;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      const float a = alpha ? std::clamp(image.at(x, y, image.channels - 1), 0.0f, 1.0f) : 1.0f;
      anyAlpha = anyAlpha || a > 0;
      for (int c = 0; c < 3; ++c)
      {
        const float v = image.at(x, y, image.channels >= 3 ? c : 0);
        rgb.at(x, y, c) = std::clamp(v, 0.0f, 1.0f) * a;
      }
    }
  if (!anyAlpha)
    throw Error("the query image is fully transparent (alpha is 0 everywhere)");
  // 2. background = median of the border, content = pixels that differ from it
  std::array<float, 3> bg{};
  for (int c = 0; c < 3; ++c)
  {
    std::vector<float> border;
    for (int x = 0; x < w; ++x)
    {
      border.push_back(rgb.at(x, 0, c));
      border.push_back(rgb.at(x, h - 1, c));
    }
    for (int y = 1; y < h - 1; ++y)
    {
      border.push_back(rgb.at(0, y, c));
      border.push_back(rgb.at(w - 1, y, c));
    }
    std::nth_element(border.begin(), border.begin() + border.size() / 2, border.end());
    bg[c] = border[border.size() / 2];
  }
  int x0 = w, y0 = h, x1 = -1, y1 = -1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      bool content = false;
      for (int c = 0; c < 3; ++c)
        content = content || std::abs(rgb.at(x, y, c) - bg[c]) > 0.04f;
      if (content)
      {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
    }
  if (x1 < 0)
    throw Error("the query image shows nothing: every pixel is the background colour");
  // 3. a square of the shorter side on the content's centre, inside the image if it fits
  const int extent = std::max(x1 - x0 + 1, y1 - y0 + 1);
  const int side = std::max(std::min(w, h), extent);
  auto place = [side](double centre, int length)
  {
    int o = static_cast<int>(std::lround(centre - 0.5 * side));
    if (side <= length)
      o = std::clamp(o, 0, length - side);
    return o;
  };
  const int ox = place(0.5 * (x0 + x1 + 1), w), oy = place(0.5 * (y0 + y1 + 1), h);
  Image square(side, side, 3);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
    {
      const int sx = ox + x, sy = oy + y;
      const bool in = sx >= 0 && sx < w && sy >= 0 && sy < h;
      for (int c = 0; c < 3; ++c)
        square.at(x, y, c) = in ? rgb.at(sx, sy, c) : bg[c];
    }
  // 4. the model's size, quantised to 8 bits as the training images are
  // halve by 2 x 2 box averages while the square is over 4x the size (exact area averages,
  // much cheaper than one wide filtered resize), then the filtered resize
  while (square.width >= 4 * size)
  {
    const int hw = square.width / 2;
    Image half(hw, hw, 3);
    for (int y = 0; y < hw; ++y)
      for (int x = 0; x < hw; ++x)
        for (int c = 0; c < 3; ++c)
          half.at(x, y, c) = 0.25f *
            (square.at(2 * x, 2 * y, c) + square.at(2 * x + 1, 2 * y, c) +
              square.at(2 * x, 2 * y + 1, c) + square.at(2 * x + 1, 2 * y + 1, c));
    square = std::move(half);
  }
  Image out = square.width == size ? square : resizeImage(square, size, size);
  for (float& v : out.pixels)
    v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
  return out;
}

} // namespace ddg
