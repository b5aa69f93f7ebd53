// QueryImage.h: how any image (screenshot, figure, photo of a screen) becomes the analyzer's
// input: channels, background, framing around the content, size.
#pragma once

#include "Image/Image.h"

#include <vector>

namespace ddg
{

/// How a query image becomes the analyzer's input (documented for users in README "Query"):
///  1. channels: gray -> RGB, gray+alpha -> RGBA; RGBA (straight alpha) is composed over black;
///     an image whose alpha is 0 everywhere is refused;
///  2. the background colour is the median of the 1-pixel border; pixels differing from it by
///     more than 0.04 in any channel are content; an image without content is refused. A
///     uniform background (90 % of the border within 0.04 of the median) neither black nor white
///     (ParaView's palette grey-blue, any colour) becomes the nearer of the two by luminance, the
///     backgrounds the analyzer was trained on, and the
///     overlays drawn over it (orientation axes, text, a scalar bar: connected parts of the
///     content under a fifth of the largest one's area) become background as well; the content
///     is otherwise kept as it is (its edges still mixed with the old colour). A gradient, a
///     border the content crosses, or content that would vanish on the new colour keep the
///     picture as it was;
///  3. a square of the image's shorter side (the frame ParaView's camera fits the volume to:
///     the vertical view angle of a landscape window), placed on the content's centre and moved
///     inside the image; when the content does not fit, the square grows to hold it and is padded
///     with the background colour. The volume's size in the frame is kept, as the analyzer
///     saw it in training (rescaling it to a standard size changes the latent more than any
///     other step);
///  4. 2 x 2 box averages while the square is 4x the size or more, then OpenImageIO's filtered
///     resize to size x size, quantised to 8 bits as training images are.
/// So any size and aspect works, and a square image of the model's size over black or white is
/// used as it is. Throws ddg::Error for images smaller than 8 x 8, larger than 16384 on a side
/// (DesignGallery's query halves a picture over kQueryPictureSide first; readImage refuses files
/// over 16384 or 64 Mpixel), with other than 1-4 channels, fully transparent or uniform.
Image prepareQueryImage(const Image& image, int size);

/// The side a query's picture is read at, at most: a larger one (a 4K or Retina screenshot, a
/// poster's figure) is halved first (shrinkPicture), which changes neither its framing nor its
/// colours but spares time and memory (DesignGallery::query, analyzeImage, picturePSNR).
constexpr int kQueryPictureSide = 2048;

/// The part of a user's picture a query reads (DesignGallery's query, analyzeImage and
/// picturePSNR, the kind check): its rendered part (inside a letterbox; the render view of a
/// screenshot of a whole window: matchparts::renderedPart, as the match and the carried look read
/// it), halved while over kQueryPictureSide on its longer side (shrinkPicture). `picture` itself
/// when that is all of it and small enough, else `held` holding it (keep `held` while it is used).
const Image& queryPicture(const Image& picture, Image& held);

/// Whether prepareQueryImage finds content in an RGB image: a pixel that differs from the median
/// of the border by more than 0.04 in a channel.
bool hasQueryContent(const Image& rgb);

/// How close a design's render looks to the query's picture when the picture's camera is not
/// known: PSNR (dB) of the two, each cut to a square 10 % larger than its content's box (content:
/// pixels differing from the picture's background, the median of its border, by more than 0.04)
/// and resized to `size`, with `render` (premultiplied RGBA) composed over the picture's
/// background. On a uniform background (90 % of the border within 0.04 of the median) the
/// picture's overlays (orientation axes, text, a scalar bar: its content's connected parts under a
/// fifth of the largest one's area, as step 2 of prepareQueryImage finds them) are painted over
/// with the background first, and each render's parts of that size likewise (a render has no
/// overlays, but a design may have a small part of its own, which the picture then lost too). So
/// the pictures' sizes, aspects, framing, zoom, background and overlays do not count; the viewpoint
/// still does. A render that shows nothing compares as a square of the background.
double framedPSNR(const Image& picture, const Image& render, int size = 128);
/// framedPSNR of each of `renders` against one picture, the picture framed once.
std::vector<double> framedPSNR(
  const Image& picture, const std::vector<const Image*>& renders, int size = 128);

} // namespace ddg
