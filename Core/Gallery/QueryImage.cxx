// QueryImage.cxx: query images to analyzer inputs.
#include "Gallery/QueryImage.h"

#include "Reconstruct/MatchParts.h"

#include "Common/Error.h"
#include "Image/ImageMetrics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

namespace ddg
{

namespace
{
/// Step 1: RGB over black (straight alpha composed); throws for a fully transparent image.
Image rgbOverBlack(const Image& image)
{
  const int w = image.width, h = image.height;
  Image rgb(w, h, 3);
  const bool alpha = image.channels == 2 || image.channels == 4;
  bool anyAlpha = !alpha;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      const float a = alpha ? std::clamp(image.at(x, y, image.channels - 1), 0.0f, 1.0f) : 1.0f;
      anyAlpha = anyAlpha || a > 0;
      for (int c = 0; c < 3; ++c)
      {
        const float v = image.at(x, y, image.channels >= 3 ? c : 0);
        rgb.at(x, y, c) = std::clamp(v, 0.0f, 1.0f) * a;
      }
    }
  if (!anyAlpha)
    throw Error("the query image is fully transparent (alpha is 0 everywhere)");
  return rgb;
}

/// Step 2: the background (median of the border) and the content's box (pixels differing from
/// it by more than 0.04 in a channel; x1 < 0 when there is none).
struct Content
{
  std::array<float, 3> bg{};
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
};

/// A pixel is content when a channel differs from the background by more than this.
constexpr float kContentTolerance = 0.04f;

/// Whether pixel (x, y) of `rgb` differs from `bg` by more than kContentTolerance in a channel.
bool differs(const Image& rgb, int x, int y, const std::array<float, 3>& bg)
{
  for (int c = 0; c < 3; ++c)
    if (std::abs(rgb.at(x, y, c) - bg[c]) > kContentTolerance)
      return true;
  return false;
}

/// The background the analyzer sees for a picture's background colour: black or white as they
/// are (within kContentTolerance); any other colour (ParaView's palette grey-blue, a user's
/// colour) the nearer of black and white by luminance (Rec. 709), the two the analyzer was
/// trained on.
std::array<float, 3> analyzerBackground(const std::array<float, 3>& bg)
{
  auto isNear = [&bg](float v)
  {
    for (float c : bg)
      if (std::abs(c - v) > kContentTolerance)
        return false;
    return true;
  };
  if (isNear(0.0f) || isNear(1.0f))
    return bg;
  const float luminance = 0.2126f * bg[0] + 0.7152f * bg[1] + 0.0722f * bg[2];
  return luminance < 0.5f ? std::array<float, 3>{ 0, 0, 0 } : std::array<float, 3>{ 1, 1, 1 };
}

/// Whether the picture's border is one colour: at least 90 % of its pixels within
/// kContentTolerance of `bg` (its median). Not so for a gradient background (only a band of rows
/// is near the median) or content across the border.
bool uniformBorder(const Image& rgb, const std::array<float, 3>& bg)
{
  const int w = rgb.width, h = rgb.height;
  long alike = 0, total = 0;
  auto count = [&](int x, int y)
  {
    alike += differs(rgb, x, y, bg) ? 0 : 1;
    ++total;
  };
  for (int x = 0; x < w; ++x)
  {
    count(x, 0);
    count(x, h - 1);
  }
  for (int y = 1; y < h - 1; ++y)
  {
    count(0, y);
    count(w - 1, y);
  }
  return alike >= 0.9 * total;
}

/// Per pixel (row-major), what it shows against the background: kBackground (within
/// kContentTolerance of it), kOverlay (a connected part of the content under a fifth of the
/// largest one's area: orientation axes, text, a scalar bar; the size rule by which the match
/// takes parts for overlay candidates) or kShown.
enum PixelKind : std::uint8_t
{
  kShown,
  kBackground,
  kOverlay
};
struct PixelKinds
{
  std::vector<std::uint8_t> kind;
  bool anyOverlay = false;
};
/// The kinds of the pixels of a content mask (findContent's, or contentMask's).
PixelKinds pixelKinds(const matchparts::Mask& content)
{
  std::vector<int> area;
  const std::vector<int> part = matchparts::components(content, area);
  const std::vector<char> overlay = matchparts::smallParts(area, 0.2);
  PixelKinds k;
  k.kind.assign(part.size(), kShown);
  for (size_t i = 0; i < part.size(); ++i)
    if (part[i] < 0)
      k.kind[i] = kBackground;
    else if (overlay[static_cast<size_t>(part[i])])
    {
      k.kind[i] = kOverlay;
      k.anyOverlay = true;
    }
  return k;
}

/// The pixels of `rgb` that differ from `bg` (differs).
matchparts::Mask contentMask(const Image& rgb, const std::array<float, 3>& bg)
{
  matchparts::Mask content(rgb.width, rgb.height);
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < rgb.width; ++x)
      content(x, y) = differs(rgb, x, y, bg);
  return content;
}

