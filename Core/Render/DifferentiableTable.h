// DifferentiableTable.h: the differentiable renderer's per-sample pieces — trilinear sampling of
// the scalars in their own type (one sample or a batch), the transfer function table prepared for
// a step (clamped, opacity corrected) with its chain rule, and the 1D/2D lookup with its adjoint
// (SSE2 vector code for float RGBA). Private to Core/Render/DifferentiableRenderer.cxx.
#pragma once

#include "Render/Adjoint.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace ddg::differentiable
{

// Sampling of a scalar field (values in their compact type T, or the float gradient magnitude)
// at index coordinates, clamped to the grid.
template <typename S, typename T = float>
struct FieldSampler
{
  const T* v = nullptr;
  int nx = 0, ny = 0, nz = 0;

  // Corner values and fractions of the cell holding p.
  void cell(const S p[3], S c[8], S f[3]) const
  {
    const int n[3] = { nx, ny, nz };
    int i[3];
    for (int a = 0; a < 3; ++a)
    {
      const S x = std::clamp(p[a], S(0), static_cast<S>(n[a] - 1));
      i[a] = std::min(static_cast<int>(x), n[a] - 2);
      f[a] = x - static_cast<S>(i[a]);
    }
    const size_t sy = static_cast<size_t>(nx), sz = static_cast<size_t>(nx) * ny;
    const T* q = v + static_cast<size_t>(i[0]) + sy * i[1] + sz * i[2];
    c[0] = static_cast<S>(q[0]);
    c[1] = static_cast<S>(q[1]);
    c[2] = static_cast<S>(q[sy]);
    c[3] = static_cast<S>(q[sy + 1]);
    c[4] = static_cast<S>(q[sz]);
    c[5] = static_cast<S>(q[sz + 1]);
    c[6] = static_cast<S>(q[sz + sy]);
    c[7] = static_cast<S>(q[sz + sy + 1]);
  }

  S sample(const S p[3]) const
  {
    S c[8], f[3];
    cell(p, c, f);
    return adjoint::trilinear(c, f[0], f[1], f[2]);
  }

  // Values at kBatch consecutive samples e + (k0 + l) st (independent: vectorisable); the same
  // arithmetic as sample().
  static constexpr int kBatch = 8;
  void sampleBatch(const S e[3], const S st[3], S k0, S* out) const
  {
    const int n[3] = { nx, ny, nz };
    std::int64_t idx[kBatch];
    S f[3][kBatch];
    for (int l = 0; l < kBatch; ++l)
    {
      const S kk = k0 + static_cast<S>(l);
      int i[3];
      for (int a = 0; a < 3; ++a)
      {
        const S x = std::min(std::max(e[a] + kk * st[a], S(0)), static_cast<S>(n[a] - 1));
        i[a] = std::min(static_cast<int>(x), n[a] - 2);
        f[a][l] = x - static_cast<S>(i[a]);
      }
      idx[l] = i[0] + static_cast<std::int64_t>(nx) * (i[1] + static_cast<std::int64_t>(ny) * i[2]);
    }
    adjoint::trilinearBatch(v, idx, static_cast<std::int64_t>(nx),
      static_cast<std::int64_t>(nx) * ny, f[0], f[1], f[2], out);
  }
};

// A dense table prepared for rendering: rgb clamped to [0, 1], opacity corrected for the step
// and clamped to kMaxOpacity. chain() turns gradients w.r.t. the prepared entries into
// gradients w.r.t. the raw entries.
template <typename S>
struct PreparedTable
{
  std::vector<S> entries; // n * 4
  const S* raw = nullptr;
  S exponent = 1;

  void prepare(const S* table, size_t n, S e)
  {
    raw = table;
    exponent = e;
    entries.resize(n * 4);
    for (size_t i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        entries[4 * i + c] = std::clamp(table[4 * i + c], S(0), S(1));
      }
      const S a = std::clamp(table[4 * i + 3], S(0), S(1));
      entries[4 * i + 3] =
        std::min(adjoint::correctOpacity(a, e), static_cast<S>(adjoint::kMaxOpacity));
    }
  }

  // dL/d(raw) += dL/d(prepared) * d(prepared)/d(raw), entry by entry.
  void chain(const std::vector<S>& dPrepared, std::vector<S>& dRaw) const
  {
    const size_t n = entries.size() / 4;
    for (size_t i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        const S r = raw[4 * i + c];
        if (r >= S(0) && r <= S(1))
        {
          dRaw[4 * i + c] += dPrepared[4 * i + c];
        }
      }
      const S a = raw[4 * i + 3];
      if (a >= S(0) && a <= S(1) && entries[4 * i + 3] < static_cast<S>(adjoint::kMaxOpacity))
      {
        dRaw[4 * i + 3] += dPrepared[4 * i + 3] * adjoint::correctOpacityDerivative(a, exponent);
      }
    }
  }
};

