// Adam.h: the Adam optimiser (Kingma & Ba 2015) on a flat vector of double parameters; every
// hand-written fit in Core (TF reconstruction, ParaView box fit) steps with it.
#pragma once

#include <cstddef>
#include <vector>

namespace ddg
{

/// Options of Adam (defaults in brackets: the paper's).
struct AdamOptions
{
  double beta1 = 0.9;    ///< decay of the first-moment estimate [0.9]
  double beta2 = 0.999;  ///< decay of the second-moment estimate [0.999]
  double epsilon = 1e-8; ///< added to the root of the second moment [1e-8]
};

/// Adam with bias correction. Step t = 1, 2, ... updates every parameter i with its gradient
/// g_i and learning rate lr_i as
///   m_i = beta1 m_i + (1 - beta1) g_i
///   v_i = beta2 v_i + (1 - beta2) g_i^2
///   theta_i -= lr_i (m_i / (1 - beta1^t)) / (sqrt(v_i / (1 - beta2^t)) + epsilon)
/// in exactly this order of floating-point operations (the fits' results depend on it).
/// The moments start at 0 and are sized by the first step (or the constructor).
class Adam
{
public:
  explicit Adam(const AdamOptions& options = {}, std::size_t parameters = 0);

  /// One step with the same learning rate for every parameter. theta and gradient must have
  /// the same size, and the same size at every step (throws ddg::Error otherwise).
  void step(std::vector<double>& theta, const std::vector<double>& gradient, double learningRate);
  /// One step with a learning rate per parameter (learningRates.size() == theta.size()).
  void step(std::vector<double>& theta, const std::vector<double>& gradient,
    const std::vector<double>& learningRates);

  /// Steps taken so far (t of the last step).
  int steps() const { return Steps; }
  const AdamOptions& options() const { return Options; }
  /// First and second moment estimates (before bias correction).
  const std::vector<double>& firstMoment() const { return M; }
  const std::vector<double>& secondMoment() const { return V; }

private:
  template <typename Rate>
  void update(std::vector<double>& theta, const std::vector<double>& gradient, Rate rate);

  AdamOptions Options;
  std::vector<double> M, V;
  int Steps = 0;
};

} // namespace ddg
