// SelfConsistencyCase.h: the random TF and target conversion shared by the self-consistency
// test and the reconstruction benchmark, so both measure the same case.
#pragma once

#include "Image/Image.h"
#include "TransferFunction/GaussianPrimitive.h"

#include <algorithm>
#include <random>
#include <vector>

namespace ddg::testcase
{

/// Three Gaussian primitives with means in [110, 245], standard deviations in [6, 18] (data
/// values of 8-bit volumes), colours in [0.1, 1] and peak opacities in [0.3, 0.9], from `seed`.
inline std::vector<GaussianPrimitive> randomPrimitives(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> mean(110, 245), sd(6, 18), colour(0.1, 1.0),
    alpha(0.3, 0.9);
  std::vector<GaussianPrimitive> p(3);
  for (auto& g : p)
  {
    g.mean = { mean(rng), 0 };
    g.stddev = { sd(rng), 1 };
    g.rgb = { colour(rng), colour(rng), colour(rng) };
    g.opacity = alpha(rng);
  }
  return p;
}

/// Straight-alpha RGBA (as a PNG holds it) from a premultiplied render (Core's
/// unpremultiplyAlpha).
inline Image straightAlpha(const Image& premultiplied)
{
  return unpremultiplyAlpha(premultiplied);
}

} // namespace ddg::testcase
