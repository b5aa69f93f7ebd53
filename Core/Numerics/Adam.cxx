// Adam.cxx: the Adam update with bias correction.
#include "Numerics/Adam.h"

#include "Common/Error.h"

#include <cmath>
#include <string>

namespace ddg
{

Adam::Adam(const AdamOptions& options, std::size_t parameters)
  : Options(options)
  , M(parameters, 0.0)
  , V(parameters, 0.0)
{
  if (!(options.beta1 >= 0 && options.beta1 < 1) || !(options.beta2 >= 0 && options.beta2 < 1) ||
    !(options.epsilon >= 0))
  {
    throw Error("Adam needs beta1 and beta2 in [0, 1) and epsilon >= 0");
  }
}

template <typename Rate>
void Adam::update(std::vector<double>& theta, const std::vector<double>& gradient, Rate rate)
{
  if (gradient.size() != theta.size())
  {
    throw Error("Adam: " + std::to_string(theta.size()) + " parameters but " +
      std::to_string(gradient.size()) + " gradients");
  }
  if (Steps == 0 && M.empty())
  {
    M.assign(theta.size(), 0.0);
    V.assign(theta.size(), 0.0);
  }
  if (M.size() != theta.size())
  {
    throw Error("Adam: the number of parameters changed from " + std::to_string(M.size()) + " to " +
      std::to_string(theta.size()));
  }
  ++Steps;
  const double beta1 = Options.beta1, beta2 = Options.beta2, eps = Options.epsilon;
  const double c1 = 1.0 - std::pow(beta1, Steps), c2 = 1.0 - std::pow(beta2, Steps);
  for (std::size_t i = 0; i < theta.size(); ++i)
  {
    const double g = gradient[i];
    M[i] = beta1 * M[i] + (1 - beta1) * g;
    V[i] = beta2 * V[i] + (1 - beta2) * g * g;
    theta[i] -= rate(i) * (M[i] / c1) / (std::sqrt(V[i] / c2) + eps);
  }
}

void Adam::step(
  std::vector<double>& theta, const std::vector<double>& gradient, double learningRate)
{
  update(theta, gradient, [learningRate](std::size_t) { return learningRate; });
}

void Adam::step(std::vector<double>& theta, const std::vector<double>& gradient,
  const std::vector<double>& learningRates)
{
  if (learningRates.size() != theta.size())
  {
    throw Error("Adam: " + std::to_string(theta.size()) + " parameters but " +
      std::to_string(learningRates.size()) + " learning rates");
  }
  update(theta, gradient, [&learningRates](std::size_t i) { return learningRates[i]; });
}

} // namespace ddg
