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
  return compositeBricks(parts,
    std::vector<PixelRect>(
      parts.size(), PixelRect{ 0, 0, std::max(width, 0), std::max(height, 0) }),
    width, height);
}

Image compositeBricks(const std::vector<const float*>& parts, const std::vector<PixelRect>& rects,
  int width, int height)
{
  if (parts.empty())
    throw Error("sort-last compositing: no images");
  if (width <= 0 || height <= 0)
    throw Error("sort-last compositing: empty image size");
  if (rects.size() != parts.size())
    throw Error("sort-last compositing: one rectangle per image");
  for (const PixelRect& r : rects)
    if (!r.empty() && (r.x < 0 || r.y < 0 || r.x + r.width > width || r.y + r.height > height))
      throw Error("sort-last compositing: a piece's rectangle lies outside the image");
  Image out(width, height, 4, 0.0f);
  const int n = static_cast<int>(parts.size());
  parallelFor(height, 0,
    [&](std::int64_t y, int)
    {
      // the parts whose rectangles cross this row, and where the row starts in each
      std::vector<int> row, order;
      for (int i = 0; i < n; ++i)
      {
        const PixelRect& r = rects[static_cast<size_t>(i)];
        if (!r.empty() && y >= r.y && y < r.y + r.height)
          row.push_back(i);
      }
      for (int x = 0; x < width; ++x)
      {
        auto at = [&](int i)
        {
          const PixelRect& r = rects[static_cast<size_t>(i)];
          return parts[static_cast<size_t>(i)] +
            5 * ((static_cast<std::int64_t>(y) - r.y) * r.width + (x - r.x));
        };
        order.clear();
        for (int i : row)
        {
          const PixelRect& r = rects[static_cast<size_t>(i)];
          if (x >= r.x && x < r.x + r.width)
            order.push_back(i);
        }
        std::sort(order.begin(), order.end(), [&](int a, int b) { return at(a)[4] < at(b)[4]; });
        float c[4] = { 0, 0, 0, 0 };
        for (int i : order)
        {
          const float* q = at(i);
          const float t = 1.0f - c[3];
          for (int k = 0; k < 4; ++k)
            c[k] += t * q[k];
        }
        const size_t p = static_cast<size_t>(y) * width + x;
        for (int k = 0; k < 4; ++k)
          out.pixels[4 * p + k] = c[k];
      }
    });
  return out;
}

PixelRect footprint(const Image& part)
{
  if (part.channels != 5)
    throw Error("sort-last compositing: a piece's image has five channels");
  int x0 = part.width, y0 = part.height, x1 = -1, y1 = -1;
  for (int y = 0; y < part.height; ++y)
    for (int x = 0; x < part.width; ++x)
      if (part.pixels[5 * (static_cast<size_t>(y) * part.width + x) + 3] > 0.0f)
      {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  return x1 < 0 ? PixelRect{} : PixelRect{ x0, y0, x1 - x0 + 1, y1 - y0 + 1 };
}

std::vector<float> cropPixels(const Image& part, const PixelRect& rect)
{
  if (!rect.empty() &&
    (rect.x < 0 || rect.y < 0 || rect.x + rect.width > part.width ||
      rect.y + rect.height > part.height))
    throw Error("cropPixels: the rectangle lies outside the image");
  const size_t ch = static_cast<size_t>(part.channels);
  std::vector<float> out(static_cast<size_t>(rect.pixels()) * ch);
  for (int y = 0; y < rect.height; ++y)
  {
    const float* from =
      part.pixels.data() + (static_cast<size_t>(rect.y + y) * part.width + rect.x) * ch;
    std::copy(from, from + static_cast<size_t>(rect.width) * ch,
      out.data() + static_cast<size_t>(y) * rect.width * ch);
  }
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
