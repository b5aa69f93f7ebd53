// QueryKeyGelu.h: the query key network's pieces shared by its training and its use: the
// latents standardised, one layer's affine map, and the activation — GELU as libtorch's (exact,
// by erf), and its derivative, on Eigen arrays (Eigen's erf and exp are vectorised; std::erf a
// value at a time took a third of applying a key to 50 000 latents).
#pragma once

#include "Gallery/QueryKey.h"

#include <Eigen/Core>
#include <unsupported/Eigen/SpecialFunctions>

namespace ddg
{

using QueryKeyMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

inline void geluInPlace(QueryKeyMatrix& m)
{
  auto a = m.array();
  a = 0.5f * a * (1.0f + (a * 0.70710678f).erf());
}

/// d GELU / dx at every entry of x.
inline QueryKeyMatrix geluDerivative(const QueryKeyMatrix& x)
{
  const auto a = x.array();
  return (0.5f * (1.0f + (a * 0.70710678f).erf()) + a * 0.39894228f * (-0.5f * a.square()).exp())
    .matrix();
}

/// `count` latents (dim values each) as the key's first layer takes them: standardised when the
/// key has a mean, else as they are.
inline QueryKeyMatrix standardisedLatents(const QueryKey& key, const float* z, Eigen::Index count)
{
  QueryKeyMatrix x = Eigen::Map<const QueryKeyMatrix>(z, count, key.dim);
  if (!key.mean.empty())
    for (int c = 0; c < key.dim; ++c)
      x.col(c) =
        (x.col(c).array() - key.mean[static_cast<size_t>(c)]) / key.scale[static_cast<size_t>(c)];
  return x;
}

/// One layer's affine map of the rows of x: x W^T + bias (no bias when it has none).
inline QueryKeyMatrix layerOutput(const QueryKeyLayer& layer, const QueryKeyMatrix& x)
{
  QueryKeyMatrix y =
    x * Eigen::Map<const QueryKeyMatrix>(layer.weights.data(), layer.rows, layer.cols).transpose();
  if (!layer.bias.empty())
    y.rowwise() += Eigen::Map<const Eigen::RowVectorXf>(layer.bias.data(), layer.rows);
  return y;
}

} // namespace ddg
