// Lighting.cxx: ParaView's default light kit in eye coordinates, and its per-point gradient.
#include "Render/Lighting.h"

#include "Volume/Volume.h"

#include "Common/Parallel.h"

#include <algorithm>
#include <cmath>

namespace ddg
{

LightKit LightKit::paraview(const Lighting& lighting)
{
  // vtkLightKit's defaults, as ParaView's render view sets them (UseLight on, no other light):
  // key intensity 0.75, warmth 0.6, elevation 50, azimuth 10; fill key/3, warmth 0.4, -75, -10;
  // two back lights key/3.5, warmth 0.5, 0, +-110; head light key/3, warmth 0.5. The colours
  // are vtkLightKit's warmth table at those warmths (read back from ParaView 5.11's lights).
  struct Source
  {
    double elevation, azimuth, intensity;
    std::array<float, 3> warmth;
    bool head;
  };
  const double key = 0.75;
  const std::array<float, 3> neutral{ 0.9998f, 0.9998f, 0.9998f };
  const Source lights[kLights] = { { 0, 0, key / 3, neutral, true },
    { 50, 10, key, { 1.0f, 0.97232f, 0.90222f }, false },
    { -75, -10, key / 3, { 0.90824f, 0.93314f, 1.0f }, false },
    { 0, 110, key / 3.5, neutral, false }, { 0, -110, key / 3.5, neutral, false } };
  LightKit kit;
  for (int i = 0; i < kLights; ++i)
  {
    const Source& s = lights[i];
    auto& d = kit.direction[static_cast<size_t>(i)];
    if (s.head)
    {
      d = { 0.0f, 0.0f, -1.0f }; // along the view direction
    }
    else
    {
      // vtkLight::SetDirectionAngle: position (cos e sin a, sin e, cos e cos a) in camera
      // coordinates, focal point at the origin; the direction points from the light
      const double e = s.elevation * M_PI / 180, a = s.azimuth * M_PI / 180;
      d = { static_cast<float>(-std::cos(e) * std::sin(a)), static_cast<float>(-std::sin(e)),
        static_cast<float>(-std::cos(e) * std::cos(a)) };
    }
    for (int c = 0; c < 3; ++c)
      kit.colour[static_cast<size_t>(i)][static_cast<size_t>(c)] =
        static_cast<float>(s.intensity * s.warmth[static_cast<size_t>(c)]);
  }
  kit.diffuse = static_cast<float>(lighting.diffuse);
  kit.specular = static_cast<float>(lighting.specular);
  kit.specularPower = static_cast<float>(lighting.specularPower);
  int first = kPowerSteps + 1; // the first entry at or above kPowerFloor (rho^p grows with rho)
  for (int i = 0; i <= kPowerSteps; ++i)
  {
    const double v = std::pow(static_cast<double>(i) / kPowerSteps, lighting.specularPower);
    if (v >= kPowerFloor && first > kPowerSteps)
      first = i;
    kit.power[static_cast<size_t>(i)] = i >= first ? static_cast<float>(v) : 0.0f;
  }
  // rho < (first - 1) / steps reads entries first - 2 and first - 1 at most: both 0
  kit.powerCutoff = static_cast<float>(first - 1) / kPowerSteps;
  return kit;
}

LightingFrame LightingFrame::of(const Volume& vol, const View& view)
{
  return of(vol.dims(), vol.origin(), vol.spacing(), view);
}

LightingFrame LightingFrame::of(const std::array<int, 3>& d, const std::array<double, 3>& origin,
  const std::array<double, 3>& spacing, const View& view)
{
  LightingFrame f;
  const RayGenerator rays(view);
  const Eigen::Vector3d rows[3] = { rays.right(), rays.up(), -rays.forward() }; // world -> eye
  Eigen::Vector3d extent;
  for (int a = 0; a < 3; ++a)
    extent[a] = (d[a] - 1) * spacing[a];
  for (int r = 0; r < 3; ++r)
  {
    double offset = 0;
    for (int a = 0; a < 3; ++a)
    {
      // VTK's untransposed texture-to-eye matrix: the extents scale the eye axes
      f.normalMap[r][a] = extent[r] * rows[r][a];
      // world' = origin + extent (c + 0.5) / N: the texture coordinate, not the point's
      f.positionMap[r][a] = rows[r][a] * extent[a] / d[a];
      offset += rows[r][a] * (origin[a] + extent[a] * 0.5 / d[a] - view.camera.position[a]);
    }
    f.positionOffset[r] = offset;
  }
  return f;
}

GradientStencil GradientStencil::of(const Volume& vol)
{
  return of(vol, vol.dims());
}

GradientStencil GradientStencil::of(const Volume& piece, const std::array<int, 3>& wholeDims)
{
  GradientStencil g;
  for (int a = 0; a < 3; ++a)
  {
    const double whole = wholeDims[a];
    g.n[a] = piece.dims()[a];
    g.scale[a] = whole > 1 ? whole / ((whole - 1) * piece.spacing()[a]) : 0.0;
    g.scaleFloat[a] = static_cast<float>(g.scale[a]);
  }
  return g;
}

// The gradient ParaView's shader computes (for lighting and the 2D TF's gradient axis), per point:
// the central difference (clamped at the faces, as the texture is) times N/(N-1) — the shader's
// offset of one cell in texture coordinates is N/(N-1) voxels — divided by the spacing.
// Interpolated trilinearly at a sample, it gives the shader's difference of two interpolated values
// up to the offset's N/(N-1) - 1 (exact for fields linear over the two cells). 12 bytes per point.
std::vector<float> lightingGradients(const Volume& vol)
{
  const auto& d = vol.dims();
  const int nx = d[0], ny = d[1], nz = d[2];
  const GradientStencil stencil = GradientStencil::of(vol);
  std::vector<float> g(static_cast<size_t>(vol.voxelCount()) * 3);
  vol.visit(
    [&](const auto* v)
    {
      parallelFor(nz, 0,
        [&](std::int64_t k64, int)
        {
          const int k = static_cast<int>(k64);
          for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
              stencil.atPoint(v, i, j, k,
                &g[3 *
                  (static_cast<size_t>(i) +
                    static_cast<size_t>(nx) * (j + static_cast<size_t>(ny) * k))]);
        });
    });
  return g;
}

} // namespace ddg