/// The box of the kShown pixels of `rgb` that differ from `bg` (x1 < 0 when there is none):
/// findContent's box of `rgb` with its other kinds painted `bg`, without scanning it again.
Content shownBox(const Image& rgb, const PixelKinds& kinds, const std::array<float, 3>& bg)
{
  Content box;
  box.bg = bg;
  box.x0 = rgb.width;
  box.y0 = rgb.height;
  box.x1 = box.y1 = -1;
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < rgb.width; ++x)
      if (kinds.kind[static_cast<size_t>(y) * rgb.width + x] == kShown && differs(rgb, x, y, bg))
      {
        box.x0 = std::min(box.x0, x);
        box.x1 = std::max(box.x1, x);
        box.y0 = std::min(box.y0, y);
        box.y1 = std::max(box.y1, y);
      }
  return box;
}

/// `rgb` with the pixels of the kinds `paint` says painted `colour`.
Image paintedOver(const Image& rgb, const std::vector<std::uint8_t>& kind,
  std::initializer_list<PixelKind> paint, const std::array<float, 3>& colour)
{
  if (rgb.channels != 3)
    throw Error("paintedOver: RGB expected");
  Image painted = rgb;
  for (size_t i = 0; i < kind.size(); ++i)
    if (std::find(paint.begin(), paint.end(), kind[i]) != paint.end())
      for (int c = 0; c < 3; ++c)
        painted.pixels[i * 3 + static_cast<size_t>(c)] = colour[static_cast<size_t>(c)];
  return painted;
}

/// The background (median of the border) and the content's box; with `mask`, the content's
/// pixels too (contentMask of the background found).
Content findContent(const Image& rgb, matchparts::Mask* mask = nullptr)
{
  const int w = rgb.width, h = rgb.height;
  Content k;
  for (int c = 0; c < 3; ++c)
  {
    std::vector<float> border;
    for (int x = 0; x < w; ++x)
    {
      border.push_back(rgb.at(x, 0, c));
      border.push_back(rgb.at(x, h - 1, c));
    }
    for (int y = 1; y < h - 1; ++y)
    {
      border.push_back(rgb.at(0, y, c));
      border.push_back(rgb.at(w - 1, y, c));
    }
    std::nth_element(border.begin(), border.begin() + border.size() / 2, border.end());
    k.bg[c] = border[border.size() / 2];
  }
  k.x0 = w;
  k.y0 = h;
  if (mask)
    *mask = matchparts::Mask(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      if (differs(rgb, x, y, k.bg))
      {
        if (mask)
          (*mask)(x, y) = 1;
        k.x0 = std::min(k.x0, x);
        k.x1 = std::max(k.x1, x);
        k.y0 = std::min(k.y0, y);
        k.y1 = std::max(k.y1, y);
      }
    }
  return k;
}

/// A square of `side` pixels of `rgb` with its top left at (ox, oy), the background outside.
Image squareOf(const Image& rgb, int side, int ox, int oy, const std::array<float, 3>& bg)
{
  Image square(side, side, 3);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
    {
      const int sx = ox + x, sy = oy + y;
      const bool in = sx >= 0 && sx < rgb.width && sy >= 0 && sy < rgb.height;
      for (int c = 0; c < 3; ++c)
        square.at(x, y, c) = in ? rgb.at(sx, sy, c) : bg[c];
    }
  return square;
}
} // namespace

const Image& queryPicture(const Image& picture, Image& held)
{
  const std::array<int, 4> part = matchparts::renderedPart(picture);
  if (part[2] == picture.width && part[3] == picture.height)
    return shrinkPicture(picture, kQueryPictureSide, held);
  held = shrinkPicture(matchparts::cropTo(picture, part), kQueryPictureSide);
  return held;
}

