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

void compositePixels(const std::vector<const float*>& rgba, const std::vector<const float*>& keys,
  std::int64_t n, int mine, float* out, float* front, float* back)
{
  const int pieces = static_cast<int>(rgba.size());
  if (pieces < 1 || keys.size() != rgba.size() || mine < 0 || mine >= pieces || n < 0)
    throw Error("sort-last compositing: the pieces' pixels do not match");
  parallelFor((n + 255) / 256, 0,
    [&](std::int64_t chunk, int)
    {
      std::vector<int> order(static_cast<size_t>(pieces));
      for (std::int64_t q = chunk * 256; q < std::min(n, (chunk + 1) * 256); ++q)
      {
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(
          order.begin(), order.end(), [&](int a, int b) { return keys[a][q] < keys[b][q]; });
        double c[4] = { 0, 0, 0, 0 }, b[4] = { 0, 0, 0, 0 };
        bool behind = false;
        for (int i : order)
        {
          const float* p = rgba[static_cast<size_t>(i)] + 4 * q;
          if (i == mine)
          {
            front[q] = static_cast<float>(c[3]);
            behind = true;
          }
          else if (behind)
          {
            const double tb = 1.0 - b[3];
            for (int k = 0; k < 4; ++k)
              b[k] += tb * p[k];
          }
          const double t = 1.0 - c[3];
          for (int k = 0; k < 4; ++k)
            c[k] += t * p[k];
        }
        for (int k = 0; k < 4; ++k)
        {
          out[4 * q + k] = static_cast<float>(c[k]);
          back[4 * q + k] = static_cast<float>(b[k]);
        }
      }
    });
}

void compositePixelsAdjoint(
  const float* g, const float* front, const float* back, std::int64_t n, float* dPiece)
{
  for (std::int64_t q = 0; q < n; ++q)
  {
    const double t = 1.0 - front[q];
    const float* gq = g + 4 * q;
    const float* b = back + 4 * q;
    const double gDotC = static_cast<double>(gq[0]) * b[0] + static_cast<double>(gq[1]) * b[1] +
      static_cast<double>(gq[2]) * b[2];
    for (int k = 0; k < 3; ++k)
      dPiece[4 * q + k] = static_cast<float>(t * gq[k]);
    dPiece[4 * q + 3] = static_cast<float>(t * (gq[3] * (1.0 - b[3]) - gDotC));
  }
}

} // namespace ddg