// RGBA entries as one SSE2 register (GCC/Clang vector extensions): the lookup's lerp and its
// adjoint's scatter per entry in one operation each, the same arithmetic per channel as
// adjoint::tableLookup / tableLookupAdjoint. Other scalars take the generic loops.
#if defined(__GNUC__)
typedef float RGBA4 __attribute__((vector_size(16)));
inline RGBA4 loadRGBA(const float* p)
{
  RGBA4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void storeRGBA(float* p, RGBA4 v)
{
  std::memcpy(p, &v, sizeof v);
}
constexpr bool kVectorRGBA = true;
#else
constexpr bool kVectorRGBA = false;
#endif

// Classification of a sample: 1D (value) or 2D (value, gradient magnitude) bilinear lookup.
template <typename S, bool TwoD>
struct Classifier
{
  PreparedTable<S> table;
  int width = 0, height = 1;
  S vScale = 1, vBias = 0, gScale = 1, gBias = 0;

  struct Coord
  {
    int i = 0, j = 0;
    S f = 0, g = 0;
  };

  void classify(S value, S grad, S rgba[4], Coord& k) const
  {
    adjoint::tableCoordinate(value, vScale, vBias, width, k.i, k.f);
    const S* e = table.entries.data();
#if defined(__GNUC__)
    if constexpr (std::is_same_v<S, float> && kVectorRGBA)
    {
      // out = T[i] + f (T[i + 1] - T[i]), per channel
      const RGBA4 f = { k.f, k.f, k.f, k.f };
      const float* p = e + 4 * static_cast<size_t>(k.i);
      if constexpr (!TwoD)
      {
        const RGBA4 a = loadRGBA(p), b = loadRGBA(p + 4);
        storeRGBA(rgba, a + f * (b - a));
      }
      else
      {
        adjoint::tableCoordinate(grad, gScale, gBias, height, k.j, k.g);
        const float* r0 = p + 4 * static_cast<size_t>(k.j) * width;
        const float* r1 = r0 + 4 * static_cast<size_t>(width);
        const RGBA4 a0 = loadRGBA(r0), b0 = loadRGBA(r0 + 4), a1 = loadRGBA(r1),
                    b1 = loadRGBA(r1 + 4);
        const RGBA4 g = { k.g, k.g, k.g, k.g };
        const RGBA4 lo = a0 + f * (b0 - a0), hi = a1 + f * (b1 - a1);
        storeRGBA(rgba, lo + g * (hi - lo));
      }
      return;
    }
#endif
    if constexpr (!TwoD)
    {
      adjoint::tableLookup<S, 4>(e, k.i, k.f, rgba);
    }
    else
    {
      adjoint::tableCoordinate(grad, gScale, gBias, height, k.j, k.g);
      S lo[4], hi[4];
      adjoint::tableLookup<S, 4>(e + 4 * static_cast<size_t>(k.j) * width, k.i, k.f, lo);
      adjoint::tableLookup<S, 4>(e + 4 * static_cast<size_t>(k.j + 1) * width, k.i, k.f, hi);
      for (int c = 0; c < 4; ++c)
      {
        rgba[c] = lo[c] + k.g * (hi[c] - lo[c]);
      }
    }
  }

  // Accumulates dL/d(prepared table) from dL/d(rgba) of a sample.
  void classifyAdjoint(const Coord& k, const S dL_drgba[4], S* dTable) const
  {
#if defined(__GNUC__)
    if constexpr (std::is_same_v<S, float> && kVectorRGBA)
    {
      // dT[i] += (1 - f) d,  dT[i + 1] += f d   (per row, rows weighted 1 - g and g in 2D)
      const RGBA4 d = loadRGBA(dL_drgba);
      const RGBA4 f = { k.f, k.f, k.f, k.f };
      const RGBA4 f1 = 1.0f - f;
      float* p = dTable + 4 * static_cast<size_t>(k.i);
      auto scatter = [&](float* row, RGBA4 dRow)
      {
        storeRGBA(row, loadRGBA(row) + f1 * dRow);
        storeRGBA(row + 4, loadRGBA(row + 4) + f * dRow);
      };
      if constexpr (!TwoD)
      {
        scatter(p, d);
      }
      else
      {
        const RGBA4 g = { k.g, k.g, k.g, k.g };
        float* r0 = p + 4 * static_cast<size_t>(k.j) * width;
        scatter(r0, (1.0f - g) * d);
        scatter(r0 + 4 * static_cast<size_t>(width), g * d);
      }
      return;
    }
#endif
    if constexpr (!TwoD)
    {
      adjoint::tableLookupAdjoint<S, 4>(k.i, k.f, dL_drgba, dTable);
    }
    else
    {
      S lo[4], hi[4];
      for (int c = 0; c < 4; ++c)
      {
        lo[c] = (1 - k.g) * dL_drgba[c];
        hi[c] = k.g * dL_drgba[c];
      }
      adjoint::tableLookupAdjoint<S, 4>(
        k.i, k.f, lo, dTable + 4 * static_cast<size_t>(k.j) * width);
      adjoint::tableLookupAdjoint<S, 4>(
        k.i, k.f, hi, dTable + 4 * static_cast<size_t>(k.j + 1) * width);
    }
  }
};

} // namespace ddg::differentiable
