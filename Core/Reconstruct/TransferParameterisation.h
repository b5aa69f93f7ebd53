// TransferParameterisation.h: what a TF reconstruction optimises — free bins (1D or 2D) or
// Gaussian primitives — as unconstrained parameters theta, mapped to TF entries and back.
#pragma once

#include "TransferFunction/GaussianPrimitive.h"
#include "TransferFunction/TransferFunction1D.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace ddg
{

/// Maps unconstrained parameters theta (n numbers) to the entries of a TF table and pulls a
/// gradient on those entries back to theta.
///   values: bins x gradientBins entries of straight RGBA with uncorrected opacity, in [0, 1]
///           (4 numbers per entry, value index fastest; gradientBins = 1 in 1D).
/// The optimisation loop (Reconstruction.cxx) calls forward, then backward with the gradient of
/// the loss at that forward, and steps theta with Adam at learningRates().
class TransferParameterisation
{
public:
  virtual ~TransferParameterisation() = default;

  /// Number of parameters n.
  virtual std::size_t size() const = 0;
  /// The parameters to start from (n numbers).
  virtual std::vector<double> initial() const = 0;
  /// OVERWRITES values with the TF entries of theta; remembers what backward needs.
  virtual void forward(const std::vector<double>& theta, std::vector<double>& values) = 0;
  /// OVERWRITES dL_dTheta (n numbers) from dL_dValues, at the last forward (whose output was
  /// `values`).
  virtual void backward(const std::vector<double>& values, const std::vector<double>& dL_dValues,
    std::vector<double>& dL_dTheta) const = 0;
  /// ACCUMULATES a prior on the entries into loss and dL_dValues [none].
  virtual void addPrior(
    const std::vector<double>& values, double& loss, std::vector<double>& dL_dValues) const;
  /// Adam's learning rate of every parameter for the base rate [base for all].
  virtual std::vector<double> learningRates(double base) const;
  /// The Gaussian primitives of the last forward [none: free bins].
  virtual std::vector<GaussianPrimitive> primitives() const { return {}; }
};

/// Another 1D parameterisation with the opacity of the entries below `lowest` held at 0 (entry b
/// at range[0] + b (range[1] - range[0]) / (bins - 1)): forward zeroes them, backward drops
/// their gradients. Keeps a volume's air (the values under its feature regions) transparent
/// whatever the fit does with the inner parameters.
class OpacityFloor : public TransferParameterisation
{
public:
  OpacityFloor(std::unique_ptr<TransferParameterisation> inner, int bins,
    std::array<double, 2> range, double lowest);

  std::size_t size() const override { return Inner->size(); }
  std::vector<double> initial() const override { return Inner->initial(); }
  void forward(const std::vector<double>& theta, std::vector<double>& values) override;
  void backward(const std::vector<double>& values, const std::vector<double>& dL_dValues,
    std::vector<double>& dL_dTheta) const override;
  void addPrior(
    const std::vector<double>& values, double& loss, std::vector<double>& dL_dValues) const override
  {
    Inner->addPrior(values, loss, dL_dValues);
  }
  std::vector<double> learningRates(double base) const override
  {
    return Inner->learningRates(base);
  }
  std::vector<GaussianPrimitive> primitives() const override { return Inner->primitives(); }

private:
  std::unique_ptr<TransferParameterisation> Inner;
  std::vector<std::uint8_t> Transparent; ///< per entry: held at opacity 0
  std::vector<double> InnerValues;       ///< the inner forward's output (its backward needs it)
};

/// Free bins: theta = the logit of every entry's R, G, B and A; values = sigmoid(theta).
/// Prior (when smoothness > 0): smoothness * mean over neighbouring pairs of entries (along the
/// value axis, and along the gradient axis in 2D) of the squared difference, summed over the 4
/// channels.
class FreeBins : public TransferParameterisation
{
public:
  /// 1D: `bins` entries over `range`, starting from `initial` looked up at the bins (entry b at
  /// range[0] + b (range[1] - range[0]) / (bins - 1)) or, without it, from grey with opacity
  /// 0.02. Starting values are clamped to [1e-6, 1 - 1e-6] before the logit.
  static FreeBins oneD(int bins, std::array<double, 2> range, double smoothness,
    const std::optional<TransferTable1D>& initial = std::nullopt);
  /// 2D: bins x gradientBins entries starting from grey with opacity 0.02.
  static FreeBins twoD(int bins, int gradientBins, double smoothness);

  std::size_t size() const override { return Start.size(); }
  std::vector<double> initial() const override { return Start; }
  void forward(const std::vector<double>& theta, std::vector<double>& values) override;
  void backward(const std::vector<double>& values, const std::vector<double>& dL_dValues,
    std::vector<double>& dL_dTheta) const override;
  void addPrior(const std::vector<double>& values, double& loss,
    std::vector<double>& dL_dValues) const override;

private:
  FreeBins(int bins, int gradientBins, double smoothness);

  std::vector<double> Start;
  double Smoothness = 0;
  std::vector<std::pair<std::size_t, std::size_t>> Neighbours; ///< entry pairs of the prior
};

/// The parametric fit: K Gaussian primitives of 8 unconstrained numbers each,
///   theta_k = (mean_x, mean_y, log stddev_x, log stddev_y, r, g, b, opacity logits)
/// with means and widths in units of their axis' range (value range; gradient range in 2D):
///   mean = lo + t * span,  stddev = exp(clamp(t, -12, 3)) * span,  colour = sigmoid(t).
/// values = the primitives rasterized (rasterize1D / rasterize2D) at bins (x gradientBins)
/// entries; backward goes through rasterizeAdjoint. In 1D the gradient-axis slots stay put.
/// They start evenly spread over the value range (mean (k + 0.5) / K, width 1 / (2 K) of the
/// range, grey, opacity 0.05). Learning rates relative to the base: 0.1 for means, 0.25 for
/// widths, 1 for the logits (positions move in units of the range, so more slowly).
class GaussianPrimitiveParameters : public TransferParameterisation
{
public:
  static constexpr int kPerPrimitive = 8;

  GaussianPrimitiveParameters(int count, bool twoD, std::array<double, 2> valueRange,
    std::array<double, 2> gradientRange, int bins, int gradientBins);

  std::size_t size() const override;
  std::vector<double> initial() const override;
  void forward(const std::vector<double>& theta, std::vector<double>& values) override;
  void backward(const std::vector<double>& values, const std::vector<double>& dL_dValues,
    std::vector<double>& dL_dTheta) const override;
  std::vector<double> learningRates(double base) const override;
  std::vector<GaussianPrimitive> primitives() const override { return Current; }

  /// The primitives of theta.
  std::vector<GaussianPrimitive> decode(const std::vector<double>& theta) const;
  /// initial() becomes theta of these primitives (decode's inverse; colours and opacity kept
  /// inside the logit's margin). Throws ddg::Error unless there are `count` of them.
  void startFrom(const std::vector<GaussianPrimitive>& primitives);

private:
  int Count = 0;
  bool TwoD = false;
  std::array<double, 2> ValueRange{ 0, 1 }, GradientRange{ 0, 1 };
  int Bins = 0, GradientBins = 1;
  std::array<double, 2> Lo{ 0, 0 }, Span{ 1, 1 };
  std::vector<GaussianPrimitive> Current; ///< decoded at the last forward
  std::vector<double> Start;              ///< startFrom's theta (empty: evenly spread)
};

} // namespace ddg
