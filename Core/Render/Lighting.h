// Lighting.h: ParaView 5.11's lit volume rendering (Shade on) for one sample — the light kit,
// the gradient's eye-space normal and the two-sided Phong sum of VTK's multi-light shader path —
// shared by the ray caster and its adjoint. Read from VTK's sources and measured against
// ParaView: Documentation/Rendering.md, "Shade on".
#pragma once

#include "Render/View.h"

#include <algorithm>
#include <array>
#include <cmath>

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
  static constexpr int kPowerSteps = 4096;
  std::array<float, kPowerSteps + 1> power{};

  /// ParaView's default light kit (vtkLightKit defaults, as the render view sets them).
  static LightKit paraview(const Lighting& lighting);
};

/// Shades the table colour rgb (in [0, 1]) of a sample whose eye-space normal direction is m
/// (not normalised) and eye-space position p (only its direction is used). Returns the lit,
/// clamped colour in rgb.
inline void shadeSample(const LightKit& kit, const float m[3], const float p[3], float rgb[3])
{
  const float len2 = m[0] * m[0] + m[1] * m[1] + m[2] * m[2];
  if (!(len2 > 0.0f))
  {
    rgb[0] = rgb[1] = rgb[2] = 0.0f; // VTK's normal is NaN there: every light test fails
    return;
  }
  const float inv = 1.0f / std::sqrt(len2);
  const float n[3] = { m[0] * inv, m[1] * inv, m[2] * inv };
  float diff[3] = { 0, 0, 0 }, spec[3] = { 0, 0, 0 };
  const bool specular = kit.specular > 0.0f;
  float w[3] = { 0, 0, 0 }, nw = 0; // the direction from the eye to the sample, n . w
  if (specular)
  {
    const float pl = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (pl > 0.0f)
      for (int a = 0; a < 3; ++a)
        w[a] = p[a] / pl;
    nw = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
  }
  for (int i = 0; i < LightKit::kLights; ++i)
  {
    const auto& d = kit.direction[static_cast<size_t>(i)];
    const auto& c = kit.colour[static_cast<size_t>(i)];
    const float nd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    const float l = std::abs(nd);
    if (!(l > 0.0f))
      continue;
    for (int a = 0; a < 3; ++a)
      diff[a] += l * c[a];
    if (specular)
    {
      // |2 l n - d| = 1 when n . d = l, sqrt(1 + 8 l^2) when two-sided lighting flipped it
      const float rl = nd >= 0.0f ? 1.0f : std::sqrt(1.0f + 8.0f * l * l);
      const float rho = (2 * l * nw - (d[0] * w[0] + d[1] * w[1] + d[2] * w[2])) / rl;
      if (rho > 0.0f)
      {
        const float t = std::min(rho, 1.0f) * LightKit::kPowerSteps;
        const int i = std::min(static_cast<int>(t), LightKit::kPowerSteps - 1);
        const float s = kit.power[static_cast<size_t>(i)] +
          (t - i) * (kit.power[static_cast<size_t>(i) + 1] - kit.power[static_cast<size_t>(i)]);
        for (int a = 0; a < 3; ++a)
          spec[a] += s * c[a];
      }
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    const float v = kit.diffuse * diff[a] * rgb[a] + kit.specular * spec[a];
    rgb[a] = v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
  }
}

} // namespace ddg
