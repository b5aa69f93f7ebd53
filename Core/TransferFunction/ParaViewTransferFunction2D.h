// ParaViewTransferFunction2D.h: a 2D TF as ParaView 5.11's TransferFunction2D proxy holds it
// (Gaussian boxes), its evaluation, and the fit of boxes to any of our 2D TFs.
#pragma once

#include "TransferFunction/TransferFunction2D.h"

#include <array>
#include <string>
#include <vector>

namespace ddg
{

struct ParaViewBoxFitReport;
struct ParaViewTransfer2DMapping;

/// One entry of the proxy's `Boxes` property: lower-left corner (x, y) and size in the Range's
/// units, straight colour rgb and peak opacity a, all as vtkPVTransferFunction2DBox holds them.
/// Its texture is an isotropic Gaussian in box coordinates with sigma = 0.3 * side:
///   alpha(x, y) = a * exp(-((x - cx)^2 / w^2 + (y - cy)^2 / h^2) / (2 * 0.3^2)) inside the box,
///   0 outside (the Gaussian is cut at the box edge); rgb is constant inside the box.
struct ParaViewBox
{
  double x = 0, y = 0, width = 1, height = 1;
  std::array<double, 4> rgba{ 1, 1, 1, 1 };
};

/// The TransferFunction2D proxy's properties.
///   Boxes: composited in order as vtkPVTransferFunction2D::Build does, with straight colour:
///     c.rgb = f.rgb + c.rgb (1 - f.a),  c.a = f.a + c.a (1 - f.a)   (rgb may exceed 1 where
///     boxes overlap, as in ParaView);
///   Range: (xmin, xmax, ymin, ymax); OutputDimensions: the function image's size (1024 x 1024
///   skips the mapper's Lanczos resize).
/// In rendering, ParaView looks the image up at x = the data value, y = |grad| in "value per
/// voxel" units (clamped to ymax = 0.25 * value range), and applies alpha per ray sample: no
/// opacity-unit-distance correction.
struct ParaViewTransferFunction2D
{
  std::vector<ParaViewBox> boxes;
  std::array<double, 4> range{ 0, 1, 0, 1 };
  std::array<int, 2> outputDimensions{ 1024, 1024 };

  /// RGBA at (x, y) in Range units: straight rgb (may exceed 1), per-sample alpha. The smooth
  /// Gaussian the box fit works with; functionImage is what ParaView renders.
  std::array<double, 4> evaluate(double x, double y) const;
  /// The function image vtkPVTransferFunction2D::Build makes (ParaView 5.11): OutputDimensions
  /// pixels, x fastest, RGBA floats; pixel (i, j) is the composite at x = Range[0] + i (Range
  /// width) / OutputDimensions[0] (likewise y) of every box covering it, each box sampled from
  /// its 128 x 128 8-bit texture (colour and Gaussian alpha truncated to 1/255 steps) at the
  /// texel below the pixel.
  std::vector<float> functionImage() const;
  /// The 2D table ParaView's mapper samples from this function on a volume with `mapping`, as
  /// our TransferTable2D: the function image (which must need no resampling: OutputDimensions a
  /// power of two >= 1024 on both axes) spread over the data range and the gradient axis up to
  /// mapping.gradientMax / gradientScale (the mapper ignores Range), alpha turned back into
  /// opacity per unit distance (ParaView does not correct 2D opacity for the step), colour
  /// clamped to [0, 1] (overlapping boxes can exceed it in ParaView). Throws ddg::Error.
  TransferTable2D table(const ParaViewTransfer2DMapping& mapping) const;
  /// {"Boxes": [x, y, w, h, r, g, b, a, ...], "Range": [...], "OutputDimensions": [...]}: the
  /// proxy's property values, ready for paraview.simple or vtkSMPropertyHelper; with a fit
  /// report also "Fit": {"rmse", "initial_rmse", "alpha_rmse", "max_alpha"}.
  std::string toJson(const ParaViewBoxFitReport* report = nullptr) const;
  /// Reads what toJson writes ("Fit" ignored); validates boxes (finite, positive size, colour
  /// and alpha in [0, 1]), Range and OutputDimensions. `origin` names the source in errors.
  static ParaViewTransferFunction2D fromJson(
    const std::string& jsonText, const std::string& origin);
};

/// How one volume's data map our 2D TF axes and opacity onto ParaView's.
struct ParaViewTransfer2DMapping
{
  std::array<double, 2> valueRange{ 0, 1 }; ///< X: the data range
  double gradientScale = 1;   ///< ParaView's Y per unit of our gradient magnitude (per world unit)
  double gradientMax = 0.25;  ///< ParaView's Y saturates here: 0.25 * (value range width)
  double opacityExponent = 1; ///< our alpha a -> per-sample alpha 1 - (1 - a)^exponent

