// SortLast.cxx: per-pixel front-to-back compositing of the pieces' images.
#include "Render/SortLast.h"

#include "Common/Error.h"
#include "Common/Parallel.h"

#include <algorithm>
#include <numeric>

namespace ddg
{

Image compositeBricks(const std::vector<const float*>& parts, int width, int height)
{
  if (parts.empty())
    throw Error("sort-last compositing: no images");
  if (width <= 0 || height <= 0)
    throw Error("sort-last compositing: empty image size");
  Image out(width, height, 4, 0.0f);
  const int n = static_cast<int>(parts.size());
  parallelFor(height, 0,
    [&](std::int64_t y, int)
    {
      std::vector<int> order(static_cast<size_t>(n));
      for (int x = 0; x < width; ++x)
      {
        const size_t p = static_cast<size_t>(y) * width + x;
        std::iota(order.begin(), order.end(), 0);
        std::sort(order.begin(), order.end(),
          [&](int a, int b) { return parts[a][5 * p + 4] < parts[b][5 * p + 4]; });
        float c[4] = { 0, 0, 0, 0 };
        for (int i : order)
        {
          const float* q = parts[static_cast<size_t>(i)] + 5 * p;
          const float t = 1.0f - c[3];
          for (int k = 0; k < 4; ++k)
            c[k] += t * q[k];
        }
        for (int k = 0; k < 4; ++k)
          out.pixels[4 * p + k] = c[k];
      }
    });
  return out;
}

Image compositeBricks(const std::vector<Image>& parts)
{
  std::vector<const float*> data;
  for (const Image& part : parts)
  {
    if (part.channels != 5 || part.width != parts.front().width ||
      part.height != parts.front().height)
      throw Error("sort-last compositing: the pieces' images must be five channels of one size");
    data.push_back(part.pixels.data());
  }
  return compositeBricks(
    data, parts.empty() ? 0 : parts.front().width, parts.empty() ? 0 : parts.front().height);
}

} // namespace ddg
