// ReferenceRayCaster.cxx: NAIVE IMPLEMENTATION, USED FOR TESTING ONLY.
#include "ReferenceRayCaster.h"

#include <cmath>
#include <functional>

namespace ddg::reference
{
namespace
{

// Entry and exit distances of a ray through the point bounds b; false when it misses.
bool clipToBox(const std::array<double, 6>& b, const Eigen::Vector3d& o, const Eigen::Vector3d& dir,
  double& t0, double& t1)
{
  t0 = -1e300;
  t1 = 1e300;
  for (int a = 0; a < 3; ++a)
  {
    if (dir[a] == 0)
    {
      if (o[a] < b[2 * a] || o[a] > b[2 * a + 1])
        return false;
      continue;
    }
    const double ta = (b[2 * a] - o[a]) / dir[a], tb = (b[2 * a + 1] - o[a]) / dir[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  t0 = std::max(t0, 0.0);
  return t1 >= t0;
}

double corrected(double a, double exponent)
{
  return a > 0.0001 ? 1.0 - std::pow(1.0 - a, exponent) : a;
}

Image march(const Volume& volume, const View& view, double d, double offset, double termination,
  const std::function<std::array<double, 4>(const Eigen::Vector3d&)>& classify)
{
  Image img(view.width, view.height, 4, 0.0f);
  RayGenerator rays(view);
  const auto b = volume.bounds();
  for (int y = 0; y < view.height; ++y)
  {
    for (int x = 0; x < view.width; ++x)
    {
      Eigen::Vector3d o, dir;
      rays.ray(x, y, o, dir);
      double t0, t1;
      if (!clipToBox(b, o, dir, t0, t1))
      {
        continue;
      }
      double C[3] = { 0, 0, 0 }, A = 0;
      for (int k = 0;; ++k)
      {
        const double t = t0 + (offset + k) * d;
        if (k > 0 && t > t1)
        {
          break;
        }
        const auto c = classify(o + t * dir);
        if (c[3] > 0)
        {
          for (int ch = 0; ch < 3; ++ch)
          {
            C[ch] += (1 - A) * c[3] * c[ch]; // classify clamps where ParaView does
          }
          A += (1 - A) * c[3];
          if (A > termination)
          {
            break;
          }
        }
      }
      img.at(x, y, 0) = static_cast<float>(C[0]);
      img.at(x, y, 1) = static_cast<float>(C[1]);
      img.at(x, y, 2) = static_cast<float>(C[2]);
      img.at(x, y, 3) = static_cast<float>(A);
    }
  }
  return img;
}

// The table with its opacities corrected for the step.
TransferTable1D correctedTable(const TransferTable1D& table, double exponent)
{
  TransferTable1D t = table;
  for (int i = 0; i < t.width; ++i)
  {
    t.rgba[4 * i + 3] = static_cast<float>(corrected(t.rgba[4 * i + 3], exponent));
  }
  return t;
}

} // namespace

Image referenceRender(const Volume& volume, const TransferTable1D& table, const View& view,
  double d, double unit, double offset, double termination)
{
  const TransferTable1D t = correctedTable(table, d / unit);
  const double q = RayCaster::textureScale(volume.originalType());
  return march(volume, view, d, offset, termination,
    [&](const Eigen::Vector3d& p)
    {
      const auto c = t.lookup(q * volume.sampleWorld(p[0], p[1], p[2]));
      return std::array<double, 4>{ c[0], c[1], c[2], c[3] };
    });
}

namespace
{

// The shader's gradient at world position p: two trilinear samples N/(N-1) voxels either side
// per axis, their difference over the spacing (data units; ParaView's computeGradient).
Eigen::Vector3d shaderGradient(const Volume& volume, const Eigen::Vector3d& p)
{
  const auto& n = volume.dims();
  const auto& s = volume.spacing();
  Eigen::Vector3d g;
  for (int k = 0; k < 3; ++k)
  {
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    step[k] = s[k] * n[k] / (n[k] - 1.0);
    const Eigen::Vector3d a = p + step, b = p - step;
    g[k] = (volume.sampleWorld(a[0], a[1], a[2]) - volume.sampleWorld(b[0], b[1], b[2])) / s[k];
  }
  return g;
}

// The lit colour of table colour rgb at world position p with shader gradient g, clamped to
// [0, 1] when `clamp` (1D tables); black where g = 0.
std::array<double, 3> litColour(const Volume& volume, const View& view, const Eigen::Vector3d& p,
  const Eigen::Vector3d& g, const double rgb[3], bool clamp, double* dLit = nullptr)
{
  if (dLit)
    dLit[0] = dLit[1] = dLit[2] = 0;
  const RayGenerator rays(view);
  const Eigen::Vector3d eye[3] = { rays.right(), rays.up(), -rays.forward() };
  const auto& n = volume.dims();
  const auto& s = volume.spacing();
  const auto& o = volume.origin();
  // ParaView's light kit: (elevation, azimuth, intensity, warmth colour); the head light first
  struct L
  {
    double e, a, i, c[3];
    bool head;
  };
  const L lights[5] = { { 0, 0, 0.25, { 0.9998, 0.9998, 0.9998 }, true },
    { 50, 10, 0.75, { 1, 0.97232, 0.90222 }, false },
    { -75, -10, 0.25, { 0.90824, 0.93314, 1 }, false },
    { 0, 110, 0.75 / 3.5, { 0.9998, 0.9998, 0.9998 }, false },
    { 0, -110, 0.75 / 3.5, { 0.9998, 0.9998, 0.9998 }, false } };
  const Lighting& lit = view.lighting;
  Eigen::Vector3d m, pe, tex; // tex: the sample's world position through its texture coordinate
  for (int k = 0; k < 3; ++k)
  {
    const double c01 = ((p[k] - o[k]) / s[k] + 0.5) / n[k];
    tex[k] = o[k] + (n[k] - 1) * s[k] * c01;
  }
  for (int r = 0; r < 3; ++r)
  {
    m[r] = (n[r] - 1) * s[r] * eye[r].dot(g); // VTK's untransposed texture-to-eye matrix
    pe[r] = eye[r].dot(tex - view.camera.position);
  }
  std::array<double, 3> out{ 0, 0, 0 };
  if (!(m.norm() > 0))
    return out;
  const Eigen::Vector3d nn = m.normalized(), w = pe.normalized();
  double diff[3] = { 0, 0, 0 }, spec[3] = { 0, 0, 0 };
  for (const L& l : lights)
  {
    const double e = l.e * M_PI / 180, az = l.a * M_PI / 180;
    const Eigen::Vector3d dir = l.head
      ? Eigen::Vector3d(0, 0, -1)
      : Eigen::Vector3d(-std::cos(e) * std::sin(az), -std::sin(e), -std::cos(e) * std::cos(az));
    const double lambda = std::abs(nn.dot(dir));
    if (!(lambda > 0))
      continue;
    const double rho = (2 * lambda * nn - dir).normalized().dot(w);
    for (int ch = 0; ch < 3; ++ch)
    {
      diff[ch] += lambda * l.i * l.c[ch];
      if (rho > 0)
        spec[ch] += std::pow(rho, lit.specularPower) * l.i * l.c[ch];
    }
  }
  for (int ch = 0; ch < 3; ++ch)
  {
    out[ch] = lit.diffuse * diff[ch] * std::clamp(rgb[ch], 0.0, 1.0) + lit.specular * spec[ch];
    // d(lit)/d(table colour): Diffuse x the light sum, 0 where the clamp cuts
    if (dLit)
      dLit[ch] = !clamp || (out[ch] > 0 && out[ch] < 1) ? lit.diffuse * diff[ch] : 0.0;
    if (clamp)
      out[ch] = std::clamp(out[ch], 0.0, 1.0);
  }
  return out;
}

} // namespace

Image referenceRenderLit(const Volume& volume, const TransferTable1D& table, const View& view,
  double d, double unit, double offset, double termination)
{
  const TransferTable1D t = correctedTable(table, d / unit);
  const double q = RayCaster::textureScale(volume.originalType());
  return march(volume, view, d, offset, termination,
    [&](const Eigen::Vector3d& p)
    {
      const auto c = t.lookup(q * volume.sampleWorld(p[0], p[1], p[2]));
      std::array<double, 4> out{ c[0], c[1], c[2], c[3] };
      if (!(out[3] > 0))
        return out;
      const double rgb[3] = { out[0], out[1], out[2] };
      const auto lit = litColour(volume, view, p, shaderGradient(volume, p), rgb, true);
      return std::array<double, 4>{ lit[0], lit[1], lit[2], out[3] };
    });
}

Image referenceRender2D(const Volume& volume, const TransferTable2D& table, const View& view,
  double d, double unit, double offset, double termination)
{
  TransferTable2D t = table;
  for (size_t i = 0; i < t.rgba.size() / 4; ++i)
  {
    t.rgba[4 * i + 3] = static_cast<float>(corrected(t.rgba[4 * i + 3], d / unit));
  }
  return march(volume, view, d, offset, termination,
    [&](const Eigen::Vector3d& p)
    {
      // ParaView's 2D shader: |d|, d_k = (F(p + step_k) - F(p - step_k)) avgS / (2 s_k), looked
      // up in units of avgS: half the shader gradient's norm; both axes through ParaView's
      // texture scale q, as the 1D lookup.
      const double q = RayCaster::textureScale(volume.originalType());
      const Eigen::Vector3d g = shaderGradient(volume, p);
      const auto c = t.lookup(q * volume.sampleWorld(p[0], p[1], p[2]), q * 0.5 * g.norm());
      std::array<double, 4> out{ c[0], c[1], c[2], c[3] };
      if (!view.lighting.shade || !(out[3] > 0))
        return out;
      const double rgb[3] = { out[0], out[1], out[2] };
      const auto lit = litColour(volume, view, p, g, rgb, false); // not clamped in 2D
      return std::array<double, 4>{ lit[0], lit[1], lit[2], out[3] };
    });
}

} // namespace ddg::reference

#include "Render/Adjoint.h"
#include "Render/Lighting.h"

namespace ddg::reference
{

std::vector<double> referenceGradient(const Volume& volume, const std::vector<double>& table,
  int width, double min, double max, const View& view, double d, double unit, double offset,
  double termination, const std::vector<double>& dL_dRGBA)
{
  const double e = d / unit;
  const double q = RayCaster::textureScale(volume.originalType());
  // prepared table: rgb clamped, opacity corrected and clamped to the guard
  std::vector<double> prepared(table.size());
  for (int i = 0; i < width; ++i)
  {
    for (int c = 0; c < 3; ++c)
      prepared[4 * i + c] = std::clamp(table[4 * i + c], 0.0, 1.0);
    prepared[4 * i + 3] = std::min(
      adjoint::correctOpacity(std::clamp(table[4 * i + 3], 0.0, 1.0), e), adjoint::kMaxOpacity);
  }
  std::vector<double> dPrepared(table.size(), 0.0);
  RayGenerator rays(view);
  const auto b = volume.bounds();
  struct Sample
  {
    int i;
    double f, c[3], a, Abefore, dLit[3];
  };
  // Shade on: the model's gradient (lightingGradients, Render/Lighting.h, per point) interpolated
  // trilinearly per component, the obvious way
  std::vector<Volume> gradient;
  if (view.lighting.shade)
  {
    const auto g = lightingGradients(volume);
    for (int a = 0; a < 3; ++a)
    {
      std::vector<float> component(g.size() / 3);
      for (size_t i = 0; i < component.size(); ++i)
        component[i] = g[3 * i + static_cast<size_t>(a)];
      gradient.emplace_back(volume.dims(), volume.origin(), volume.spacing(), component);
    }
  }
  for (int y = 0; y < view.height; ++y)
  {
    for (int x = 0; x < view.width; ++x)
    {
      Eigen::Vector3d o, dir;
      rays.ray(x, y, o, dir);
      double t0, t1;
      if (!clipToBox(b, o, dir, t0, t1))
      {
        continue;
      }
      std::vector<Sample> samples;
      double A = 0;
      for (int k = 0;; ++k)
      {
        const double t = t0 + (offset + k) * d;
        if (k > 0 && t > t1)
        {
          break;
        }
        const Eigen::Vector3d p = o + t * dir;
        Sample s;
        adjoint::tableCoordinate(q * volume.sampleWorld(p[0], p[1], p[2]), q * width / (max - min),
          -min * width / (max - min) - 0.5, width, s.i, s.f);
        double rgba[4];
        adjoint::tableLookup<double, 4>(prepared.data(), s.i, s.f, rgba);
        s.c[0] = rgba[0];
        s.c[1] = rgba[1];
        s.c[2] = rgba[2];
        s.a = rgba[3];
        s.dLit[0] = s.dLit[1] = s.dLit[2] = 1;
        if (!gradient.empty() && s.a > 0)
        {
          const Eigen::Vector3d gp(gradient[0].sampleWorld(p[0], p[1], p[2]),
            gradient[1].sampleWorld(p[0], p[1], p[2]), gradient[2].sampleWorld(p[0], p[1], p[2]));
          const auto lit = litColour(volume, view, p, gp, s.c, true, s.dLit);
          std::copy(lit.begin(), lit.end(), s.c);
        }
        s.Abefore = A;
        samples.push_back(s);
        A += (1 - A) * s.a;
        if (A > termination)
        {
          break;
        }
      }
      const double* g = &dL_dRGBA[4 * (static_cast<size_t>(y) * view.width + x)];
      double gA = g[3];
      for (auto it = samples.rbegin(); it != samples.rend(); ++it)
      {
        double g_c[3] = { 0, 0, 0 }, g_a = 0;
        adjoint::blendAdjoint(g, gA, it->Abefore, it->c, it->a, g_c, g_a);
        const double dl[4] = { g_c[0] * it->dLit[0], g_c[1] * it->dLit[1], g_c[2] * it->dLit[2],
          g_a };
        adjoint::tableLookupAdjoint<double, 4>(it->i, it->f, dl, dPrepared.data());
      }
    }
  }
  std::vector<double> dRaw(table.size(), 0.0);
  for (int i = 0; i < width; ++i)
  {
    for (int c = 0; c < 3; ++c)
      if (table[4 * i + c] >= 0 && table[4 * i + c] <= 1)
        dRaw[4 * i + c] = dPrepared[4 * i + c];
    const double a = table[4 * i + 3];
    if (a >= 0 && a <= 1 && prepared[4 * i + 3] < adjoint::kMaxOpacity)
      dRaw[4 * i + 3] = dPrepared[4 * i + 3] * adjoint::correctOpacityDerivative(a, e);
  }
  return dRaw;
}

} // namespace ddg::reference
