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
/// k = kFirst .. kLast (the first sample is always taken, later ones while inside the closed box
/// of the points; kFirst > 0 only for a piece of a volume, ownedSamples). s is the step
/// d * direction / spacing.
struct RaySegment
{
  double e[3] = { 0, 0, 0 };
  double s[3] = { 0, 0, 0 };
  std::int64_t kFirst = 0;
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
  seg.kFirst = 0;
  seg.kLast = span > 0 ? static_cast<std::int64_t>(std::floor(span)) : 0;
  return true;
}

/// Restricts `seg` (from raySegment over the whole volume's box, whole index space, first-sample
/// offset j) to the samples a piece owns (VolumeBrick): the owned cells [lo, hi) of a whole of n
/// points per axis. Sample k at x = clamp(e + (j + k) s, 0, n - 1), in double, is owned when
/// lo <= x < hi on every axis (x <= hi where hi = n - 1): the same test on every piece, so each
/// sample of the whole belongs to exactly one piece of a partition; x moves monotonically along
/// the ray, so the owned samples are one run kFirst .. kLast. Returns false when there are none.
inline bool ownedSamples(
  RaySegment& seg, double j, const int lo[3], const int hi[3], const int n[3])
{
  auto ownedAlong = [&](int a, double t) // t = j + k
  {
    const double x = std::clamp(seg.e[a] + t * seg.s[a], 0.0, static_cast<double>(n[a] - 1));
    return x >= lo[a] && (x < hi[a] || (hi[a] == n[a] - 1 && x <= hi[a]));
  };
  auto owned = [&](std::int64_t k)
  {
    return ownedAlong(0, j + static_cast<double>(k)) && ownedAlong(1, j + static_cast<double>(k)) &&
      ownedAlong(2, j + static_cast<double>(k));
  };
  // The run from the planes in real numbers, then settled by the test itself (a few steps).
  double t0 = -1e300, t1 = 1e300; // owned for t = j + k in [t0, t1]
  for (int a = 0; a < 3; ++a)
  {
    if (seg.s[a] == 0.0) // the axis holds for all samples or for none
    {
      if (!ownedAlong(a, 0.0))
        return false;
      continue;
    }
    const double toLo = (lo[a] - seg.e[a]) / seg.s[a], toHi = (hi[a] - seg.e[a]) / seg.s[a];
    t0 = std::max(t0, std::min(toLo, toHi));
    t1 = std::min(t1, std::max(toLo, toHi));
  }
  const double kLo = std::max(0.0, std::floor(t0 - j) - 2.0);
  const double kHi = std::min(static_cast<double>(seg.kLast), std::ceil(t1 - j) + 2.0);
  if (kLo > kHi)
    return false;
  std::int64_t first = static_cast<std::int64_t>(kLo), last = static_cast<std::int64_t>(kHi);
  while (first <= last && !owned(first))
    ++first;
  while (last >= first && !owned(last))
    --last;
  if (first > last)
    return false;
  seg.kFirst = first;
  seg.kLast = last;
  return true;
}

} // namespace ddg
