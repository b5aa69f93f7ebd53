// Lighting.h: ParaView 5.11's lit volume rendering (Shade on) for one sample — the light kit,
// the gradient's eye-space normal and the two-sided Phong sum of VTK's multi-light shader path —
// shared by the ray caster and its adjoint. Read from VTK's sources and measured against
// ParaView: Documentation/Rendering.md, "Shade on".
#pragma once

#include "Render/Adjoint.h"
#include "Render/View.h"
#include "Volume/Volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace ddg
{

/// The lighting of one render: ParaView's default light kit (head, key, fill and two back
/// lights, all directional and following the camera; their ambient colour is 0) in eye
/// coordinates, the view's coefficients, and the transforms from the volume's index space.
///
/// Per sample (eye space, x right, y up, z towards the viewer):
///   g    = the scalar's central difference over N/(N-1) voxels per axis, divided by the spacing
///          (ParaView's computeGradient; here interpolated from per-voxel differences);
///   m    = E (.) (R g), E_k = (N_k - 1) s_k: VTK uploads its texture-to-eye matrix untransposed,
///          so the extents scale the eye axes; n = m / |m| (|m| = 0: no light reaches, black);
///   for each light i with direction d_i (from the light) and colour C_i = intensity x warmth:
///          l = |n . d_i| (two-sided), diffuse += l C_i,
///          r = normalize(2 l n - d_i), rho = r . normalize(P_eye), specular += rho^p C_i if rho >
///          0;
///   rgb  = clamp(kd diffuse (.) c + ks specular, 0, 1) (ambient: the lights' ambient colour is 0);
///   alpha unchanged.
struct LightKit
{
  static constexpr int kLights = 5;
  std::array<std::array<float, 3>, kLights> direction{}; ///< d_i, eye space, unit
  std::array<std::array<float, 3>, kLights> colour{};    ///< C_i (diffuse = specular colour)
  float diffuse = 1, specular = 0, specularPower = 100;
  /// rho^specularPower at rho = i / kPowerSteps, interpolated linearly between entries (error
  /// below 1e-4 for powers up to ParaView's 100; std::pow per light and sample cost more than
  /// the rest of a lit sample).
  /// Entries below 1e-6 are 0, and lanes with rho < powerCutoff read only such entries: a
  /// batch whose lanes all lie below it skips the light's specular term (most do: highlights are
  /// few), the same values.
  static constexpr int kPowerSteps = 4096;
  static constexpr double kPowerFloor = 1e-6;
  std::array<float, kPowerSteps + 1> power{};
  float powerCutoff = 0;

  /// ParaView's default light kit (vtkLightKit defaults, as the render view sets them).
  static LightKit paraview(const Lighting& lighting);
};

/// ParaView's gradient per point, x, y, z interleaved (12 bytes per point): the central
/// difference (clamped at the faces, as the texture is) times N/(N-1) — the shader's offset of
/// one cell in texture coordinates is N/(N-1) voxels — over the spacing. The reference the
/// renderers' GradientStencil is checked against (they keep no per-point buffer).
std::vector<float> lightingGradients(const Volume& vol);

/// ParaView's gradient at a sample for Shade and the 2D TF's gradient axis: lightingGradients'
/// per-point gradients interpolated trilinearly there, computed from the scalars around the
/// sample's cell (its 8 corners and the 24 points beside them) instead of a per-point buffer —
/// the same numbers with no memory per voxel.
struct GradientStencil
{
  std::array<int, 3> n{ 2, 2, 2 };
  double scale[3] = { 1, 1, 1 };     ///< N/(N-1) / spacing per axis
  float scaleFloat[3] = { 1, 1, 1 }; ///< the same in float (the float renderers' per sample)

  static GradientStencil of(const Volume& vol);
  /// For a piece of a volume of `wholeDims` points: the piece's strides and faces, the whole's
  /// scaling (N/(N-1) of the whole). The piece must hold one ghost point beside its owned cells
  /// where they are not the whole's faces (VolumeBrick::validate), so that faces clamp as the
  /// whole's do.
  static GradientStencil of(const Volume& piece, const std::array<int, 3>& wholeDims);

  /// The differences of the scalars v (x fastest) along each axis at the 8 corners of the cell
  /// whose first corner is point (i, j, k) (0 <= i <= nx - 2, ...): d[a][x + 2 y + 4 z], the
  /// per-point gradients before scaling.
  template <typename S, typename T>
  void corners(const T* v, int i, int j, int k, S d[3][8]) const
  {
    const std::int64_t sy = n[0], sz = static_cast<std::int64_t>(n[0]) * n[1];
    const T* p = v + i + sy * j + sz * k;
    // the points before the cell (clamped at the faces) and after it, as offsets from p
    const std::int64_t bx = i > 0 ? 1 : 0, ax = i + 2 < n[0] ? 2 : 1;
    const std::int64_t by = j > 0 ? sy : 0, ay = j + 2 < n[1] ? 2 * sy : sy;
    const std::int64_t bz = k > 0 ? sz : 0, az = k + 2 < n[2] ? 2 * sz : sz;
    // a - b: exact in int for 8/16-bit scalars (one conversion), in S for float ones
    auto D = [](T a, T b)
    {
      if constexpr (std::is_integral_v<T>)
        return static_cast<S>(static_cast<int>(a) - static_cast<int>(b));
      else
        return static_cast<S>(a) - static_cast<S>(b);
    };
    for (int r = 0; r < 4; ++r) // x: the cell's four rows along x
    {
      const T* q = p + ((r & 1) ? sy : 0) + ((r & 2) ? sz : 0);
      d[0][2 * r] = D(q[1], q[-bx]);
      d[0][2 * r + 1] = D(q[ax], q[0]);
    }
    for (int r = 0; r < 4; ++r) // y: its four columns along y
    {
      const int x = r & 1, z = r >> 1;
      const T* q = p + x + (z ? sz : 0);
      d[1][x + 4 * z] = D(q[sy], q[-by]);
      d[1][x + 2 + 4 * z] = D(q[ay], q[0]);
    }
    for (int r = 0; r < 4; ++r) // z: its four pillars along z
    {
      const T* q = p + r % 2 + (r / 2) * sy;
      d[2][r] = D(q[sz], q[-bz]);
      d[2][r + 4] = D(q[az], q[0]);
    }
  }

  /// The last cell's corner differences, ready to interpolate: per axis a and row r (the cell's
  /// rows along x, r = y + 2 z), base[a][r] = d[a][2 r] and delta[a][r] = d[a][2 r + 1] - base.
  template <typename S>
  struct Cell
  {
    std::int64_t id = -1; ///< flat index of the first corner (-1: none yet)
    S base[3][4]{};
    S delta[3][4]{};
  };

  /// Fills `cell` with the differences of the cell whose first corner is point (i, j, k).
  template <typename S, typename T>
  void fill(const T* v, int i, int j, int k, Cell<S>& cell) const
  {
    S d[3][8];
    corners(v, i, j, k, d);
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 4; ++r)
      {
        cell.base[a][r] = d[a][2 * r];
        cell.delta[a][r] = d[a][2 * r + 1] - d[a][2 * r];
      }
  }

  /// The gradient at weights fx, fy, fz in a cell: per axis, the corners' differences interpolated
  /// (x, then y, then z, as adjoint::trilinear), then scaled (the sum of interpolating the scaled
  /// per-point gradients, up to rounding).
  template <typename S>
  void interpolate(const Cell<S>& cell, S fx, S fy, S fz, S out[3]) const
  {
    for (int a = 0; a < 3; ++a)
    {
      S c[4];
      for (int r = 0; r < 4; ++r)
        c[r] = cell.base[a][r] + fx * cell.delta[a][r];
      const S c0 = c[0] + fy * (c[1] - c[0]);
      const S c1 = c[2] + fy * (c[3] - c[2]);
      S sa;
      if constexpr (std::is_same_v<S, float>)
        sa = scaleFloat[a];
      else
        sa = static_cast<S>(scale[a]);
      out[a] = sa * (c0 + fz * (c1 - c0));
    }
  }

  /// The gradient in the cell whose first corner is point (i, j, k) at weights fx, fy, fz.
  template <typename S, typename T>
  void inCell(const T* v, int i, int j, int k, S fx, S fy, S fz, S out[3]) const
  {
    Cell<S> cell;
    fill(v, i, j, k, cell);
    interpolate(cell, fx, fy, fz, out);
  }

  /// inCell through `cell`: the differences recomputed only when the cell (flat index `id` of
  /// point (i, j, k)) changes.
  template <typename S, typename T>
  void inCell(const T* v, int i, int j, int k, std::int64_t id, S fx, S fy, S fz, Cell<S>& cell,
    S out[3]) const
  {
    if (cell.id != id)
    {
      fill(v, i, j, k, cell);
      cell.id = id;
    }
    interpolate(cell, fx, fy, fz, out);
  }

  /// The gradient at index coordinates x (clamped to the grid as the scalar is).
  template <typename S, typename T>
  void at(const T* v, const S x[3], S out[3]) const
  {
    Cell<S> cell;
    at(v, x, cell, out);
  }

  /// at() through `cell` (the differences recomputed only when the cell changes).
  template <typename S, typename T>
  void at(const T* v, const S x[3], Cell<S>& cell, S out[3]) const
  {
    int i[3];
    S f[3];
    for (int a = 0; a < 3; ++a)
    {
      const S c = std::clamp(x[a], S(0), static_cast<S>(n[a] - 1));
      i[a] = std::min(static_cast<int>(c), n[a] - 2);
      f[a] = c - static_cast<S>(i[a]);
    }
    const std::int64_t id =
      i[0] + static_cast<std::int64_t>(n[0]) * (i[1] + static_cast<std::int64_t>(n[1]) * i[2]);
    inCell(v, i[0], i[1], i[2], id, f[0], f[1], f[2], cell, out);
  }

  /// The per-point gradient of point (i, j, k) (lightingGradients' entry).
  template <typename T>
  void atPoint(const T* v, int i, int j, int k, float out[3]) const
  {
    const std::int64_t sy = n[0], sz = static_cast<std::int64_t>(n[0]) * n[1];
    const std::int64_t stride[3] = { 1, sy, sz };
    const int at[3] = { i, j, k };
    const T* p = v + i + sy * j + sz * k;
    for (int a = 0; a < 3; ++a)
    {
      const std::int64_t back = at[a] > 0 ? stride[a] : 0, fwd = at[a] + 1 < n[a] ? stride[a] : 0;
      out[a] = static_cast<float>(
        (static_cast<double>(p[fwd]) - static_cast<double>(p[-back])) * scale[a]);
    }
  }
};