Image prepareQueryImage(const Image& image, int size)
{
  if (size < 8)
    throw Error("the analyzer input must be at least 8 pixels");
  if (image.width < 8 || image.height < 8)
    throw Error("the query image is " + std::to_string(image.width) + " x " +
      std::to_string(image.height) + " pixels: too small (at least 8 x 8)");
  if (image.width > 16384 || image.height > 16384)
    throw Error("the query image is " + std::to_string(image.width) + " x " +
      std::to_string(image.height) + " pixels: too large (at most 16384 on a side)");
  if (image.channels < 1 || image.channels > 4)
    throw Error("the query image has " + std::to_string(image.channels) +
      " channels (gray, gray+alpha, RGB or RGBA expected)");
  for (float v : image.pixels)
    if (!std::isfinite(v))
      throw Error("the query image holds non-finite values");
  // 1. RGB over black
  const int w = image.width, h = image.height;
  Image rgb = rgbOverBlack(image);
  // 2. background = median of the border, content = pixels that differ from it
  matchparts::Mask content;
  const Content k = findContent(rgb, &content);
  if (k.x1 < 0)
    throw Error("the query image shows nothing: every pixel is the background colour");
  // 2b. a uniform background of another colour (a screenshot of ParaView's GUI) becomes the
  // nearer of black and white, and the overlays drawn over it (orientation axes, text, a scalar
  // bar: the content's connected parts under a fifth of the largest one's area) become
  // background too; a gradient, or a border the content crosses, is kept as it is
  std::array<float, 3> bg = analyzerBackground(k.bg);
  if (bg != k.bg && !uniformBorder(rgb, k.bg))
    bg = k.bg;
  Content kept = k;
  if (bg != k.bg)
  {
    const PixelKinds kinds = pixelKinds(content);
    // content as dark (light) as black (white) would vanish: the picture is kept as it was
    const Content left = shownBox(rgb, kinds, bg);
    if (left.x1 >= 0)
    {
      rgb = paintedOver(rgb, kinds.kind, { kBackground, kOverlay }, bg);
      kept = left;
    }
    else
      bg = k.bg;
  }
  const int x0 = kept.x0, y0 = kept.y0, x1 = kept.x1, y1 = kept.y1;
  // 3. a square of the shorter side on the content's centre, inside the image if it fits
  const int extent = std::max(x1 - x0 + 1, y1 - y0 + 1);
  const int side = std::max(std::min(w, h), extent);
  auto place = [side](double centre, int length)
  {
    int o = static_cast<int>(std::lround(centre - 0.5 * side));
    if (side <= length)
      o = std::clamp(o, 0, length - side);
    return o;
  };
  const int ox = place(0.5 * (x0 + x1 + 1), w), oy = place(0.5 * (y0 + y1 + 1), h);
  Image square = squareOf(rgb, side, ox, oy, bg);
  // 4. the model's size, quantised to 8 bits as the training images are
  Image out = shrinkImage(std::move(square), size, size, 4); // as the analyzer was trained
  for (float& v : out.pixels)
    v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
  return out;
}

bool hasQueryContent(const Image& rgb)
{
  return findContent(rgbOverBlack(rgb)).x1 >= 0;
}

double framedPSNR(const Image& picture, const Image& render, int size)
{
  return framedPSNR(picture, std::vector<const Image*>{ &render }, size).front();
}

std::vector<double> framedPSNR(
  const Image& picture, const std::vector<const Image*>& renders, int size)
{
  for (const Image* render : renders)
    if (render->channels != 4)
      throw Error("framedPSNR: the render must be premultiplied RGBA");
  // the picture's background under the render too, so that only the content counts
  Image rgb = rgbOverBlack(picture);
  matchparts::Mask content;
  Content k = findContent(rgb, &content);
  // on a uniform background the picture's overlays (orientation axes, text, a scalar bar) are
  // painted over with it, so that they neither widen its frame nor count; each render's small
  // parts likewise, so that a design with a small part of its own scores as its picture does
  // (an image of one part, most renders, is left as it is)
  const bool leaveOutSmallParts = k.x1 >= 0 && uniformBorder(rgb, k.bg);
  // `shown`: the content of `img` against the picture's background; c keeps its own background
  auto withoutSmallParts = [&k](Image& img, Content& c, const matchparts::Mask& shown)
  {
    const PixelKinds kinds = pixelKinds(shown);
    if (!kinds.anyOverlay)
      return;
    const Content left = shownBox(img, kinds, k.bg);
    img = paintedOver(img, kinds.kind, { kOverlay }, k.bg);
    c.x0 = left.x0;
    c.y0 = left.y0;
    c.x1 = left.x1;
    c.y1 = left.y1;
  };
  if (leaveOutSmallParts)
    withoutSmallParts(rgb, k, content);
  const std::array<double, 3> bg{ k.bg[0], k.bg[1], k.bg[2] };
  auto framed = [size, &k](const Image& img, const Content& c)
  {
    if (c.x1 < 0) // nothing shows: a square of the background
    {
      Image plain(size, size, 3);
      for (size_t i = 0; i < plain.pixels.size(); ++i)
        plain.pixels[i] = k.bg[i % 3];
      return plain;
    }
    // a square 10 % larger than the content's box, on its centre, resized
    const int extent = std::max(c.x1 - c.x0 + 1, c.y1 - c.y0 + 1);
    const int side = std::max(8, static_cast<int>(std::lround(1.1 * extent)));
    const Image sq =
      squareOf(img, side, (c.x0 + c.x1 + 1 - side) / 2, (c.y0 + c.y1 + 1 - side) / 2, k.bg);
    return shrinkImage(sq, size, size, 2);
  };
  const Image a = framed(rgb, k);
  std::vector<double> out;
  for (const Image* render : renders)
  {
    Image over = compositeOverBackground(*render, bg);
    matchparts::Mask shown; // the render's content, against the picture's background
    Content c = findContent(over, leaveOutSmallParts ? &shown : nullptr);
    if (leaveOutSmallParts && c.x1 >= 0)
    {
      if (c.bg != k.bg) // its border is not all background: it reaches it, or 8-bit rounding
        shown = contentMask(over, k.bg);
      withoutSmallParts(over, c, shown);
    }
    out.push_back(psnr(a, framed(over, c)));
  }
  return out;
}

} // namespace ddg
