// MatchParts.h: the picture match's inner parts (Match.cxx and the reading of a picture it
// shares with the carried look and the query's framing): binary rasters, their moments and
// overlaps, connected parts, the volume's block silhouettes, and the part of a picture that shows
// the render (inside a letterbox, the render view of a window's screenshot).
#pragma once

#include "Image/Image.h"
#include "Reconstruct/Match.h"
#include "Render/View.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddg
{
class Volume;

/// The refusal's message when no camera's fit reaches minimumFitPSNR (`matched`: each
/// lighting's fit when the lighting was estimated, else empty).
std::string noCameraExplains(
  double fitPSNR, double minimum, double overlap, const std::string& matched);

namespace matchparts
{
struct CameraSearchStages;
}

/// matchPicture with the lighting as given (options.lighting, or the view's, or unlit): the
/// match itself (Match.cxx); matchPicture (MatchLighting.cxx) estimates the lighting with it.
/// With `stages`, a camera search takes its lighting-free stages from there when they are
/// filled, else fills them (MatchCamera.h).
MatchResult matchPictureLit(const DifferentiableRenderer& renderer, const Image& picture,
  const MatchOptions& options, const MatchProgress& progress,
  matchparts::CameraSearchStages* stages = nullptr);

namespace matchparts
{

// A binary raster (row 0 at the top).
struct Mask
{
  int w = 0, h = 0;
  std::vector<std::uint8_t> m;
  Mask() = default;
  Mask(int width, int height)
    : w(width)
    , h(height)
    , m(static_cast<size_t>(width) * height, 0)
  {
  }
  std::uint8_t operator()(int x, int y) const { return m[static_cast<size_t>(y) * w + x]; }
  std::uint8_t& operator()(int x, int y) { return m[static_cast<size_t>(y) * w + x]; }
};

Image toImage(const Mask& mask);
/// Dilation by a (2r+1)^2 box.
Mask dilate(const Mask& in, int r);
/// The foreground of an RGB picture over `view`'s background (View::backgroundAt, the view the
/// picture's size): pixels off it by more than max(3.5 levels of 255, 4 x noise) in a channel.
Mask foregroundOf(const Image& rgb, const View& view, double noise);
/// Overlay candidates among connected parts: those under `fraction` of the largest part's area.
std::vector<char> smallParts(const std::vector<int>& area, double fraction);
/// Downsampling: a coarse pixel is set when at least half of its area is.
Mask shrink(const Mask& in, int w, int h);
/// The mask with every unset region that does not reach the border set.
Mask fillHoles(const Mask& in);
/// Connected parts (8-neighbourhood): label per pixel (-1 = unset) and areas.
std::vector<int> components(const Mask& mask, std::vector<int>& area);
double median(std::vector<double> v);
/// A fit's final loss: the mean of its last 10 steps' losses.
double tailLoss(const ReconstructionResult& r);

// Area, centroid and principal axis of a mask's set pixels (where care is set).
struct Moments
{
  double area = 0, cx = 0, cy = 0, angle = 0, anisotropy = 1;
};
Moments moments(const Mask& m, const Mask* care = nullptr);
/// IoU of the target with `rendered` moved by the image-plane similarity taking its point cr
/// to the target's ct, rotated by rho (pixel coordinates, y down) and scaled.
double similarityIoU(const Mask& target, const Mask& care, const Mask& rendered, double cr_x,
  double cr_y, double ct_x, double ct_y, double rho, double scale);
/// The image-plane turns (radians) that may align a rendered silhouette `mr` with a target
/// `mt`: their principal axes either way, and every 30 degrees when either is round (anisotropy
/// under 1.3).
std::vector<double> alignmentTurns(const Moments& mt, const Moments& mr);
/// IoU of two masks over the pixels `care` keeps.
double maskIoU(const Mask& target, const Mask& care, const Mask& rendered);

// The volume as blocks: per occupancy level (a value threshold), the centres of the occupied
// blocks on the surface of the occupied set; their projections (discs) make the silhouette of
// "opaque above the threshold" at any camera, far faster than ray casting.
class SilhouetteModel
{
public:
  explicit SilhouetteModel(const Volume& vol);
  /// The renderer's volume; for a piece of one (collective), the whole's: each piece takes the
  /// blocks over the points it owns, the pieces exchange them.
  explicit SilhouetteModel(const DifferentiableRenderer& renderer);

  int levels() const { return static_cast<int>(Points.size()); }
  /// The value threshold of a level (opaque at and above it).
  float threshold(int level) const { return Thresholds[static_cast<size_t>(level)]; }

  // The silhouette of level `level` at `view` in a w x h raster (the view's framing).
  void render(const View& view, int level, int w, int h, Mask& out) const;

private:
  // the levels from the largest value per block (Blocks in MatchSilhouette.cxx) of a volume of
  // `dims` points from `origin` at `spacing`
  void build(const std::array<int, 3>& dims, const std::array<double, 3>& origin,
    const std::array<double, 3>& spacing, const std::vector<float>& blockMax);

  std::vector<std::vector<Eigen::Vector3f>> Points;
  std::vector<float> Thresholds;
  double Radius = 0;
};

/// Bands of one colour along the picture's edges, each followed by a line of another colour:
/// a letterbox (or pillarbox). The part inside {x, y, width, height} (all when there is none).
std::array<int, 4> letterbox(const Image& img);
/// In a screenshot of a whole window (ParaView's GUI: toolbars, the pipeline browser and the
/// properties around the render view), the render view {x, y, width, height}; in a figure (a page
/// of one colour with a render pasted on it, a caption and a colour bar beside it), the pasted
/// render; else the whole picture. A picture whose border has one colour (estimateBackground
/// reads it) is a page when its largest part off that colour is a filled rectangle (97 % of its
/// box) of at least a tenth of the picture, not all of it, whose fill is a render's background,
/// not a veil over the page (a TF that paints the air shows the volume's box so): a vertical
/// gradient (ends 0.1 apart) or black, white or ParaView's palette grey-blue (within 0.06), at
/// least 0.25 from the page (at one end, for a gradient), and that holds an object (below); it is
/// read inside that rectangle less 2 read pixels (below) at its edges, which are mixed with the
/// page (a JPEG's ringing beside them is trimmed off first); a letterbox's inside is left to
/// letterbox, exact to the pixel. A page with a gradient is read whole. A picture whose border has
/// no one colour is a window when it holds a view. The view is the largest region of smoothly
/// varying colour (4-neighbours within 3 levels of 255 in every channel, read at most 512 pixels a
/// side by box halvings) that covers at least 2 % of the picture and 30 % of its box, does not
/// reach the picture's edge (a render cut by the frame, its haze over the volume's box, is no
/// view), whose box's border has one colour or one vertical gradient (estimateBackground) and holds
/// an object: parts off that background of which the ones of at least a fifth of the largest are a
/// solid shape (solidShareOf at least 0.25: a panel of text is not). The box is mapped back to the
/// picture's pixels it was halved from. A picture that is neither (no pasted render, no view),
/// whose border at its own resolution has no one colour, is read inside the first border inset
/// by up to a JPEG block (8 pixels) that has one colour and holds an object (holdsARender): a
/// render cut from a JPEG at or just inside its edge, where the blocks beside the cut ring with
/// the colour cut off (the halved reading averages that ringing away); else whole.
std::array<int, 4> renderView(const Image& img);
/// The part of a picture that shows the rendered scene {x, y, width, height}: the render view of
/// a window's screenshot (renderView), else the inside of its letterbox (letterbox).
std::array<int, 4> renderedPart(const Image& img);
/// The part {x, y, width, height} of a picture (a copy of it all when that is the part).
Image cropTo(const Image& img, const std::array<int, 4>& part);
/// The picture's renderedPart (the picture itself when that is all of it); `crop` gets the part.
Image insideRenderedPart(const Image& img, std::array<int, 4>& crop);
/// The share of a mask's set pixels deeper inside it than 2 % of its box's longer side: a
/// rendered volume is a solid shape (most of it survives), lines and text are not. A mask under
/// 25 pixels on that side (where 2 % is under half a pixel) is too small to tell: 1; an empty
/// one 0.
double solidShareOf(const Mask& object);

} // namespace matchparts
} // namespace ddg
