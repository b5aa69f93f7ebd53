// RayCasterSample.h: the ray caster's work on one batch of samples along a ray — where they sit
// and their trilinear values, their lighting (Shade) and the front-to-back "over". Private to
// Core/Render/RayCaster.cxx.
#pragma once

#include "Render/Adjoint.h"
#include "Render/Lighting.h"
#include "Render/RayCasterClassify.h"
#include "Render/RayCasterField.h"

#include <algorithm>
#include <cstdint>
#include <type_traits>

namespace ddg::raycast
{

constexpr int kBatch = 8; // samples interpolated together along a ray

// Where kBatch samples sit: the first corner's index and the weights of their cells.
struct Lanes
{
  std::int64_t idx[kBatch];
  int i[kBatch], j[kBatch], k[kBatch]; // the first corner as a point (i, j, k)
  float fx[kBatch], fy[kBatch], fz[kBatch];
};

// Lighting of one render: the light kit, and the maps from a sample's index coordinates to its
// eye-space normal direction (m = E (.) R g, VTK's untransposed texture-to-eye matrix) and
// position (VTK's P_eye, from texture coordinates).
struct SampleLighting
{
  LightKit kit;
  float normalMap[3][3];                      // m = normalMap g
  float positionMap[3][3], positionOffset[3]; // P_eye = positionMap c + positionOffset

  // `frame` of the whole volume; the march's index coordinates are `offset` points from the
  // whole's (a piece of a volume), folded into the position's offset.
  void setup(const LightingFrame& frame, const View& view, const double offset[3])
  {
    kit = LightKit::paraview(view.lighting);
    for (int r = 0; r < 3; ++r)
    {
      double shift = frame.positionOffset[r];
      for (int a = 0; a < 3; ++a)
      {
        normalMap[r][a] = static_cast<float>(frame.normalMap[r][a]);
        positionMap[r][a] = static_cast<float>(frame.positionMap[r][a]);
        shift += frame.positionMap[r][a] * offset[a];
      }
      positionOffset[r] = static_cast<float>(shift);
    }
  }

  // Lights the table colours rgb[channel][lane] of lanes 0 .. count-1, lane l at index
  // coordinates e + kk[l] s with interpolated gradient g[axis][lane]; clamps the lit colour
  // to [0, 1] when `clamp` (1D tables). The lanes together (lightSumsBatch, Render/Lighting.h).
  template <int kLanes>
  void shadeBatch(int count, const float (&g)[3][kLanes], const float e[3], const float s[3],
    const float (&kk)[kLanes], bool clamp, float (&rgb)[3][kLanes]) const
  {
    float m[3][kLanes], p[3][kLanes];
    for (int l = 0; l < count; ++l)
      for (int r = 0; r < 3; ++r)
        m[r][l] = normalMap[r][0] * g[0][l] + normalMap[r][1] * g[1][l] + normalMap[r][2] * g[2][l];
    if (kit.specular > 0.0f) // only the specular term looks at where the sample is
      for (int l = 0; l < count; ++l)
      {
        const float x[3] = { e[0] + kk[l] * s[0], e[1] + kk[l] * s[1], e[2] + kk[l] * s[2] };
        for (int r = 0; r < 3; ++r)
          p[r][l] = positionMap[r][0] * x[0] + positionMap[r][1] * x[1] + positionMap[r][2] * x[2] +
            positionOffset[r];
      }
    float diff[3][kLanes], spec[3][kLanes], lit[kLanes];
    lightSumsBatch(kit, count, m, p, diff, spec, lit);
    for (int a = 0; a < 3; ++a)
      for (int l = 0; l < count; ++l)
      {
        const float c = kit.diffuse * diff[a][l] * rgb[a][l] + kit.specular * spec[a][l];
        const float out = clamp ? std::clamp(c, 0.0f, 1.0f) : c;
        rgb[a][l] = lit[l] > 0.0f ? out : 0.0f; // m = 0: no light reaches, black
      }
  }
};

// SampleLighting::shadeBatch over a LitQueue's lanes (RayCaster.cxx): shadeQueue runs its AVX2
// build where the CPU has it (8 lanes per register; about 4 % less lit time on the CT head with
// specular, Documentation/Rendering.md), else shadeBatch itself. Both do the same operations in
// the same order, so the same bits (RayCaster.ShadeQueueBuildsAgree). shadeQueueAvx2 returns false,
// doing nothing, where the CPU or the compiler has no AVX2.
void shadeQueue(const SampleLighting& light, int count, const float (&g)[3][kBatch],
  const float e[3], const float s[3], const float (&k)[kBatch], bool clamp,
  float (&rgb)[3][kBatch]);
bool shadeQueueAvx2(const SampleLighting& light, int count, const float (&g)[3][kBatch],
  const float e[3], const float s[3], const float (&k)[kBatch], bool clamp,
  float (&rgb)[3][kBatch]);

// The weight of a sample of opacity a behind accumulated opacity ca in the front-to-back "over".
inline float overWeight(float ca, float a)
{
  return (1.0f - ca) * a;
}

// Front-to-back "over" of one classified sample; returns true when the ray is opaque enough.
inline bool composite(const RGBA& c, float& cr, float& cg, float& cb, float& ca, float termination)
{
  const float wgt = overWeight(ca, c.a);
  cr += wgt * c.r;
  cg += wgt * c.g;
  cb += wgt * c.b;
  ca += wgt;
  return ca > termination;
}

// Shade: samples with opacity of one ray, in order, waiting to be lit together and composited.
// Lighting leaves opacity as it is, so the ray's opacity is known as samples are queued.
struct LitQueue
{
  int count = 0;
  float alpha = 0.0f; // the ray's opacity over every sample queued so far
  float g[3][kBatch], k[kBatch], rgb[3][kBatch], a[kBatch];

