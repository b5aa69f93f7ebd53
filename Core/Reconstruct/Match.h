// Match.h: a transfer function and a camera from a picture as users have it — a screenshot of
// ParaView's GUI, a figure — whose camera, framing and background nobody wrote down. The
// background is estimated (uniform or ParaView's vertical gradient), overlays (orientation
// axes, scalar bar, text) are masked out, the camera (azimuth, elevation, roll, distance, pan,
// and perspective or parallel projection) is estimated from ParaView's reset camera by
// silhouettes and by the picture's colours (an emission model of each camera's rays), and the
// differentiable reconstruction then fits the TF with empty space kept transparent.
#pragma once

#include "Image/Image.h"
#include "Reconstruct/Reconstruction.h"
#include "Render/DifferentiableRenderer.h"
#include "Render/View.h"

#include <array>
#include <functional>
#include <optional>
#include <string>

namespace ddg
{

/// The background of a picture: one colour, or ParaView's vertical gradient (the view's
/// Background at the bottom row, Background2 at the top row, linear in between).
struct PictureBackground
{
  bool gradient = false;
  std::array<double, 3> bottom{ 0, 0, 0 }; ///< the colour, or the gradient's bottom row
  std::array<double, 3> top{ 0, 0, 0 };    ///< the gradient's top row (= bottom when uniform)
  double noise = 0; ///< robust spread of the border pixels about it ([0, 1] units)