/// The maps of one render from a sample's index coordinates c to VTK's eye-space normal
/// direction m = normalMap g (g the per-point gradient interpolated there) and eye-space position
/// P = positionMap c + positionOffset (through the sample's texture coordinate).
struct LightingFrame
{
  double normalMap[3][3];
  double positionMap[3][3];
  double positionOffset[3];

  static LightingFrame of(const Volume& volume, const View& view);
  /// The same for a volume of `dims` points from `origin` (a piece's whole volume).
  static LightingFrame of(const std::array<int, 3>& dims, const std::array<double, 3>& origin,
    const std::array<double, 3>& spacing, const View& view);
};

/// The light sums of lanes 0 .. count-1, lane l with eye-space normal direction m[.][l] (not
/// normalised) and eye-space position p[.][l] (read by the specular term only): diffuse
/// multiplies the table colour, specular adds; lit[l] = 0 where m = 0 (VTK's normal is NaN: no
/// light reaches, the sample is black; its sums are 0), else 1. The same operations per lane in
/// arrays the compiler vectorises (the ray caster lights the samples of a batch together; K = 1
/// is lightSums). The specular power: kit.power's table in float (branch-free, the table read
/// lane by lane), std::pow in double (gradient checks).
template <typename S, int K>
void lightSumsBatch(const LightKit& kit, int count, const S (&m)[3][K], const S (&p)[3][K],
  S (&diff)[3][K], S (&spec)[3][K], S (&lit)[K])
{
  S n[3][K];
  for (int a = 0; a < 3; ++a) // every lane, not only count: fixed-size stores, no memset calls
    for (int l = 0; l < K; ++l)
      diff[a][l] = spec[a][l] = S(0);
  for (int l = 0; l < count; ++l)
  {
    const S len2 = m[0][l] * m[0][l] + m[1][l] * m[1][l] + m[2][l] * m[2][l];
    lit[l] = len2 > S(0) ? S(1) : S(0);
    const S inv = S(1) / std::sqrt(len2 > S(0) ? len2 : S(1));
    for (int a = 0; a < 3; ++a)
      n[a][l] = m[a][l] * inv;
  }
  const bool specular = kit.specular > 0.0f;
  S w[3][K], nw[K]; // the direction from the eye to the sample, n . w
  if (specular)
    for (int l = 0; l < count; ++l)
    {
      const S pl = std::sqrt(p[0][l] * p[0][l] + p[1][l] * p[1][l] + p[2][l] * p[2][l]);
      const S inv = pl > S(0) ? S(1) / pl : S(0);
      for (int a = 0; a < 3; ++a)
        w[a][l] = p[a][l] * inv;
      nw[l] = n[0][l] * w[0][l] + n[1][l] * w[1][l] + n[2][l] * w[2][l];
    }
  for (int i = 0; i < LightKit::kLights; ++i)
  {
    const auto& d = kit.direction[static_cast<size_t>(i)];
    const auto& c = kit.colour[static_cast<size_t>(i)];
    S nd[K], la[K], rho[K];
    for (int l = 0; l < count; ++l)
    {
      nd[l] = n[0][l] * d[0] + n[1][l] * d[1] + n[2][l] * d[2];
      la[l] = std::abs(nd[l]); // two-sided
      for (int a = 0; a < 3; ++a)
        diff[a][l] += la[l] * c[a];
    }
    if (!specular)
      continue;
    for (int l = 0; l < count; ++l)
    {
      // r = normalize(2 l n - d): |2 l n - d| = 1 when n . d = l, sqrt(1 + 8 l^2) when flipped
      const S rl = nd[l] >= S(0) ? S(1) : std::sqrt(S(1) + S(8) * la[l] * la[l]);
      rho[l] = (2 * la[l] * nw[l] - (d[0] * w[0][l] + d[1] * w[1][l] + d[2] * w[2][l])) / rl;
    }
    S sp[K]; // rho^power where light arrives (l > 0, rho > 0), else 0
    if constexpr (std::is_same_v<S, float>)
    {
      int any = 0; // a lane that can read a non-zero entry
      for (int l = 0; l < count; ++l)
        any |= rho[l] >= kit.powerCutoff && la[l] > 0.0f ? 1 : 0;
      if (!any)
        continue;
      int entry[K];
      float frac[K], lo[K], hi[K];
      for (int l = 0; l < count; ++l)
      {
        const float t = std::min(std::max(rho[l], 0.0f), 1.0f) * LightKit::kPowerSteps;
        entry[l] = std::min(static_cast<int>(t), LightKit::kPowerSteps - 1);
        frac[l] = t - static_cast<float>(entry[l]);
      }
      for (int l = 0; l < count; ++l)
      {
        lo[l] = kit.power[static_cast<size_t>(entry[l])];
        hi[l] = kit.power[static_cast<size_t>(entry[l]) + 1];
      }
      for (int l = 0; l < count; ++l)
        sp[l] = la[l] > 0.0f && rho[l] > 0.0f ? lo[l] + frac[l] * (hi[l] - lo[l]) : 0.0f;
    }
    else
    {
      for (int l = 0; l < count; ++l)
        sp[l] = la[l] > S(0) && rho[l] > S(0) ? std::pow(rho[l], static_cast<S>(kit.specularPower))
                                              : S(0);
    }
    for (int l = 0; l < count; ++l)
      for (int a = 0; a < 3; ++a)
        spec[a][l] += sp[l] * c[a];
  }
}

