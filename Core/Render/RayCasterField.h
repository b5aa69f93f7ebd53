// RayCasterField.h: the ray caster's prepared volume — the volume's scalars read in place and the
// block min/max of empty-space skipping. Private to Core/Render/RayCaster.cxx.
#pragma once

#include "Common/Parallel.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ddg::raycast
{

constexpr int kBlock = 8; // cells per block side for empty-space skipping

// Min and max of value(index, i, j, k) over the points of every block (block b covers cells
// [8b, 8b + 8), i.e. points 8b .. 8b + 8): bx x by x bz blocks, x fastest.
template <typename F>
void blockRanges(int nx, int ny, int nz, const F& value, std::vector<float>& blockMin,
  std::vector<float>& blockMax, int& bx, int& by, int& bz)
{
  bx = std::max(1, (nx - 1 + kBlock - 1) / kBlock);
  by = std::max(1, (ny - 1 + kBlock - 1) / kBlock);
  bz = std::max(1, (nz - 1 + kBlock - 1) / kBlock);
  blockMin.assign(static_cast<size_t>(bx) * by * bz, 0.0f);
  blockMax.assign(blockMin.size(), 0.0f);
  const size_t sy = static_cast<size_t>(nx), sz = static_cast<size_t>(nx) * ny;
  parallelFor(bz, 0,
    [&](std::int64_t c64, int)
    {
      const int c = static_cast<int>(c64);
      for (int b = 0; b < by; ++b)
      {
        for (int a = 0; a < bx; ++a)
        {
          float lo = value(a * kBlock + sy * b * kBlock + sz * c * kBlock, a * kBlock, b * kBlock,
                  c * kBlock),
                hi = lo;
          for (int k = c * kBlock; k <= std::min(nz - 1, (c + 1) * kBlock); ++k)
            for (int j = b * kBlock; j <= std::min(ny - 1, (b + 1) * kBlock); ++j)
              for (int i = a * kBlock; i <= std::min(nx - 1, (a + 1) * kBlock); ++i)
              {
                const float v = value(i + sy * j + sz * k, i, j, k);
                lo = std::min(lo, v);
                hi = std::max(hi, v);
              }
          const size_t id = (static_cast<size_t>(c) * by + b) * bx + a;
          blockMin[id] = lo;
          blockMax[id] = hi;
        }
      }
    });
}

// Volume prepared for the march: the volume's scalars in their own (compact) type T, x fastest
// (read in place, not copied), and per-block min/max for empty-space skipping. Block b covers cells
// [8b, 8b + 8), i.e. points 8b .. 8b + 8, so a sample in the block only reads points inside the
// block's min/max.
template <typename T>
struct Field
{
  int nx = 0, ny = 0, nz = 0;
  const T* w = nullptr; // the Volume's scalars (RayCaster::Internals::Vol keeps them alive)
  int bx = 0, by = 0, bz = 0;
  std::vector<float> blockMin, blockMax;

  void build(int dx, int dy, int dz, const T* values)
  {
    nx = dx;
    ny = dy;
    nz = dz;
    w = values;
    blockRanges(
      nx, ny, nz, [this](size_t id, int, int, int) { return static_cast<float>(w[id]); }, blockMin,
      blockMax, bx, by, bz);
  }

  size_t index(int i, int j, int k) const
  {
    return static_cast<size_t>(i) +
      static_cast<size_t>(nx) * (static_cast<size_t>(j) + static_cast<size_t>(ny) * k);
  }

  // Trilinear interpolation at index coordinates, clamped to the grid (nx, ny, nz >= 2).
  float sample(float x, float y, float z) const
  {
    x = std::clamp(x, 0.0f, static_cast<float>(nx - 1));
    y = std::clamp(y, 0.0f, static_cast<float>(ny - 1));
    z = std::clamp(z, 0.0f, static_cast<float>(nz - 1));
    const int i = std::min(static_cast<int>(x), nx - 2);
    const int j = std::min(static_cast<int>(y), ny - 2);
    const int k = std::min(static_cast<int>(z), nz - 2);
    const float fx = x - i, fy = y - j, fz = z - k;
    const size_t sy = static_cast<size_t>(nx), sz = static_cast<size_t>(nx) * ny;
    const T* p = w + index(i, j, k);
    auto v = [p](size_t o) { return static_cast<float>(p[o]); };
    const float c00 = v(0) + fx * (v(1) - v(0));
    const float c10 = v(sy) + fx * (v(sy + 1) - v(sy));
    const float c01 = v(sz) + fx * (v(sz + 1) - v(sz));
    const float c11 = v(sz + sy) + fx * (v(sz + sy + 1) - v(sz + sy));
    const float c0 = c00 + fy * (c10 - c00);
    const float c1 = c01 + fy * (c11 - c01);
    return c0 + fz * (c1 - c0);
  }
};

} // namespace ddg::raycast
