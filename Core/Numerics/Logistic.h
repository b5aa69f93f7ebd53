// Logistic.h: the logistic sigmoid and its inverse (logit), the squashing every fit here uses
// to keep colours and opacities in (0, 1) while optimising unconstrained parameters.
#pragma once

#include <algorithm>
#include <cmath>

namespace ddg
{

/// 1 / (1 + exp(-x)), in (0, 1); its derivative is sigmoid(x) (1 - sigmoid(x)).
inline double sigmoid(double x)
{
  return 1.0 / (1.0 + std::exp(-x));
}

/// log(p / (1 - p)) of p clamped to [margin, 1 - margin], so that 0 and 1 map to finite
/// values: logit(0) = log(margin / (1 - margin)). Callers choose the margin (the
/// reconstruction 1e-6, the ParaView box fit 1e-4).
inline double logit(double p, double margin)
{
  p = std::clamp(p, margin, 1.0 - margin);
  return std::log(p / (1.0 - p));
}

} // namespace ddg