/// The light sums of one sample (lightSumsBatch for one lane). Returns false when m = 0.
template <typename S>
bool lightSums(const LightKit& kit, const S m[3], const S p[3], S diff[3], S spec[3])
{
  const S m1[3][1] = { { m[0] }, { m[1] }, { m[2] } }, p1[3][1] = { { p[0] }, { p[1] }, { p[2] } };
  S d1[3][1], s1[3][1], lit[1];
  lightSumsBatch(kit, 1, m1, p1, d1, s1, lit);
  for (int a = 0; a < 3; ++a)
  {
    diff[a] = d1[a][0];
    spec[a] = s1[a][0];
  }
  return lit[0] > S(0);
}

/// The lit colour before the clamp: kd diffuse (.) rgb + ks specular (ParaView clamps it to
/// [0, 1]; the adjoint needs it unclamped to know where the clamp cuts the gradient).
template <typename S>
void litColour(const LightKit& kit, const S diff[3], const S spec[3], const S rgb[3], S out[3])
{
  for (int a = 0; a < 3; ++a)
    out[a] =
      static_cast<S>(kit.diffuse) * diff[a] * rgb[a] + static_cast<S>(kit.specular) * spec[a];
}

/// The gradient axis of 2D transfer functions at a sample, from its interpolated gradient g:
/// G = |g| / 2, the magnitude ParaView's 2D shader computes divided by the mean spacing
/// (it looks up |d|, d_k = (F(x + N/(N-1) e_k) - F(x - N/(N-1) e_k)) avgS / (2 s_k)), so that
/// ParaView's Y = avgS G exactly. Data units per world unit, N/(N-1) above the true gradient.
template <typename S>
S transferGradient(const S g[3])
{
  return S(0.5) * std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
}

