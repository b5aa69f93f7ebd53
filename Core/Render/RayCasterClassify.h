// RayCasterClassify.h: the ray caster's classification tables (1D and 2D, ParaView's lookup and
// opacity correction). Private to Core/Render/RayCaster.cxx.
#pragma once

#include "Common/Error.h"
#include "TransferFunction/TransferFunction1D.h"
#include "TransferFunction/TransferFunction2D.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace ddg::raycast
{

struct RGBA
{
  float r, g, b, a;
};

// Opacity correction for the step, as ParaView's opacity table (entries <= 1e-4 untouched).
inline float correctOpacity(float a, double exponent)
{
  return a > 0.0001f ? static_cast<float>(1.0 - std::pow(1.0 - a, exponent)) : a;
}

// Table coordinate of w: t = w * scale + bias, clamped to [0, width - 1].
struct Classify1D
{
  std::vector<RGBA> table;
  int width = 0;
  float scale = 1, bias = 0;
  std::vector<int> nonzeroPrefix; // count of entries with alpha > 0 in [0, i]

  // q: the texture normalisation factor, folded into the scale (lookups take raw values).
  void prepare(const TransferTable1D& t, double q, double exponent)
  {
    if (t.width < 2 || t.rgba.size() != static_cast<size_t>(t.width) * 4 || !(t.max > t.min))
    {
      throw Error("transfer function table is empty, has a bad size or an empty range");
    }
    width = t.width;
    table.resize(static_cast<size_t>(width));
    nonzeroPrefix.resize(static_cast<size_t>(width));
    int count = 0;
    for (int i = 0; i < width; ++i)
    {
      const float* e = &t.rgba[4 * static_cast<size_t>(i)];
      for (int c = 0; c < 4; ++c)
      {
        if (!std::isfinite(e[c]))
        {
          throw Error("transfer function table holds a non-finite value");
        }
      }
      table[i] = { std::clamp(e[0], 0.0f, 1.0f), std::clamp(e[1], 0.0f, 1.0f),
        std::clamp(e[2], 0.0f, 1.0f), correctOpacity(std::clamp(e[3], 0.0f, 1.0f), exponent) };
      count += table[i].a > 0.0f ? 1 : 0;
      nonzeroPrefix[i] = count;
    }
    // t = ((q v - min) / (max - min)) * width - 0.5
    scale = static_cast<float>(q * width / (t.max - t.min));
    bias = static_cast<float>(-t.min * width / (t.max - t.min) - 0.5);
  }

  bool anyOpaque(float lo, float hi) const
  {
    float t0 = lo * scale + bias, t1 = hi * scale + bias;
    if (t0 > t1)
      std::swap(t0, t1);
    const int i0 = std::clamp(static_cast<int>(std::floor(t0)) - 1, 0, width - 1);
    const int i1 = std::clamp(static_cast<int>(std::ceil(t1)) + 1, 0, width - 1);
    return nonzeroPrefix[i1] - (i0 > 0 ? nonzeroPrefix[i0 - 1] : 0) > 0;
  }

  RGBA lookup(float w) const
  {
    const float t = std::clamp(w * scale + bias, 0.0f, static_cast<float>(width - 1));
    const int i = std::min(static_cast<int>(t), width - 2);
    const float f = t - i;
    const RGBA& a = table[i];
    const RGBA& b = table[i + 1];
    return { a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b),
      a.a + f * (b.a - a.a) };
  }
};

// 2D classification: bilinear lookup over (value, gradient magnitude), both scaled by ParaView's
// texture scale q (RayCaster::textureScale: its 2D lookup and gradient read the same normalised
// texture as the 1D lookup).
struct Classify2D
{
  std::vector<RGBA> table;
  int width = 0, height = 0;
  float vScale = 1, vBias = 0, gScale = 1, gBias = 0;

  void prepare(const TransferTable2D& t, double q, double exponent)
  {
    t.validate();
    if (static_cast<long long>(t.width) * t.height > std::numeric_limits<int>::max())
      throw Error("2D transfer function table: more than 2^31 - 1 entries");
    width = t.width;
    height = t.height;
    table.resize(static_cast<size_t>(width) * height);
    for (size_t i = 0; i < table.size(); ++i)
    {
      const float* e = &t.rgba[4 * i];
      table[i] = { e[0], e[1], e[2], correctOpacity(e[3], exponent) };
    }
    const double dv = t.valueRange[1] - t.valueRange[0];
    const double dg = t.gradientRange[1] - t.gradientRange[0];
    vScale = static_cast<float>(q * width / dv);
    vBias = static_cast<float>(-t.valueRange[0] * width / dv - 0.5);
    gScale = static_cast<float>(q * height / dg);
    gBias = static_cast<float>(-t.gradientRange[0] * height / dg - 0.5);
  }

  static void coordRange(float lo, float hi, float scale, float bias, int n, int& i0, int& i1)
  {
    float t0 = lo * scale + bias, t1 = hi * scale + bias;
    if (t0 > t1)
      std::swap(t0, t1);
    i0 = std::clamp(static_cast<int>(std::floor(t0)) - 1, 0, n - 1);
    i1 = std::clamp(static_cast<int>(std::ceil(t1)) + 1, 0, n - 1);
  }

  bool anyOpaque(float vLo, float vHi, float gLo, float gHi) const
  {
    int v0, v1, g0, g1;
    coordRange(vLo, vHi, vScale, vBias, width, v0, v1);
    coordRange(gLo, gHi, gScale, gBias, height, g0, g1);
    for (int j = g0; j <= g1; ++j)
      for (int i = v0; i <= v1; ++i)
        if (table[static_cast<size_t>(j) * width + i].a > 0.0f)
          return true;
    return false;
  }

  // Where (v, g) falls in the table: its first texel's index and the weights.
  void coordinates(float v, float g, int& index, float& fx, float& fy) const
  {
    const float tx = std::clamp(v * vScale + vBias, 0.0f, static_cast<float>(width - 1));
    const float ty = std::clamp(g * gScale + gBias, 0.0f, static_cast<float>(height - 1));
    const int i = std::min(static_cast<int>(tx), width - 2);
    const int j = std::min(static_cast<int>(ty), height - 2);
    fx = tx - static_cast<float>(i);
    fy = ty - static_cast<float>(j);
    index = j * width + i; // under 2^31 (prepare)
  }

  RGBA at(int index, float fx, float fy) const
  {
    const RGBA* r0 = &table[static_cast<size_t>(index)];
    const RGBA* r1 = r0 + width;
    auto lerp = [](const RGBA& a, const RGBA& b, float f)
    {
      return RGBA{ a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b),
        a.a + f * (b.a - a.a) };
    };
    return lerp(lerp(r0[0], r0[1], fx), lerp(r1[0], r1[1], fx), fy);
  }

  RGBA lookup(float v, float g) const
  {
    int index;
    float fx, fy;
    coordinates(v, g, index, fx, fy);
    return at(index, fx, fy);
  }

  // lookup of lanes 0 .. count-1: the coordinates of all kLanes lanes together (vectorisable;
  // v and g must be finite on every lane), then the table's reads; the same values as lookup.
  template <int kLanes>
  void lookupBatch(
    int count, const float (&v)[kLanes], const float (&g)[kLanes], RGBA (&out)[kLanes]) const
  {
    int index[kLanes];
    float fx[kLanes], fy[kLanes];
    for (int l = 0; l < kLanes; ++l)
      coordinates(v[l], g[l], index[l], fx[l], fy[l]);
    for (int l = 0; l < count; ++l)
      out[l] = at(index[l], fx[l], fy[l]);
  }
};

} // namespace ddg::raycast