  // Queues a sample; returns true when the ray turns opaque at it (composite's test).
  bool push(const float gl[3], float kk, const RGBA& c, float termination)
  {
    for (int r = 0; r < 3; ++r)
      g[r][count] = gl[r];
    k[count] = kk;
    rgb[0][count] = c.r;
    rgb[1][count] = c.g;
    rgb[2][count] = c.b;
    a[count++] = c.a;
    alpha += overWeight(alpha, c.a);
    return alpha > termination;
  }

  // Lights the queued samples (at e + k s) and composites them in order onto the ray's colour;
  // with `unlit` (r, g, b, a), composites them unlit onto it first.
  void flush(const SampleLighting& light, const float e[3], const float s[3], bool clamp, float& cr,
    float& cg, float& cb, float& ca, float* unlit = nullptr)
  {
    if (count == 0)
      return;
    if (unlit)
      for (int q = 0; q < count; ++q)
        composite(RGBA{ rgb[0][q], rgb[1][q], rgb[2][q], a[q] }, unlit[0], unlit[1], unlit[2],
          unlit[3], 2.0f);
    shadeQueue(light, count, g, e, s, k, clamp, rgb);
    for (int q = 0; q < count; ++q) // the queue ends where the ray turns opaque: no check here
      composite(RGBA{ rgb[0][q], rgb[1][q], rgb[2][q], a[q] }, cr, cg, cb, ca, 2.0f);
    count = 0;
  }
};

// Trilinear values of kBatch consecutive samples p = e + (k0 + l) s, l = 0 .. kBatch-1; their
// cells and weights in `lanes`.
template <typename T>
inline void sampleBatch(const Field<T>& f, float k0, float ex, float ey, float ez, float sx,
  float sy, float sz, float* out, Lanes& lanes)
{
  const float mx = static_cast<float>(f.nx - 1), my = static_cast<float>(f.ny - 1),
              mz = static_cast<float>(f.nz - 1);
  std::int64_t* idx = lanes.idx;
  float *fx = lanes.fx, *fy = lanes.fy, *fz = lanes.fz;
  for (int l = 0; l < kBatch; ++l)
  {
    const float kk = k0 + static_cast<float>(l);
    const float x = std::min(std::max(ex + kk * sx, 0.0f), mx);
    const float y = std::min(std::max(ey + kk * sy, 0.0f), my);
    const float z = std::min(std::max(ez + kk * sz, 0.0f), mz);
    const int i = std::min(static_cast<int>(x), f.nx - 2);
    const int jj = std::min(static_cast<int>(y), f.ny - 2);
    const int kz = std::min(static_cast<int>(z), f.nz - 2);
    fx[l] = x - static_cast<float>(i);
    fy[l] = y - static_cast<float>(jj);
    fz[l] = z - static_cast<float>(kz);
    idx[l] = i + static_cast<std::int64_t>(f.nx) * (jj + static_cast<std::int64_t>(f.ny) * kz);
    lanes.i[l] = i;
    lanes.j[l] = jj;
    lanes.k[l] = kz;
  }
  // the same operations per lane as one sample's, the same values
  adjoint::trilinearBatch(f.w, lanes.idx, static_cast<std::int64_t>(f.nx),
    static_cast<std::int64_t>(f.nx) * f.ny, fx, fy, fz, out);
}

} // namespace ddg::raycast