  /// Writes it into a view: background (= bottom) and, for a gradient, background2 (= top).
  void applyTo(View& view) const;
};

/// Estimates the background from the picture's border (the outer rows and columns): per row the
/// median of the left and right border pixels, a straight line fitted over the rows (robustly);
/// a gradient when top and bottom differ by more than 3 levels of 255, else one colour (the
/// median of the whole border). Throws ddg::Error when no colour dominates the border (a
/// picture cropped into the object, a photograph): a quarter of the border or more far from it.
PictureBackground estimateBackground(const Image& picture);

/// The background a reconstruction target (an opaque RGB picture at a known view) is compared
/// over, and how it was settled.
struct TargetBackground
{
  PictureBackground background; ///< the one to use (write it into the target's view: applyTo)
  /// Where it came from: "given" (the caller's colour), "view" (the view's background: the
  /// picture's border agrees with it, or has no one colour) or "picture" (estimated from the
  /// picture's border, which disagrees with the view's background).
  std::string source;
  /// Empty, or why the picture's border and the stated background disagree (for a warning).
  std::string warning;
};

/// Settles the background of `picture` (RGB in [0, 1]) taken at `view`. `given`: the colour the
/// caller states; unset: estimated from the picture's border (estimateBackground). The view's
/// background (and background2) is kept when the picture's border agrees with it within
/// max(6 levels of 255, 3 x the border's noise) per channel, or when the border has no one
/// colour (an object cut by the frame); otherwise the picture's estimate is used and `warning`
/// says so. With `given`, that colour is used and `warning` says when the border disagrees.
TargetBackground targetBackground(const Image& picture, const View& view,
  const std::optional<std::array<double, 3>>& given = std::nullopt);

/// Per pixel of a picture: 1 in `foreground` where it differs from the background by more than
/// its noise allows (the object and any overlay), 1 in `overlay` where a foreground part is
/// judged an overlay — a connected part that the object does not explain (see matchPicture).
struct PictureMasks
{
  Image foreground; ///< 1 channel, the size of the part matched (MatchResult::crop)
  Image overlay;    ///< 1 channel, the size of the part matched (MatchResult::crop)
};

/// The final fit's defaults (see MatchOptions::reconstruction).
inline ReconstructionOptions matchReconstructionDefaults()
{
  ReconstructionOptions o;
  o.raysPerIteration = 512;
  o.tolerance = 0.002;
  o.patience = 100;
  return o;
}

/// Options (defaults in brackets).
struct MatchOptions
{
  /// The picture's camera when it is known (e.g. the user says it was taken from the current
  /// camera); its size is replaced by the picture's. Unset: estimated [unset].
  std::optional<View> view;
  /// Refine a given `view` by the camera search too (a hint, not the answer) [false].
  bool refineGivenView = false;
  /// The background colour when it is known; unset: estimated from the picture [unset].
  std::optional<std::array<double, 3>> background;
  /// Opacity unit distance of the views (ParaView's default for the volume when unset).
  std::optional<double> opacityUnitDistance;
  /// The picture's lighting (ParaView's Shade and coefficients) when known; a given `view`
  /// brings its own. Unset with no view: estimated — the picture matched unlit and with Shade on
  /// (ParaView's default coefficients), the TF refitted with Shade on and Specular 0.5 /
  /// SpecularPower 30 at the lit match's camera, the best fit over the object kept; the camera
  /// search's lighting-free stages (silhouettes, the colours' screening) run once for both
  /// matches (about 3.5 times an unlit match's time: a lit render costs more) [unset].
  std::optional<Lighting> lighting;
  /// Reconstruction settings (1D/2D, bins, smoothness, iterations, rays, initial TF, threads)
  /// of the final fit. The match's defaults differ from ReconstructionOptions' in three: 512 rays
  /// per step and convergence judged as a change under 0.2 % over 100 steps (many cheap steps:
  /// the parts of the TF the picture shows least settle late).
  ReconstructionOptions reconstruction = matchReconstructionDefaults();
  /// Weight of the empty-space term: on pixels that show the background, the render's
  /// premultiplied RGBA is pulled to 0, so no air is painted in the background's colour [1].
  double emptySpaceWeight = 1.0;
  /// Mask overlays (parts of the picture the object does not explain) [true].
  bool maskOverlays = true;
  /// Camera candidates scored by a short reconstruction [6].
  int cameraCandidates = 6;
  /// Cameras found by the picture's colours (an emission model of each camera's rays, no TF)
  /// rather than silhouettes, refined on it; those that explain the colours clearly better than
  /// every silhouette camera (a residual under 0.8 of theirs) are scored by a short
  /// reconstruction too, and so is the best explained of them when no scored camera looks from
  /// within 15 degrees of its direction and it explains the colours better than each
  /// (matchparts::camerasToScore). They tell apart the directions of a roundish or translucent
  /// object, whose silhouettes are alike [8; 0: silhouettes only].
  int colourCandidates = 8;
  /// Rounds of the camera's refinement on the picture's colours, each a Nelder-Mead search
  /// with the TF held, then a short refit of the TF [2]. The winner's polish then repeats a
  /// longer fit and a refinement until the camera settles (at most 3 times).
  int cameraRounds = 2;
  /// Below this silhouette overlap (IoU) of the best camera, no camera explains the picture and
  /// matchPicture throws [0.6].
  double minimumOverlap = 0.6;
  /// Below this PSNR of the fit over the object (the picture's foreground or what the render
  /// shows, overlays left out; at a quarter of the picture's size, the render made at the
  /// picture's size and reduced as the picture is), no camera explains the picture and
  /// matchPicture throws [25 dB: an RMS error of 5.6 % of the range. Chosen when the render was
  /// made at the quarter size (pictures of the volume 29.2-41.6 dB on 24 suite screenshots,
  /// another volume's 14.8-22.7 dB on 16 pairs). Judged at the picture's size (2026-12-04):
  /// pictures of the volume 36.9-52.3 dB (14 screenshots), another volume's 14.8-23.6 dB (24)].
  double minimumFitPSNR = 25.0;
  /// Render a preview (the current TF at the found view, premultiplied RGBA at the picture's
  /// size divided by previewDivisor) every `reconstruction.snapshotEvery` steps [4].
  int previewDivisor = 4;
};

/// What the match found.
struct MatchResult
{
  ReconstructionResult tf; ///< the fitted TF (1D or 2D)
  View view; ///< the picture's camera, at the size of `crop` (the picture's) and its background
  /// The part of the picture matched {x, y, width, height}: the whole picture, or what is inside
  /// a letterbox (bands of one colour along its edges, each followed by another colour), or the
  /// render view of a screenshot of a whole window (matchparts::renderedPart).
  std::array<int, 4> crop{ 0, 0, 0, 0 };
  PictureBackground background;   ///< estimated or given
  PictureMasks masks;             ///< what was compared and what was ignored
  bool cameraEstimated = false;   ///< the camera came from the search (not given as is)
  bool lightingEstimated = false; ///< lit or unlit was chosen by the fit (view.lighting says which)
  double otherLightingFitPSNR = 0; ///< when estimated: the next best lighting's fit PSNR
  double overlap = 0;              ///< silhouette IoU of the found camera (1 = exact)
  double fitPSNR = 0; ///< PSNR of the fit over the object (see minimumFitPSNR), picture vs render
  /// The same for the TF the match started from (reconstruction.initial1D: e.g. the query's
  /// design) at the found camera: the "before" [0 when no initial TF was given].
  double initialPSNR = 0;
  std::array<double, 3> orbit{ 0, 0, 0 }; ///< azimuth, elevation, roll from the reset camera (deg)
  /// distance factor from the reset camera (view.camera.parallelProjection: its parallel scale
  /// divided by zoom)
  double zoom = 1;
  std::array<double, 2> pan{ 0, 0 }; ///< pan right, up, in view heights at the focal point
  /// Seconds per stage: background and masks, camera search, the final fit, and in all (lighting
  /// estimated: summed over every lighting matched).
  double backgroundSeconds = 0, cameraSeconds = 0, fitSeconds = 0, seconds = 0;
  /// The camera search's seconds by part (camera searched; a given camera: silhouettes only):
  /// the silhouettes (directions, their refinement, the distance's correction), the colours'
  /// screening, the candidates' short fits and refinement, the winner's polish.
  struct CameraStages
  {
    double silhouettes = 0, colours = 0, candidates = 0, polish = 0;
    CameraStages& operator+=(const CameraStages& o)
    {
      silhouettes += o.silhouettes, colours += o.colours, candidates += o.candidates;
      polish += o.polish;
      return *this;
    }
  } cameraStages;
};

/// Called with (stage, fraction of the whole in [0, 1], preview): stage is "background",
/// "camera" or "fit"; preview is non-null every snapshotEvery fit steps (see MatchOptions).
/// Return false to cancel (matchPicture throws ddg::Cancelled).
using MatchProgress =
  std::function<bool(const std::string& stage, double fraction, const Image* preview)>;

/// Finds a TF (and, unless given, the camera) that makes `renderer`'s volume look like
/// `picture` (RGB in [0, 1], any size and aspect; RGBA with straight alpha is taken as a picture
/// over a transparent background). Throws ddg::Error with the reason for a picture it cannot
/// use: smaller than 16 pixels a side, a uniform picture (nothing but background), no dominant
/// background, or, when the camera is searched, no camera whose silhouette overlaps the
/// picture's object by `minimumOverlap` or whose fit reaches `minimumFitPSNR` ("no camera
/// explains the picture": another volume, a crop into the object). A camera given as the
/// picture's is trusted: its fit's figures say how well it explains the picture.
/// A renderer of a piece of a volume (ParaView's ranks; DifferentiableRenderer.h): collective,
/// every piece calls it with the same picture and options and gets the same result (the block
/// silhouettes and the colours' sample counts are combined over the pieces, every render and fit
/// runs over them; Documentation/Rendering.md, "Matching a picture and carrying a look over
/// pieces").
MatchResult matchPicture(const DifferentiableRenderer& renderer, const Image& picture,
  const MatchOptions& options = {}, const MatchProgress& progress = {});

/// The view `base` (ParaView's reset camera, say) moved as a user does: orbit about the focal
/// point (azimuth about base's view up, then elevation), roll about the view direction (degrees,
/// as vtkCamera::Roll), dolly by `zoom` (distance / zoom; the parallel scale / zoom too), then
/// pan by (right, up) view heights at the focal point (focal point and position move together).
View cameraMove(const View& base, double azimuth, double elevation, double roll, double zoom,
  std::array<double, 2> pan);

} // namespace ddg
