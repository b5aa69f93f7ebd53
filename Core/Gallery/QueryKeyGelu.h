// QueryKeyGelu.h: the query key network's activation, shared by its training and its use: GELU
// as libtorch's (exact, by erf), and its derivative, on Eigen arrays (Eigen's erf and exp are
// vectorised; std::erf a value at a time took a third of applying a key to 50 000 latents).
#pragma once

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

} // namespace ddg
