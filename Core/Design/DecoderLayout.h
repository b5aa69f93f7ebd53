// DecoderLayout.h: what the lean variant's decoder outputs mean — 7 numbers per feature region —
// their targets for an exemplar, and the image loss of a decoded TF through the differentiable
// ray caster with its gradient with respect to those numbers. Plain C++ (no libtorch), so the
// chain rule from image to decoder output is tested on its own.
#pragma once

#include "Design/DesignSpace.h"
#include "Render/DifferentiableRenderer.h"

#include <cstdint>
#include <vector>

namespace ddg
{

/// Per region r, the decoder's outputs o[n r .. n r + n - 1] after squashing, n = outputs():
///   0 activity logit (raw; sigmoid(logit) scales the region's opacity),
///   1 mean shift in [-1, 1] (x spec.meanShift x region width, around the region's peak),
///   2 stddev in [0, 1] (spec.stddevScale lo..hi x the base stddev),
///   3-5 colour rgb in [0, 1], 6 peak opacity in [0, 1] (spec.opacity lo..hi);
///   2D design spaces add 7 the gradient-magnitude mean shift in [-1, 1] and 8 its stddev in
///   [0, 1], as 1 and 2 along the region's gradient extent.
struct DecoderLayout
{
  std::vector<FeatureRegion> regions;
  DesignSpaceSpec spec;
  /// 2D: the gradient-magnitude axis of the tables (Volume::gradientMagnitudeRange)
  std::array<double, 2> gradientRange{ 0, 1 };

  bool twoD() const { return spec.dimensions == 2; }
  int outputs() const { return twoD() ? 9 : 7; }
  int size() const { return outputs() * static_cast<int>(regions.size()); }

  /// Primitives whose opacity (after the activity) is below this are left out of a decoded TF.
  static constexpr double kMinOpacity = 1e-3;

  /// The primitive of region r from its outputs (activity not applied).
  GaussianPrimitive primitive(int r, const float* o) const;
  /// The explicit TF, as training's image loss sees it: every region's primitive with its
  /// opacity scaled by the soft activity sigmoid(logit), those below kMinOpacity left out.
  std::vector<GaussianPrimitive> decode(const float* o) const;
  /// The same, one primitive per region in region order, none left out.
  std::vector<GaussianPrimitive> decodeRegions(const float* o) const;
  /// The training targets of an exemplar's TF: column 0 the activity probability (1 for its
  /// regions, 0 and zeros elsewhere), the rest the squashed parameters (clamped to the spec's
  /// ranges).
  std::vector<float> targets(const Exemplar& e) const;

  /// Image loss of outputs `o` against `truth` (premultiplied RGBA bytes of view.width x
  /// view.height, e.g. an exemplar's ground truth at V_view): the primitives with their opacity
  /// scaled by the soft activity sigmoid(logit), rasterized as renderDesign does, ray cast at
  /// `view` for the listed pixels; loss = mean |rendered - truth| over pixels x 4 channels.
  /// Writes d(loss)/d(o) into grad (size() values) through the renderer's adjoint and the
  /// rasterization adjoint. The rays sample every sampleScale x ParaView's sample distance
  /// (opacity corrected as the ray caster does; 1: the truth's own step).
  template <typename S>
  double imageLoss(const DifferentiableRendererT<S>& renderer, const float* o, const View& view,
    const std::uint8_t* truth, const std::vector<int>& pixels, float* grad,
    double sampleScale = 1.0) const;
};

} // namespace ddg
