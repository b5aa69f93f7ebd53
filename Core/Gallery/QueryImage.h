// QueryImage.h: how any image (screenshot, figure, photo of a screen) becomes the analyzer's
// input: channels, background, framing around the content, size.
#pragma once

#include "Image/Image.h"

namespace ddg
{

/// How a query image becomes the analyzer's input (documented for users in README "Query"):
///  1. channels: gray -> RGB, gray+alpha -> RGBA; RGBA (straight alpha) is composed over black;
///     an image whose alpha is 0 everywhere is refused;
///  2. the background colour is the median of the 1-pixel border; pixels differing from it by
///     more than 0.04 in any channel are content; an image without content is refused;
///  3. a square centred on the content's bounding box, its side the larger extent divided by
///     `fill`, the fraction of the frame the volume's content spans in training images (median
///     over generated exemplars: Tooth 0.69, Engine 0.64; default 0.67), padded with the background colour where it leaves the image;
///  4. OpenImageIO's filtered resize to size x size.
/// So any size and aspect works, and a screenshot with the volume small in a corner is framed
/// as the analyzer was trained. Backgrounds other than black or white are kept (the analyzer
/// was trained on black and white). Throws ddg::Error for images smaller than 8 x 8, larger
/// than 16384 on a side, with other than 1-4 channels, fully transparent or uniform.
Image prepareQueryImage(const Image& image, int size, double fill = 0.67);

} // namespace ddg
