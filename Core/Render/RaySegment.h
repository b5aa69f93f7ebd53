// RaySegment.h: where a ray samples a volume — the one definition shared by the ray caster and
// its adjoint, so that both visit exactly the same samples.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ddg
{

/// Samples of one ray in the volume's index space: sample k sits at e + (j + k) s for
/// k = 0 .. kLast (the first sample is always taken, later ones while inside the closed box of
/// the points). s is the step d * direction / spacing.
struct RaySegment
{
  double e[3] = { 0, 0, 0 };
  double s[3] = { 0, 0, 0 };
  std::int64_t kLast = -1;
};

/// Intersects the ray (origin o, unit direction dir, world units) with the box [boxMin, boxMax]
/// of the points and fills `seg` for sample distance d and first-sample offset j (in steps).
/// Returns false when the ray misses the box.
inline bool raySegment(const Eigen::Vector3d& o, const Eigen::Vector3d& dir,
  const Eigen::Vector3d& boxMin, const Eigen::Vector3d& boxMax, const Eigen::Vector3d& origin,
  const Eigen::Vector3d& spacing, double d, double j, RaySegment& seg)
{
  double t0 = -1e300, t1 = 1e300;
  for (int a = 0; a < 3; ++a)
  {
    if (dir[a] != 0.0)
    {
      double ta = (boxMin[a] - o[a]) / dir[a], tb = (boxMax[a] - o[a]) / dir[a];
      if (ta > tb)
        std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    else if (o[a] < boxMin[a] || o[a] > boxMax[a])
    {
      return false;
    }
  }
  t0 = std::max(t0, 0.0);
  if (!(t1 >= t0))
  {
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    seg.e[a] = (o[a] + t0 * dir[a] - origin[a]) / spacing[a];
    seg.s[a] = d * dir[a] / spacing[a];
  }
  const double span = (t1 - t0) / d - j;
  seg.kLast = span > 0 ? static_cast<std::int64_t>(std::floor(span)) : 0;
  return true;
}

} // namespace ddg
