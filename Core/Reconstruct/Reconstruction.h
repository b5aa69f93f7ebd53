// Reconstruction.h: finds a transfer function whose rendering matches target images (Adam on
// the differentiable ray caster, with a smoothness prior).
#pragma once

#include "Image/Image.h"
#include "Render/DifferentiableRenderer.h"
#include "Render/View.h"
#include "TransferFunction/GaussianPrimitive.h"
#include "TransferFunction/TransferFunction1D.h"
#include "TransferFunction/TransferFunction2D.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace ddg
{

/// One target image and the view it was taken from.
/// image: RGB (an opaque screenshot over the view's background: view.backgroundAt(row)) or RGBA
/// (straight alpha, as PNG stores it: compared premultiplied with the render's RGBA), values in
/// [0, 1], exactly the view's size. mask (optional): 1 channel, same size, per-pixel weight in
/// [0, 1]. empty (optional, RGB targets): 1 channel, same size, 1 where the picture shows empty
/// space (the background): there the render's premultiplied RGBA is pulled to 0 with weight
/// `emptyWeight` (times the mask's) as well, so that no air is painted in the background's
/// colour (a haze invisible over this background, seen over any other).
struct ReconstructionTarget
{
  ReconstructionTarget() = default;
  ReconstructionTarget(Image image_, View view_, Image mask_ = {})
    : image(std::move(image_))
    , view(std::move(view_))
    , mask(std::move(mask_))
  {
  }

  Image image;
  View view;
  Image mask;
  Image empty;
  double emptyWeight = 1.0;
};

enum class ReconstructionLoss
{
  L1, ///< mean |render - target| (smoothed: Huber with delta 1e-3)
  L2  ///< mean (render - target)^2
};

/// Options (defaults in brackets).
struct ReconstructionOptions
{
  /// 2D TF (value x gradient magnitude) instead of 1D [false].
  bool twoD = false;
  /// TF resolution along the value [128].
  int bins = 128;
  /// 2D: resolution along gradient magnitude [32].
  int gradientBins = 32;
  /// Image loss [L1].
  ReconstructionLoss loss = ReconstructionLoss::L1;
  /// Weight of the prior: mean squared difference of neighbouring bins [0.01].
  double smoothness = 0.01;
  /// Weight of a (1 - SSIM) term on a random square patch per target and step [0: off].
  double ssimWeight = 0.0;
  /// Side of that patch in pixels [32].
  int ssimPatch = 32;
  /// Maximum Adam steps [500].
  int iterations = 500;
  /// Adam step in the unconstrained (logit) space [0.2].
  double learningRate = 0.2;
  /// Random pixels per target and step; 0 = every pixel [2048].
  int raysPerIteration = 2048;
  /// Converged when the smoothed loss improved by less than `tolerance` (relative) over
  /// `patience` steps [0.01, 50].
  double tolerance = 0.01;
  int patience = 50;
  /// Pass the current TF to the progress callback every N steps [0: never].
  int snapshotEvery = 0;
  /// Fit this many Gaussian primitives instead of free bins [0: bins]: the parametric fit.
  /// Each primitive has a mean and width per axis, a colour and a peak opacity (GaussianPrimitive;
  /// 2D adds the gradient axis); they are rasterized (rasterize1D/2D) at `bins` (x
  /// `gradientBins`) entries and their gradients come through rasterizeAdjoint. They start
  /// evenly spread over the value range (width range / (2 K), opacity 0.05, grey). The
  /// smoothness prior and `initial1D` are not used. 1..64.
  int primitives = 0;
  /// Start from this TF (1D) [grey, opacity 0.02].
  std::optional<TransferTable1D> initial1D;
  /// The parametric fit starts from these primitives when there are `primitives` of them
  /// [empty: evenly spread].
  std::vector<GaussianPrimitive> initialPrimitives;
  /// 1D: entries under this value keep opacity 0 whatever the fit does (OpacityFloor: a
  /// volume's air stays transparent) [unset: none].
  std::optional<double> transparentBelow;
  /// Colour targets: directions of the sliced Wasserstein distance per step [64].
  int directions = 64;
  /// Colour targets: when above 0, the directions are drawn from a fixed pool of this many,
  /// along which each target's colours are sorted once (ImageMetrics.h: SortedProjections;
  /// targets with the same colours share it), instead of fresh ones along which the target is
  /// sorted again at every call [0: fresh directions]. The carried look draws from 512
  /// (CarryLookOptions::fit; BenchCarryLook prints both side by side).
  int directionPool = 0;
  /// Colour targets: where lightness lies counts too: the distance gains the sliced
  /// Wasserstein distance of the points (L, colourPlacement x radius in the framed square,
  /// ColourTarget::radii), so that a bright core stays a core and a bright rim a rim, still
  /// without pixel correspondence [0: colours alone]. In CIELAB lightness units per half-side.
  double colourPlacement = 0;
  /// Seed of the pixel sampling [1].
  unsigned seed = 1;
  /// Sample distance, offset, threads (jitter is ignored).
  RenderOptions render;
};

struct ReconstructionResult
{
  bool twoD = false;
  TransferTable1D table1D; ///< bins entries over the volume's data range (uncorrected opacity)
  TransferTable2D table2D; ///< 2D result: value range x [0, max gradient magnitude]
  std::vector<GaussianPrimitive> primitives; ///< the fitted primitives (options.primitives > 0)
  int iterations = 0;
  bool converged = false;
  std::vector<double> loss; ///< per step (minibatch loss including the prior)
  double seconds = 0;
};

/// Called after every step with (step, loss, snapshot); snapshot is the current TF every
/// snapshotEvery steps and null otherwise. Return false to cancel (throws ddg::Cancelled).
using ReconstructionProgress =
  std::function<bool(int step, double loss, const struct ReconstructionResult* snapshot)>;

/// Reconstructs a TF for `renderer`'s volume from one or more targets (multi-view: the loss is
/// the mean over targets). Throws ddg::Error for unusable targets (size mismatch, wrong channel
/// count, non-finite pixels, a mask of the wrong size, nothing but background) and when the
/// loss becomes non-finite.
ReconstructionResult reconstructTransferFunction(const DifferentiableRenderer& renderer,
  const std::vector<ReconstructionTarget>& targets, const ReconstructionOptions& options,
  const ReconstructionProgress& progress = {});

/// A picture compared by its colours alone: one of another volume, whose pixels line up with no
/// render of this one. The render at `view` over its background is framed as framedColours
/// frames a picture and its colours there are compared with `colours` (sRGB in [0, 1]: a
/// picture's framedColours) by the sliced Wasserstein distance of their CIELAB values
/// (ImageMetrics.h: slicedWasserstein), so that the TF gives the render the picture's colours in
/// the picture's proportions, background included.
struct ColourTarget
{
  View view;
  std::vector<std::array<float, 3>> colours;
  /// Each colour's distance from the centre of the picture's framed square, in half-sides
  /// (framedColours' radii): needed when ReconstructionOptions::colourPlacement is above 0.
  std::vector<float> radii;
};

/// The colours of an RGB picture (values in [0, 1]) in the square 10 % larger than the box of
/// its content — the pixels differing from `view`'s background (View::backgroundAt, the view the
/// picture's size) by more than 0.04 in a channel — on the box's centre, the background counted
/// where the square reaches past the picture; the whole picture when nothing differs. Pixels
/// where `leaveOut` (1 channel, the picture's size; optional) is above 0.5 are left out (a
/// picture's overlays), of the content's box too. With `radii`: each colour's distance from the
/// square's centre, in half-sides (0 at the centre, 1 at the middle of a side). Throws
/// ddg::Error for sizes that differ.
std::vector<std::array<float, 3>> framedColours(const Image& picture, const View& view,
  const Image& leaveOut = {}, std::vector<float>* radii = nullptr);

/// reconstructTransferFunction with colour targets (the mean of their distances; every pixel of
/// each view rendered per step, options.raysPerIteration and ssimWeight unused). Throws
/// ddg::Error for a target without colours, non-finite colours, or an invalid view.
ReconstructionResult reconstructFromColours(const DifferentiableRenderer& renderer,
  const std::vector<ColourTarget>& targets, const ReconstructionOptions& options,
  const ReconstructionProgress& progress = {});

/// `result` as a TF file: a ParaView preset (1D: nodes at the bins, ParaView's midpoint and
/// sharpness defaults) or the 2D TF; `name` is its name.
TransferFunctionFile resultTransferFunction(
  const ReconstructionResult& result, const std::string& name);

/// Renders `result` with the RayCaster at `view` (RGBA premultiplied).
Image renderResult(const RayCaster& caster, const ReconstructionResult& result, const View& view,
  const RenderOptions& options = {});

/// renderResult over a differentiable renderer: its ray caster's render for a whole volume; for
/// a piece of one, the pieces' forward pass composited (collective: every piece calls it with
/// the same arguments and gets the whole's image; no empty-space skipping, the same image
/// within ~1e-6).
Image renderResult(const DifferentiableRenderer& renderer, const ReconstructionResult& result,
  const View& view, const RenderOptions& options = {});
/// The same for a 1D table as it is (RayCaster::render of the table).
Image renderTable(const DifferentiableRenderer& renderer, const TransferTable1D& table,
  const View& view, const RenderOptions& options = {});

} // namespace ddg