/// transferGradient of kLanes gradients g[axis][lane] together (the square roots vectorise).
template <int kLanes>
void transferGradientBatch(const float (&g)[3][kLanes], float (&out)[kLanes])
{
  for (int l = 0; l < kLanes; ++l)
  {
    const float gl[3] = { g[0][l], g[1][l], g[2][l] };
    out[l] = transferGradient(gl);
  }
}

// Shade on: the light sums of samples kk[i] (in steps), i < count, of the ray e + kk st (index
// coordinates): diffuse multiplies the table colour, specular adds; from the per-point gradient
// interpolated at each (`stencil` over the scalars v; `cell` keeps the ray's last cell); 0 where
// no light reaches (a zero gradient: the sample is black). The samples together
// (lightSumsBatch: the same operations per sample for any count).
template <typename S, typename T, int K>
void sampleLightSums(const LightKit& kit, const LightingFrame& frame,
  const GradientStencil& stencil, const T* v, GradientStencil::Cell<S>& cell, const S e[3],
  const S st[3], const S (&kk)[K], int count, S (&diff)[3][K], S (&spec)[3][K])
{
  S m[3][K], pe[3][K], lit[K];
  count = K == 1 ? 1 : count; // one sample: a count the compiler knows
  for (int i = 0; i < count; ++i)
  {
    const S x[3] = { e[0] + kk[i] * st[0], e[1] + kk[i] * st[1], e[2] + kk[i] * st[2] };
    S grad[3];
    stencil.at(v, x, cell, grad);
    for (int r = 0; r < 3; ++r)
    {
      m[r][i] = static_cast<S>(frame.normalMap[r][0]) * grad[0] +
        static_cast<S>(frame.normalMap[r][1]) * grad[1] +
        static_cast<S>(frame.normalMap[r][2]) * grad[2];
      pe[r][i] = static_cast<S>(frame.positionMap[r][0]) * x[0] +
        static_cast<S>(frame.positionMap[r][1]) * x[1] +
        static_cast<S>(frame.positionMap[r][2]) * x[2] + static_cast<S>(frame.positionOffset[r]);
    }
  }
  lightSumsBatch(kit, count, m, pe, diff, spec, lit);
  for (int i = 0; i < count; ++i)
    if (!(lit[i] > S(0)))
      for (int a = 0; a < 3; ++a)
        diff[a][i] = spec[a][i] = S(0);
}

} // namespace ddg
