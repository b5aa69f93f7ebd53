// CarryLook.h: the look of another volume's picture carried over to this volume (issue 20) — a
// picture of volume A (a figure, a colleague's screenshot) gives volume B of the same kind a TF
// with A's look, though no pixel of the picture lines up with any render of B.
#pragma once

#include "Design/DesignSpace.h"
#include "Reconstruct/Match.h"
#include "Reconstruct/Reconstruction.h"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ddg
{

/// Options (defaults in brackets).
struct CarryLookOptions
{
  /// Side of the volume's renders the fit compares [64].
  int size = 64;
  /// Their cameras: ParaView's reset camera orbited by (azimuth, elevation) degrees
  /// [(30, 20), (150, 20), (270, 20)].
  std::vector<std::array<double, 2>> views{ { 30, 20 }, { 150, 20 }, { 270, 20 } };
  /// Their lighting (Shade and coefficients) [unlit].
  Lighting lighting;
  /// Feature regions of the volume, at most [4] (findFeatureRegions).
  int maxRegions = 4;
  /// Each region starts in its colour cluster's material colour: the cluster taken away from
  /// the background as far as its 90th percentile of distance reaches (its pixels are the
  /// material over the background at various opacities) [true]; false: the cluster's mean.
  bool unmix = true;
  /// Each region's primitive starts at this peak opacity [0.2].
  double startOpacity = 0.2;
  /// Below this share of the picture's content lying deeper inside it than 2 % of its size, the
  /// picture shows lines or text (a chart, a diagram), not a rendered volume: refused [0.25].
  double minimumSolidShare = 0.25;
  /// Below this shape agreement the result says the shapes disagree (the picture may show a
  /// volume of another kind) [0.6, the match's silhouette floor].
  double minimumShapeAgreement = 0.6;
  /// The fit: reconstructFromColours with one Gaussian primitive per region, from the start
  /// below [150 iterations, learning rate 0.05, 64 directions a step drawn from a pool of 512
  /// along which the picture is sorted once (directionPool: 2.9x faster, within the fit's own
  /// spread over seeds; Documentation/DesignSpaces.md, "Directions from a pool"), lightness
  /// compared with where it lies in the framed picture too (colourPlacement 100 per
  /// half-side); primitives and initialPrimitives are set here]. With `fit.initial1D` (a TF of this
  /// volume to start from: a query's design) the fit is of free bins from it instead; the regions
  /// are still matched and reported.
  ReconstructionOptions fit = []
  {
    ReconstructionOptions o;
    o.iterations = 150;
    o.learningRate = 0.05;
    o.colourPlacement = 100;
    o.directionPool = 512;
    return o;
  }();
};

/// What a picture shows, read before any volume is involved (the carried look's first step and
/// the query's check): the picture inside its letterbox (when it has one) and, in a screenshot
/// of a whole window, its render view (matchparts::renderedPart), RGB over black, its
/// longer side at most 512; its background, estimated from its border (estimateBackground); its
/// foreground (pixels off the background by more than its noise allows) in connected parts,
/// those under 20 % of the largest being overlays (axes, text, a scalar bar) and the rest the
/// object.
struct PictureObject
{
  Image picture;
  PictureBackground background;
  std::vector<std::uint8_t> object;  ///< per pixel of `picture`: 1 on the object
  std::vector<std::uint8_t> overlay; ///< per pixel: 1 on an overlay
  double overlayShare = 0;           ///< of the foreground
  /// The share of the object's pixels deeper inside it than 2 % of its box's longer side: a
  /// rendered volume is a solid shape (most of it survives), lines and text are not. 1 for an
  /// object under 25 pixels on that side (2 % of it under half a pixel): too small to tell.
  double solidShare = 0;
};

/// Throws ddg::Error for a picture that is not RGB(A) of at least 16 x 16, whose border has no one
/// colour (estimateBackground), or that shows nothing but its background.
PictureObject readPictureObject(const Image& picture);

/// Whether a picture can be a query's (a picture of a rendered volume): empty when it can be read
/// as one; a warning to show with the query's design when it cannot be read (its border has no
/// one colour: a photograph, or the object cut by the frame); throws ddg::Error for a picture of
/// lines or text (a chart, a diagram: solidShare under `minimumSolidShare`, as carryLook refuses).
std::string checkQueryPicture(const Image& picture, double minimumSolidShare = 0.25);

/// One feature region of the volume and the picture's colour it was matched with.
struct CarriedRegion
{
  FeatureRegion region;
  std::array<double, 3> colour{ 0, 0, 0 }; ///< sRGB: the mean of the picture's colour cluster
  double share = 0; ///< the cluster's share of the object's pixels in the picture
};

struct CarryLookResult
{
  ReconstructionResult fit;           ///< the TF (table1D, primitives) and the fit's losses
  PictureBackground background;       ///< the picture's, estimated; the renders were over it
  std::vector<CarriedRegion> regions; ///< by value, with the colours they started from
  double overlayShare = 0;            ///< share of the picture's foreground left out as overlays
  /// The colour distance (sliced Wasserstein, CIELAB units squared) of the start and of the
  /// result (each over the views, 256 directions, seed 1).
  double distanceStart = 0, distanceEnd = 0;
  /// How well this volume's silhouettes take the shape of the picture's object: the best IoU
  /// over 62 directions and the occupancy levels, each aligned with the object by moments
  /// (position, size, turn). Low: the picture may show a volume of another kind.
  double shapeAgreement = 0;
  /// shapeAgreement reaches the options' minimumShapeAgreement (not a confidence in the look:
  /// only a gross shape mismatch is caught).
  bool shapesAgree = false;
  double seconds = 0; ///< the whole call's wall time
};

/// Carries the look of `picture` (RGB, or RGBA with straight alpha as PNG stores it; any size; a
/// picture of another volume of the same kind) over to the renderer's volume:
///  1. the picture's background is estimated (estimateBackground) and its foreground found
///     (pixels off the background by more than its noise allows); parts of the foreground under
///     20 % of the largest are overlays (axes, text, a scalar bar) and are left out;
///  2. the picture's colours: framedColours (its content's square, overlays left out);
///  3. the volume's feature regions (findFeatureRegions), ordered by value, are matched with the
///     picture's object colours by rank: k-means in CIELAB with one cluster per region (started
///     at lightness quantiles), clusters ordered by lightness, the k-th darkest to the k-th
///     lowest region; each region starts as its base primitive in its cluster's colour at
///     opacity 0.2;
///  4. reconstructFromColours refines the primitives at the option's views over the picture's
///     background by the colours and where their lightness lies in the framed picture
///     (colourPlacement), the values under the lowest region held transparent (the volume's
///     air).
/// Throws ddg::Error for a picture without one background colour or without content, one of
/// lines or text (minimumSolidShare), a volume without feature regions; Cancelled when progress
/// returns false. A picture whose object this volume's silhouettes cannot take the shape of
/// (shapesAgree false) may show a volume of another kind; measured, volumes of other kinds with
/// blob-like outlines (a tooth, a brain, an engine block, a head) agree at 0.82-0.90, so this
/// flags a gross mismatch only.
/// A renderer of a piece of a volume (ParaView's ranks): collective, every piece calls it with the
/// same picture and options and gets the same result (the feature regions from the whole's
/// histogram, the silhouettes and every fit over the pieces).
CarryLookResult carryLook(const DifferentiableRenderer& renderer, const Image& picture,
  const CarryLookOptions& options = {}, const ReconstructionProgress& progress = {});

/// The carried look starts from `tf`, a TF of this volume (a query's design) whose data range is
/// `range`: the fit is of free bins from it (baked at 1024 entries) instead of the regions'
/// primitives (`fit.initial1D`). The CLI's `--init`, the filter's InitialTransferFunction and
/// pvpython's `carry_look(initial=...)` all start it so.
void carryLookFrom(
  CarryLookOptions& options, const TransferFunction1D& tf, const std::array<double, 2>& range);

/// The view a carried look is shown at: the options' first view of the volume, `size` pixels
/// square, over the picture's background (as estimated), lit as the options say.
View carriedLookView(const std::array<double, 6>& bounds, const CarryLookResult& result,
  const CarryLookOptions& options, int size);

} // namespace ddg
