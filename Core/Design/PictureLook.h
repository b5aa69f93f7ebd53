// PictureLook.h: how users' pictures of a volume differ from a design's clean exemplar image —
// the frame, the camera's roll, pan and zoom, the background, ParaView's overlays and JPEG — so
// that the query's analyzer can learn from pictures as users have them (issue 20).
#pragma once

#include "Image/Image.h"
#include "Render/View.h"

#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace ddg
{

/// One picture's look, drawn by samplePictureLook and recorded in dataset.json ("picture").
struct PictureLook
{
  int width = 0, height = 0;      ///< the picture's frame in pixels
  double roll = 0;                ///< degrees about the view direction
  double panRight = 0, panUp = 0; ///< the camera moved by these fractions of the view height
  double zoom = 1;                ///< a dolly towards the focal point (parallel: scale / zoom)
  std::array<double, 3> background{ 0, 0, 0 };      ///< uniform, or the bottom row of a gradient
  std::optional<std::array<double, 3>> background2; ///< the top row of a gradient
  bool axes = false;                                ///< ParaView's orientation axes, lower left
  bool scalarBar = false;                           ///< a colour legend of the TF's colours, right
  bool text = false;                                ///< lines of text (a title, annotations)
  int jpegQuality = 0;                              ///< JPEG at this quality (1..100); 0: lossless
  std::uint64_t seed = 0;                           ///< the overlays' details (places, glyphs)
};

/// Draws a look for an exemplar of `size` pixels (the analyzer's input), the picture `2 size`
/// pixels high. The distribution (README, "Design space spec", picture_fraction):
///   frame 1:1, 4:3, 16:10 or 16:9 (p 0.15, 0.45, 0.2, 0.2); roll uniform in [-30, 30] degrees;
///   pan uniform in [-0.08, 0.08] of the view height along right and up; zoom x [0.8, 1.25];
///   background ParaView's palette grey-blue (0.32, 0.34, 0.43) p 0.25, black 0.15, white 0.15,
///   another uniform colour 0.2, a vertical gradient 0.25 (ParaView's default pair or two drawn
///   colours, even odds); orientation axes p 0.5, scalar bar 0.3, text 0.3; JPEG p 0.5 at quality
///   uniform in [50, 95].
PictureLook samplePictureLook(std::mt19937_64& rng, int size);

/// The picture's view: `orbit` (the exemplar's V_exp) in the look's frame, rolled, panned and
/// zoomed, over the look's background; lighting and opacity unit distance kept.
View pictureView(const View& orbit, const PictureLook& look);

/// The picture: `render` (premultiplied RGBA at pictureView) over the look's background, its
/// overlays drawn (the orientation axes point along the view's projected world axes; the scalar
/// bar shows `legend`, colours from low to high value, a cool-to-warm ramp when empty), then
/// JPEG-compressed when the look says so. RGB, values k / 255.
Image drawPicture(const Image& render, const View& view, const PictureLook& look,
  const std::vector<std::array<double, 3>>& legend = {});

/// The look as dataset.json records it (JSON text) and back (throws ddg::Error naming origin).
std::string pictureLookToJson(const PictureLook& look);
PictureLook parsePictureLook(const std::string& jsonText, const std::string& origin);

} // namespace ddg
