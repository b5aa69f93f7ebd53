// Adjoint.h: the differentiable stages of the ray caster, each forward next to its adjoint
// (DiffDVR's layout). Templated on the scalar so the same code runs in float (rendering) and
// double (gradient checks). Adjoint functions ACCUMULATE into their gradient outputs unless
// they say "overwrites".
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace ddg::adjoint
{

// The stages run once per sample in the renderer's inner loops: always inlined there (GCC
// otherwise leaves the blend's adjoint as a call per sample).
#if defined(__GNUC__)
#define DDG_ADJOINT_INLINE inline __attribute__((always_inline))
#else
#define DDG_ADJOINT_INLINE inline
#endif

// --- trilinear interpolation of 8 corner values -----------------------------------------------
// v = lerp_z(lerp_y(lerp_x(c000, c100), lerp_x(c010, c110)), lerp_y(...c001.., ...c011..))
// corners ordered c[x + 2 y + 4 z].

template <typename S>
DDG_ADJOINT_INLINE S trilinear(const S c[8], S fx, S fy, S fz)
{
  const S c00 = c[0] + fx * (c[1] - c[0]);
  const S c10 = c[2] + fx * (c[3] - c[2]);
  const S c01 = c[4] + fx * (c[5] - c[4]);
  const S c11 = c[6] + fx * (c[7] - c[6]);
  const S c0 = c00 + fy * (c10 - c00);
  const S c1 = c01 + fy * (c11 - c01);
  return c0 + fz * (c1 - c0);
}

/// trilinear() of K cells of the scalars v (x fastest; strides sy, sz): cell l's first corner at
/// flat index idx[l], its fractions fx[l], fy[l], fz[l]. The corners of every lane are read first
/// (integer scalars widened exactly), then interpolated lane by lane in arrays the compiler
/// vectorises (SSE2: 4 lanes) with trilinear()'s operations in its order: bit for bit its
/// result. The ray caster's and the differentiable renderer's batches of samples.
template <typename S, typename T, int K>
DDG_ADJOINT_INLINE void trilinearBatch(const T* v, const std::int64_t (&idx)[K], std::int64_t sy,
  std::int64_t sz, const S* fx, const S* fy, const S* fz, S* out)
{
  using Wide = std::conditional_t<std::is_integral_v<T>, std::int32_t, S>;
  const std::int64_t offset[8] = { 0, 1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1 };
  Wide w[8][K];
  for (int l = 0; l < K; ++l)
  {
    const T* q = v + idx[l];
    for (int c = 0; c < 8; ++c)
      w[c][l] = static_cast<Wide>(q[offset[c]]);
  }
  S c[8][K];
  for (int k = 0; k < 8; ++k)
    for (int l = 0; l < K; ++l)
      c[k][l] = static_cast<S>(w[k][l]);
  for (int l = 0; l < K; ++l)
  {
    const S c00 = c[0][l] + fx[l] * (c[1][l] - c[0][l]);
    const S c10 = c[2][l] + fx[l] * (c[3][l] - c[2][l]);
    const S c01 = c[4][l] + fx[l] * (c[5][l] - c[4][l]);
    const S c11 = c[6][l] + fx[l] * (c[7][l] - c[6][l]);
    const S c0 = c00 + fy[l] * (c10 - c00);
    const S c1 = c01 + fy[l] * (c11 - c01);
    out[l] = c0 + fz[l] * (c1 - c0);
  }
}

/// Accumulates dL/dc[8] and dL/d(fx, fy, fz) from dL/dv.
template <typename S>
void trilinearAdjoint(const S c[8], S fx, S fy, S fz, S dL_dv, S dL_dc[8], S dL_df[3])
{
  const S c00 = c[0] + fx * (c[1] - c[0]);
  const S c10 = c[2] + fx * (c[3] - c[2]);
  const S c01 = c[4] + fx * (c[5] - c[4]);
  const S c11 = c[6] + fx * (c[7] - c[6]);
  const S c0 = c00 + fy * (c10 - c00);
  const S c1 = c01 + fy * (c11 - c01);
  // v = c0 + fz (c1 - c0)
  const S g0 = dL_dv * (1 - fz), g1 = dL_dv * fz;
  dL_df[2] += dL_dv * (c1 - c0);
  // c0 = c00 + fy (c10 - c00); c1 = c01 + fy (c11 - c01)
  const S g00 = g0 * (1 - fy), g10 = g0 * fy, g01 = g1 * (1 - fy), g11 = g1 * fy;
  dL_df[1] += g0 * (c10 - c00) + g1 * (c11 - c01);
  // cjk = c[0jk] + fx (c[1jk] - c[0jk])
  const S g[4] = { g00, g10, g01, g11 };
  for (int q = 0; q < 4; ++q)
  {
    dL_dc[2 * q] += g[q] * (1 - fx);
    dL_dc[2 * q + 1] += g[q] * fx;
    dL_df[0] += g[q] * (c[2 * q + 1] - c[2 * q]);
  }
}

// --- 1D table lookup (ParaView's texel convention) ---------------------------------------------
// t = clamp(value * scale + bias, 0, width - 1), i = min(floor(t), width - 2), f = t - i,
// out = (1 - f) T[i] + f T[i + 1]   (per channel)

template <typename S>
DDG_ADJOINT_INLINE void tableCoordinate(S value, S scale, S bias, int width, int& i, S& f)
{
  const S t = std::clamp(value * scale + bias, S(0), static_cast<S>(width - 1));
  i = std::min(static_cast<int>(t), width - 2);
  f = t - static_cast<S>(i);
}

template <typename S, int C>
DDG_ADJOINT_INLINE void tableLookup(const S* table, int i, S f, S out[C])
{
  for (int c = 0; c < C; ++c)
  {
    out[c] = table[C * i + c] + f * (table[C * (i + 1) + c] - table[C * i + c]);
  }
}

/// Accumulates dL/dT into dL_dTable (same layout as the table) from dL/dout.
template <typename S, int C>
DDG_ADJOINT_INLINE void tableLookupAdjoint(int i, S f, const S dL_dout[C], S* dL_dTable)
{
  for (int c = 0; c < C; ++c)
  {
    dL_dTable[C * i + c] += (1 - f) * dL_dout[c];
    dL_dTable[C * (i + 1) + c] += f * dL_dout[c];
  }
}

// --- opacity correction for the step (ParaView's opacity table) --------------------------------
// a' = 1 - (1 - a)^e when a > 1e-4, else a   (e = sample distance / unit distance)

constexpr double kCorrectionThreshold = 0.0001;

template <typename S>
S correctOpacity(S a, S e)
{
  return a > S(kCorrectionThreshold) ? S(1) - std::pow(S(1) - a, e) : a;
}

/// Returns da'/da (the threshold's jump is not differentiated).
template <typename S>
S correctOpacityDerivative(S a, S e)
{
  if (!(a > S(kCorrectionThreshold)))
  {
    return S(1);
  }
  const S oneMinus = std::max(S(1) - a, S(1e-12));
  return e * std::pow(oneMinus, e - S(1));
}

// --- front-to-back "over" ------------------------------------------------------------------
// Forward (state before the sample: C, A; sample: colour c in [0,1], opacity a):
//   C' = C + (1 - A) a c        A' = A + (1 - A) a

template <typename S>
DDG_ADJOINT_INLINE void blend(S C[3], S& A, const S c[3], S a)
{
  const S w = (1 - A) * a;
  for (int q = 0; q < 3; ++q)
  {
    C[q] += w * c[q];
  }
  A += w;
}

/// Inverts the blend for A: A = (A' - a) / (1 - a). Ill-conditioned as a -> 1 (the error of
/// A' is multiplied by 1 / (1 - a)); callers keep a <= kMaxOpacity, and the forward pass stops
/// at the early-termination threshold, so over a whole ray the error grows at most by
/// 1 / transmittance <= 255 / (1 - kMaxOpacity). The result is clamped to [0, 1].
constexpr double kMaxOpacity = 1.0 - 1e-6;

template <typename S>
DDG_ADJOINT_INLINE S blendInvertAlpha(S Aafter, S a)
{
  return std::clamp((Aafter - a) / (S(1) - a), S(0), S(1));
}

/// The same with oneOverOneMinusA = 1 / (1 - a) given: a replay computes it apart from the
/// chain of recovered states, so that the chain waits on a multiplication instead of a
/// division (equal to blendInvertAlpha to the last bit or two).
template <typename S>
DDG_ADJOINT_INLINE S blendInvertAlphaReciprocal(S Aafter, S a, S oneOverOneMinusA)
{
  return std::clamp((Aafter - a) * oneOverOneMinusA, S(0), S(1));
}

/// Adjoint of blend. In: dL/dC' (gC, unchanged by the blend), dL/dA' (gA), the state before
/// (A), the sample (c, a). Out: ACCUMULATES dL/dc into g_c and dL/da into g_a; OVERWRITES gA
/// with dL/dA (the adjoint of the state before the sample).
template <typename S>
DDG_ADJOINT_INLINE void blendAdjoint(const S gC[3], S& gA, S A, const S c[3], S a, S g_c[3], S& g_a)
{
  // C' = C + (1 - A) a c   ->  dC'/dc = (1 - A) a,  dC'/da = (1 - A) c,  dC'/dA = -a c
  // A' = A + (1 - A) a     ->  dA'/da = 1 - A,      dA'/dA = 1 - a
  S gCc = 0;
  for (int q = 0; q < 3; ++q)
  {
    g_c[q] += gC[q] * (1 - A) * a;
    gCc += gC[q] * c[q];
  }
  g_a += (gCc + gA) * (1 - A);
  gA = gA * (1 - a) - gCc * a;
}

} // namespace ddg::adjoint
