// TestVolumes.h: small synthetic volumes of the Core tests, filled voxel by voxel from the
// distance to the centre of an n^3 grid (spacing 1, origin 0).
#pragma once

#include "Volume/Volume.h"

#include <cmath>
#include <vector>

namespace ddg::testing
{
/// value(r, i, j, k) at each voxel, r its distance to the grid's centre.
template <typename Value>
Volume gridVolume(int n, ScalarType type, Value value)
{
  std::vector<float> v;
  v.reserve(static_cast<size_t>(n) * n * n);
  const double c = (n - 1) / 2.0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        v.push_back(static_cast<float>(
          value(std::sqrt((i - c) * (i - c) + (j - c) * (j - c) + (k - c) * (k - c)), i, j, k)));
  return Volume({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, type);
}

/// A ball (200) in a shell (100) in air (10), float, 24^3.
inline Volume ballInShell()
{
  return gridVolume(24, ScalarType::Float32,
    [](double r, int, int, int) { return r < 5 ? 200.0 : (r < 9 ? 100.0 : 10.0); });
}
} // namespace ddg::testing
