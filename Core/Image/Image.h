// Image.h: float images, compositing over a background as ParaView's framebuffer does, and file
// I/O through OpenImageIO.
#pragma once

#include "Common/Error.h"

#include <array>
#include <string>
#include <vector>

namespace ddg
{

/// A float image, `channels` interleaved values per pixel, row 0 at the top.
struct Image
{
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels; ///< width * height * channels

  Image() = default;
  Image(int w, int h, int c, float fill = 0.0f)
    : width(w)
    , height(h)
    , channels(c)
    , pixels(static_cast<size_t>(w) * h * c, fill)
  {
  }
  float& at(int x, int y, int c)
  {
    return pixels[(static_cast<size_t>(y) * width + x) * channels + c];
  }
  float at(int x, int y, int c) const
  {
    return pixels[(static_cast<size_t>(y) * width + x) * channels + c];
  }
  bool empty() const { return pixels.empty(); }
};

/// Composes a premultiplied RGBA image over an opaque background exactly as ParaView's 8-bit
/// framebuffer does: out = round(255 C) + round(bg8 (255 - round(255 A)) / 255),
/// bg8 = round(255 background), per channel, clamped to 255. Returns RGB with values k / 255.
Image compositeOverBackground(
  const Image& premultipliedRGBA, const std::array<double, 3>& background);
/// The same over ParaView's vertical gradient background: `bottom` at the bottom row, `top` at
/// the top row, linear at pixel centres (View::backgroundAt).
Image compositeOverBackground(const Image& premultipliedRGBA, const std::array<double, 3>& bottom,
  const std::array<double, 3>& top);

/// Straight (unpremultiplied) alpha from premultiplied RGBA, as PNG stores it: C / A clamped to
/// 1, and 0 where A = 0. Throws ddg::Error for an image without 4 channels.
Image unpremultiplyAlpha(const Image& premultipliedRGBA);
/// Premultiplied RGBA from straight alpha: C * A. Throws ddg::Error for an image without 4
/// channels.
Image premultiplyAlpha(const Image& straightRGBA);

/// Reads any image OpenImageIO reads (PNG, JPEG, TIFF, EXR, ...) as float in [0, 1] for
/// integer formats, alpha exactly as stored (straight alpha for PNG; no premultiplication).
/// Throws ddg::Error with the path and OpenImageIO's reason.
Image readImage(const std::string& path);

/// What readImage found in the file: per-channel storage ("uint8", "uint16", "half", "float",
/// ...) and the channel count.
struct ImageFileInfo
{
  std::string format;
  int channels = 0;
};
Image readImage(const std::string& path, ImageFileInfo* info);

/// Reads an image file's contents held in memory (PNG, JPEG, TIFF, BMP, GIF or WebP, told by their
/// first bytes; e.g. a screenshot sent by the GUI), as readImage. `origin` names it in errors
/// ("cannot read <origin>: <reason>", "<origin> is not a PNG, JPEG, TIFF, BMP, GIF or WebP file").
/// Throws ddg::Error for another format or a file OpenImageIO cannot read.
Image decodeImage(const std::string& bytes, const std::string& origin = "the image data");
/// The format decodeImage reads `bytes` as, told by their first bytes: ".png", ".jpg", ".tif",
/// ".bmp", ".gif" or ".webp"; empty for anything else (the first 12 bytes are enough).
std::string imageFormat(const std::string& bytes);

/// The image JPEG-compressed at `quality` (1..100) with OpenImageIO and read back, in memory:
/// what a picture saved as JPEG looks like. RGB (or gray) values k / 255. Throws ddg::Error.
Image jpegRoundTrip(const Image& image, int quality);

/// Resamples an image to width x height as OpenImageIO's filtered resize does (its default
/// filter: lanczos3 shrinking, blackman-harris enlarging; its weights, its clamped edges), one
/// axis at a time: equal to ImageBufAlgo::resize to float rounding and ~10x cheaper (a 150-pixel
/// square to 128: 0.8 against 9 ms on one thread). Throws ddg::Error for an empty image or size.
Image resizeImage(const Image& image, int width, int height);

/// An image made smaller: halved by 2 x 2 box averages of each channel while it is at least
/// `halveFrom` times width x height on both sides (an odd last row or column left out), then
/// resizeImage when the size is not reached. Alpha is averaged as any channel: right for
/// premultiplied RGBA, not for straight alpha. Cheaper than one wide filtered resize (a
/// 400-pixel square to 128: 5 ms on one thread, 52 ms through OpenImageIO's resize); what the
/// query's framing and the reading of a picture (readPictureObject) shrink with.
Image shrinkImage(Image image, int width, int height, int halveFrom = 2);

/// A user's picture made no larger than its use needs: halved by 2 x 2 box averages (as
/// shrinkImage halves) while its longer side is over `longest` and its shorter side at least 32 (a
/// strip stays longer). 2 and 4 channels carry straight alpha last (grey or RGB and alpha, as PNG
/// stores them): the other channels are averaged weighted by it (premultiplied), so a transparent
/// pixel's colour does not bleed in. A picture already small enough is returned unchanged (moved,
/// not copied, when it is passed with std::move). The query reads pictures at most 2048 pixels a
/// side (kQueryPictureSide), the carried look at most 512 (readPictureObject).
Image shrinkPicture(Image picture, int longest);
/// shrinkPicture without the copy of a picture already small enough: `picture` itself then,
/// else `shrunk` holding shrinkPicture(picture, longest) (keep `shrunk` while the result is used).
const Image& shrinkPicture(const Image& picture, int longest, Image& shrunk);

/// shrinkPicture(readImage(path, info), longest), the same pixels to the bit, read strip by strip
/// (2^k scanlines at a time, each strip halved k times as it is read) so that a large picture is
/// never held whole: an 8K screenshot costs its halved size, not 566 MB of float. Tiled files are
/// read whole first. Throws ddg::Error as readImage.
Image readShrunkPicture(const std::string& path, int longest, ImageFileInfo* info = nullptr);

/// Writes an image; the format follows the extension. 8-bit formats (PNG, JPEG, ...) get
/// round(255 clamp(v, 0, 1)); EXR and TIFF ".tif(f)" keep float. 1, 3 or 4 channels.
/// Values are written as given (an RGBA image is stored as is: pass straight alpha for PNG).
/// Written atomically (temporary file + rename). Throws ddg::Error on failure.
void writeImage(const Image& image, const std::string& path);

/// Writes RGB frames of one size as an animation (a format with frame sequences: .gif), looping,
/// at `fps` frames per second. Atomic. Throws ddg::Error otherwise.
void writeAnimation(const std::vector<Image>& frames, const std::string& path, double fps = 12);

/// Drops or adds channels: RGBA -> RGB (alpha dropped), gray -> RGB, RGB -> RGBA (alpha 1).
Image toChannels(const Image& image, int channels);

/// A picture in colour: grey -> RGB and grey-alpha -> RGBA (the grey in red, green and blue),
/// RGB and RGBA as they are. How every reader of a user's picture takes a grey figure.
Image inColour(Image image);

/// A contact sheet: RGB images (RGBA: alpha dropped; gray: spread) row by row, `columns` per
/// row, cells the size of the largest image, `gap` pixels of `background` between and around
/// them. Throws ddg::Error for no images or columns < 1.
Image tileImages(
  const std::vector<Image>& images, int columns, int gap = 2, float background = 1.0f);

/// A sheet of premultiplied RGBA renders (thumbnails) to compose over a view's background:
/// `columns` x `rows` cells of cell x cell pixels, filled row by row from the top, `gap` pixels
/// between and around them; the gaps and the unused cells are transparent. Throws ddg::Error
/// for more renders than cells, a render that is not cell x cell RGBA, columns, rows or cell
/// < 1, or gap < 0. The pointers must not be null.
Image tileRenders(
  const std::vector<const Image*>& renders, int columns, int rows, int cell, int gap = 2);

} // namespace ddg
