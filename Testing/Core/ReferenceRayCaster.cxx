// ReferenceRayCaster.cxx: NAIVE IMPLEMENTATION, USED FOR TESTING ONLY.
#include "ReferenceRayCaster.h"

#include <cmath>
#include <functional>

namespace ddg::reference
{
namespace
{

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
      double t0 = -1e300, t1 = 1e300;
      bool miss = false;
      for (int a = 0; a < 3; ++a)
      {
        if (dir[a] == 0)
        {
          miss = miss || o[a] < b[2 * a] || o[a] > b[2 * a + 1];
          continue;
        }
        double ta = (b[2 * a] - o[a]) / dir[a], tb = (b[2 * a + 1] - o[a]) / dir[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
      }
      t0 = std::max(t0, 0.0);
      if (miss || t1 < t0)
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
            C[ch] += (1 - A) * c[3] * std::clamp(c[ch], 0.0, 1.0);
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

} // namespace

Image referenceRender(const Volume& volume, const TransferTable1D& table, const View& view,
  double d, double unit, double offset, double termination)
{
  TransferTable1D t = table;
  for (int i = 0; i < t.width; ++i)
  {
    t.rgba[4 * i + 3] = static_cast<float>(corrected(t.rgba[4 * i + 3], d / unit));
  }
  const double q = RayCaster::textureScale(volume.originalType());
  return march(volume, view, d, offset, termination,
    [&](const Eigen::Vector3d& p)
    {
      const auto c = t.lookup(q * volume.sampleWorld(p[0], p[1], p[2]));
      return std::array<double, 4>{ c[0], c[1], c[2], c[3] };
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
  const auto g = volume.gradientMagnitude();
  const Volume gradient(volume.dims(), volume.origin(), volume.spacing(), g);
  return march(volume, view, d, offset, termination,
    [&](const Eigen::Vector3d& p)
    {
      const auto c =
        t.lookup(volume.sampleWorld(p[0], p[1], p[2]), gradient.sampleWorld(p[0], p[1], p[2]));
      return std::array<double, 4>{ c[0], c[1], c[2], c[3] };
    });
}

} // namespace ddg::reference