  /// For a volume of `dims` points with `spacing` and data range `valueRange`, rendered with
  /// sample distance `sampleDistance` and opacity unit distance `unitDistance` (RayCaster's
  /// defaults are ParaView's). ParaView's Y is our per-sample gradient axis (the central
  /// difference over N/(N-1) voxels per axis over twice the spacing: transferGradient,
  /// Render/Lighting.h) times the mean spacing.
  static ParaViewTransfer2DMapping forVolume(const std::array<int, 3>& dims,
    const std::array<double, 3>& spacing, const std::array<double, 2>& valueRange,
    double sampleDistance, double unitDistance);
};

/// Options of fitParaViewBoxes.
struct ParaViewBoxFitOptions
{
  int maxBoxes = 16;    ///< boxes placed from a table (primitives: one box each, up to this)
  int iterations = 400; ///< Adam steps of the joint refinement (0: initial placement only)
  int gridWidth = 128;  ///< fit grid along X (cell centres over Range)
  int gridHeight = 64;  ///< fit grid along Y
};

/// What the fit achieved, on the fit grid: root-mean-square error of the emitted colour
/// (rgb * alpha per sample) and of the per-sample alpha, against the target, both in [0, 1].
struct ParaViewBoxFitReport
{
  double initialRmse = 0; ///< sqrt(mean over entries of (E - E*)^2 and (A - A*)^2), before Adam
  double rmse = 0;        ///< the same after the refinement
  double alphaRmse = 0;   ///< alpha alone, after
  double maxAlpha = 0;    ///< largest target per-sample alpha (a scale for the errors)
  int iterations = 0;
};

/// Fits ParaView boxes to our 2D TF so that ParaView's 2D rendering matches ours.
/// Target at a grid point (x, y): our TF at (value x, gradient y / gradientScale), alpha made
/// per-sample (1 - (1 - a)^opacityExponent). Initial boxes: one per primitive when `tf` has
/// primitives and no table (centre = mean, side = stddev / 0.3 per axis), else greedy placement
/// on the residual alpha of the baked table. Then Adam on all box parameters minimises the
/// squared error of emission and alpha (the box-edge discontinuities are not differentiated).
/// Throws ddg::Error on an invalid TF or mapping.
ParaViewTransferFunction2D fitParaViewBoxes(const TransferFunction2D& tf,
  const ParaViewTransfer2DMapping& mapping, const ParaViewBoxFitOptions& options = {},
  ParaViewBoxFitReport* report = nullptr);

/// The fit's loss for given boxes against a target grid (rgba per point, row-major, x fastest;
/// emission target = rgb * a), with its gradient with respect to every box parameter
/// (x, y, width, height, r, g, b, a per box: OVERWRITES dL_dBoxes, 8 per box). The boxes are
/// evaluated at the cell centres of a gridWidth x gridHeight grid over `range`. For tests.
double paraViewBoxLoss(const std::vector<ParaViewBox>& boxes, const std::array<double, 4>& range,
  int gridWidth, int gridHeight, const std::vector<double>& target,
  std::vector<double>* dL_dBoxes = nullptr);

} // namespace ddg
