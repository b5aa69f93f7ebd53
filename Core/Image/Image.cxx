// Image.cxx: compositing and OpenImageIO-based reading and writing.
#include "Image/Image.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/filter.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

namespace ddg
{

Image unpremultiplyAlpha(const Image& in)
{
  if (in.channels != 4)
    throw Error("unpremultiplyAlpha needs RGBA, not " + std::to_string(in.channels) + " channels");
  Image out = in;
  for (size_t i = 0; i < out.pixels.size(); i += 4)
  {
    const float a = out.pixels[i + 3];
    for (int c = 0; c < 3; ++c)
      out.pixels[i + c] = a > 0 ? std::min(1.0f, out.pixels[i + c] / a) : 0.0f;
  }
  return out;
}

Image premultiplyAlpha(const Image& in)
{
  if (in.channels != 4)
    throw Error("premultiplyAlpha needs RGBA, not " + std::to_string(in.channels) + " channels");
  Image out = in;
  for (size_t i = 0; i < out.pixels.size(); i += 4)
    for (int c = 0; c < 3; ++c)
      out.pixels[i + c] *= out.pixels[i + 3];
  return out;
}

Image compositeOverBackground(const Image& in, const std::array<double, 3>& background)
{
  return compositeOverBackground(in, background, background);
}

Image compositeOverBackground(
  const Image& in, const std::array<double, 3>& bottom, const std::array<double, 3>& top)
{
  if (in.channels != 4)
  {
    throw Error("compositeOverBackground needs an RGBA image");
  }
  Image out(in.width, in.height, 3);
  for (int y = 0; y < in.height; ++y)
  {
    const double t = (y + 0.5) / in.height; // 0 at the top row
    long bg8[3];
    for (int c = 0; c < 3; ++c)
    {
      bg8[c] = std::lround(255.0 * std::clamp(top[c] * (1 - t) + bottom[c] * t, 0.0, 1.0));
    }
    for (int x = 0; x < in.width; ++x)
    {
      const size_t i = static_cast<size_t>(y) * in.width + x;
      const double a = std::clamp(static_cast<double>(in.pixels[4 * i + 3]), 0.0, 1.0);
      const long a8 = std::lround(255.0 * a);
      for (int c = 0; c < 3; ++c)
      {
        const double col = std::clamp(static_cast<double>(in.pixels[4 * i + c]), 0.0, 1.0);
        long v = std::lround(255.0 * col) + std::lround(bg8[c] * (255 - a8) / 255.0);
        v = std::min(v, 255L);
        out.pixels[3 * i + c] = static_cast<float>(v) / 255.0f;
      }
    }
  }
  return out;
}

Image readImage(const std::string& path)
{
  return readImage(path, nullptr);
}

namespace
{
Image halve(const Image& image, bool alphaWeighted);

void checkLongest(int longest)
{
  if (longest < 1)
    throw Error("a picture's longest side must be at least 1 pixel");
}

/// How many times shrinkPicture halves a width x height picture for `longest`.
int halvings(int width, int height, int longest)
{
  checkLongest(longest);
  int k = 0;
  for (int w = width, h = height; std::max(w, h) > longest && std::min(w, h) >= 32; ++k)
  {
    w /= 2;
    h /= 2;
  }
  return k;
}

/// readImage through `proxy` (nullptr: the file `path`); `path` names the format and the errors.
/// With `longest` > 0 the picture is read as shrinkPicture(picture, longest) gives it, in strips
/// of 2^k scanlines each halved k times (a 2 x 2 block never crosses a strip, and both floor the
/// sizes alike, so the pixels are the same).
Image readImageFrom(
  const std::string& path, ImageFileInfo* info, OIIO::Filesystem::IOProxy* proxy, int longest = 0)
{
  // Keep alpha as stored (straight for PNG); OpenImageIO would premultiply otherwise.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  if (proxy) // OpenImageIO 2.4's readers look for the proxy in the configuration
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto input = OIIO::ImageInput::open(path, &config, proxy);
  if (!input)
  {
    const std::string reason = firstLine(OIIO::geterror());
    throw Error(
      "cannot read image '" + path + "': " + (reason.empty() ? "unknown format" : reason));
  }
  const OIIO::ImageSpec& spec = input->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1)
  {
    throw Error("image '" + path + "' is empty or not a 2D image");
  }
  if (spec.width > 16384 || spec.height > 16384 ||
    static_cast<long long>(spec.width) * spec.height > 64LL * 1024 * 1024)
  {
    throw Error("image '" + path + "' is " + std::to_string(spec.width) + " x " +
      std::to_string(spec.height) + " pixels: too large (at most 16384 on a side, 64 Mpixel)");
  }
  if (info)
  {
    info->format = spec.format.c_str();
    info->channels = spec.nchannels;
  }
  auto failed = [&]()
  {
    const std::string reason = firstLine(input->geterror());
    return Error("cannot read image '" + path + "': " + (reason.empty() ? "read error" : reason));
  };
  const int k = longest > 0 ? halvings(spec.width, spec.height, longest) : 0;
  if (k == 0 || spec.tile_width > 0)
  {
    Image img(spec.width, spec.height, spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
      throw failed();
    input->close();
    if (k == 0)
      return img;
    return shrinkPicture(std::move(img), longest);
  }
  const int rows = 1 << k;
  const bool alpha = spec.nchannels == 2 || spec.nchannels == 4;
  Image out(spec.width >> k, spec.height >> k, spec.nchannels);
  Image strip(spec.width, rows, spec.nchannels);
  const size_t rowValues = static_cast<size_t>(out.width) * static_cast<size_t>(out.channels);
  for (int y = 0; y < out.height; ++y)
  {
    if (!input->read_scanlines(0, 0, spec.y + y * rows, spec.y + (y + 1) * rows, 0, 0,
          spec.nchannels, OIIO::TypeDesc::FLOAT, strip.pixels.data()))
      throw failed();
    Image row = halve(strip, alpha);
    while (row.height > 1)
      row = halve(row, alpha);
    std::copy_n(
      row.pixels.begin(), rowValues, out.pixels.begin() + static_cast<long>(rowValues) * y);
  }
  input->close();
  return out;
}
} // namespace

Image readImage(const std::string& path, ImageFileInfo* info)
{
  return readImageFrom(path, info, nullptr);
}

Image readShrunkPicture(const std::string& path, int longest, ImageFileInfo* info)
{
  checkLongest(longest); // before the file is opened
  return readImageFrom(path, info, nullptr, longest);
}

std::string imageFormat(const std::string& bytes)
{
  auto starts = [&bytes](const char* magic, size_t n)
  { return bytes.size() >= n && bytes.compare(0, n, magic, n) == 0; };
  if (starts("\x89PNG\r\n\x1a\n", 8))
    return ".png";
  if (starts("\xff\xd8\xff", 3))
    return ".jpg";
  if (starts("II*\0", 4) || starts("MM\0*", 4))
    return ".tif";
  if (starts("BM", 2))
    return ".bmp";
  if (starts("GIF87a", 6) || starts("GIF89a", 6))
    return ".gif";
  if (starts("RIFF", 4) && bytes.size() >= 12 && bytes.compare(8, 4, "WEBP") == 0)
    return ".webp";
  return {};
}

Image decodeImage(const std::string& bytes, const std::string& origin)
{
  const std::string ext = imageFormat(bytes);
  if (ext.empty())
    throw Error(origin + " is not a PNG, JPEG, TIFF, BMP, GIF or WebP file (" +
      std::to_string(bytes.size()) + " bytes)");
  OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
  // the name only tells OpenImageIO the format; errors name the origin
  try
  {
    return readImageFrom("memory" + ext, nullptr, &reader);
  }
  catch (const Error& e)
  {
    std::string what = e.what();
    const std::string name = "image 'memory" + ext + "'";
    for (size_t at; (at = what.find(name)) != std::string::npos;)
      what.replace(at, name.size(), origin);
    throw Error(what);
  }
}

Image jpegRoundTrip(const Image& image, int quality)
{
  if (image.empty() || (image.channels != 1 && image.channels != 3))
    throw Error("jpegRoundTrip needs a gray or RGB image");
  if (quality < 1 || quality > 100)
    throw Error("JPEG quality must be in [1, 100]");
  std::vector<unsigned char> bytes(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i)
    bytes[i] =
      static_cast<unsigned char>(std::lround(std::clamp(image.pixels[i], 0.0f, 1.0f) * 255.0f));
  std::vector<unsigned char> file;
  OIIO::Filesystem::IOVecOutput writer(file);
  OIIO::Filesystem::IOProxy* proxy = &writer;
  auto out = OIIO::ImageOutput::create("memory.jpg");
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
  spec.attribute("Compression", "jpeg:" + std::to_string(quality));
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  if (!out || !out->supports("ioproxy") || !out->open("memory.jpg", spec) ||
    !out->write_image(OIIO::TypeDesc::UINT8, bytes.data()) || !out->close())
    throw Error(
      "cannot encode a JPEG in memory: " + (out ? out->geterror() : std::string("no JPEG writer")));
  return decodeImage(std::string(file.begin(), file.end()), "the JPEG in memory");
}

void writeImage(const Image& image, const std::string& path)
{
  if (image.empty() || (image.channels != 1 && image.channels != 3 && image.channels != 4))
  {
    throw Error(
      "cannot write image '" + path + "': it is empty or has an unsupported channel count");
  }
  const std::string ext = fileExtension(path);
  const bool keepFloat = ext == ".exr" || ext == ".tif" || ext == ".tiff";
  // Temporary name keeps the extension so OpenImageIO picks the right format.
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string tmp = dir + ".ddg-tmp-" + std::to_string(::getpid()) + "-" +
    path.substr(slash == std::string::npos ? 0 : slash + 1);
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
  {
    throw Error("cannot write image '" + path + "': no writer for its extension");
  }
  OIIO::ImageSpec spec(image.width, image.height, image.channels,
    keepFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  spec.attribute("oiio:UnassociatedAlpha", 1); // write alpha as given, never un-premultiply
  if (!out->open(tmp, spec))
  {
    throw Error("cannot write image '" + path + "': " + out->geterror());
  }
  bool ok;
  if (keepFloat)
  {
    ok = out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
  }
  else
  {
    std::vector<unsigned char> bytes(image.pixels.size());
    for (size_t i = 0; i < bytes.size(); ++i)
    {
      const float v = std::clamp(image.pixels[i], 0.0f, 1.0f);
      bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
    }
    ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  ok = out->close() && ok;
  if (!ok)
  {
    std::remove(tmp.c_str());
    throw Error("cannot write image '" + path + "': " + out->geterror());
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw Error("cannot write image '" + path + "': cannot move it into place");
  }
}

void writeAnimation(const std::vector<Image>& frames, const std::string& path, double fps)
{
  if (frames.empty())
    throw Error("cannot write animation '" + path + "': no frames");
  if (!(fps > 0) || fps > 100)
    throw Error("cannot write animation '" + path + "': frames per second must be in (0, 100]");
  for (const auto& f : frames)
    if (f.width != frames[0].width || f.height != frames[0].height || f.channels != 3)
      throw Error("cannot write animation '" + path + "': frames must be RGB of one size");
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string tmp = dir + ".ddg-tmp-" + std::to_string(::getpid()) + "-" +
    path.substr(slash == std::string::npos ? 0 : slash + 1);
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->supports("multiimage") || !out->supports("appendsubimage"))
    throw Error(
      "cannot write animation '" + path + "': its format holds no frame sequence (use .gif)");
  OIIO::ImageSpec spec(frames[0].width, frames[0].height, 3, OIIO::TypeDesc::UINT8);
  spec.attribute("FramesPerSecond", OIIO::TypeRational,
    std::vector<int>{ static_cast<int>(std::lround(fps * 100)), 100 }.data());
  spec.attribute("oiio:LoopCount", 0);
  std::vector<OIIO::ImageSpec> specs(frames.size(), spec);
  bool ok = out->open(tmp, static_cast<int>(specs.size()), specs.data());
  for (size_t i = 0; ok && i < frames.size(); ++i)
  {
    if (i > 0)
      ok = out->open(tmp, spec, OIIO::ImageOutput::AppendSubimage);
    std::vector<unsigned char> bytes(frames[i].pixels.size());
    for (size_t p = 0; p < bytes.size(); ++p)
      bytes[p] = static_cast<unsigned char>(
        std::lround(std::clamp(frames[i].pixels[p], 0.0f, 1.0f) * 255.0f));
    ok = ok && out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  const std::string reason = out->geterror();
  ok = out->close() && ok;
  if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw Error(
      "cannot write animation '" + path + "': " + (reason.empty() ? "write failed" : reason));
  }
}

Image toChannels(const Image& in, int channels)
{
  if (in.channels == channels)
  {
    return in;
  }
  Image out(in.width, in.height, channels);
  const size_t n = static_cast<size_t>(in.width) * in.height;
  for (size_t i = 0; i < n; ++i)
  {
    for (int c = 0; c < channels; ++c)
    {
      float v;
      if (c < 3)
      {
        v = in.channels >= 3 ? in.pixels[i * in.channels + c] : in.pixels[i * in.channels];
      }
      else
      {
        v = in.channels == 4 || in.channels == 2 ? in.pixels[i * in.channels + in.channels - 1]
                                                 : 1.0f;
      }
      out.pixels[i * channels + c] = v;
    }
  }
  return out;
}

Image inColour(Image image)
{
  if (image.channels == 1 || image.channels == 2)
  {
    return toChannels(image, image.channels + 2);
  }
  return image;
}

namespace
{
// One axis of OpenImageIO's separable resize (ImageBufAlgo::resize, OpenImageIO 2.4): for each
// output index, the source index under each tap, clamped to the edges, and the filter's weights,
// normalised to sum 1 (all zero when they sum to 0).
struct AxisTaps
{
  int taps = 0;
  std::vector<int> source;    // taps per output index
  std::vector<float> weights; // taps per output index
};

AxisTaps axisTaps(int dst, int src, const OIIO::Filter2D& filter, bool xAxis)
{
  const float ratio = float(dst) / float(src);
  // the filter's width for both axes' radii, as OpenImageIO 2.4 has it (a taller filter's extra
  // taps where its width ends change the weights)
  const float radius = filter.width() / 2.0f;
  const int rad = static_cast<int>(std::ceil(radius / ratio));
  AxisTaps a;
  a.taps = 2 * rad + 1;
  a.source.resize(static_cast<size_t>(dst) * a.taps);
  a.weights.resize(static_cast<size_t>(dst) * a.taps);
  for (int d = 0; d < dst; ++d)
  {
    const float at = (float(d) + 0.5f) * (1.0f / float(dst)) * float(src);
    const int index = static_cast<int>(std::floor(at));
    const float frac = at - float(index);
    float* w = a.weights.data() + static_cast<size_t>(d) * a.taps;
    float total = 0.0f;
    for (int i = 0; i < a.taps; ++i)
    {
      const float t = ratio * (float(i - rad) - (frac - 0.5f));
      w[i] = xAxis ? filter.xfilt(t) : filter.yfilt(t);
      total += w[i];
    }
    int* source = a.source.data() + static_cast<size_t>(d) * a.taps;
    for (int i = 0; i < a.taps; ++i)
    {
      w[i] = total != 0.0f ? w[i] / total : 0.0f;
      source[i] = std::clamp(index - rad + i, 0, src - 1);
    }
  }
  return a;
}
} // namespace

Image resizeImage(const Image& image, int width, int height)
{
  if (image.empty() || width < 1 || height < 1)
  {
    throw Error("cannot resize an empty image or to an empty size");
  }
  // OpenImageIO's default filter for its resize (lanczos3 when shrinking, blackman-harris when
  // enlarging on either axis, widened by the enlargement), applied as OpenImageIO applies it but
  // one axis at a time: the same weights, ~10x cheaper than its two-dimensional taps through
  // pixel iterators (a 150-pixel square to 128: 0.8 against 9 ms on one thread), equal to float
  // rounding (Core.Image.ResizeIsOpenImageIOsResize)
  const float wratio = float(width) / float(image.width),
              hratio = float(height) / float(image.height);
  const char* name = wratio > 1.0f || hratio > 1.0f ? "blackman-harris" : "lanczos3";
  float baseWidth = 0.0f;
  for (int i = 0, n = OIIO::Filter2D::num_filters(); i < n; ++i)
  {
    OIIO::FilterDesc fd;
    OIIO::Filter2D::get_filterdesc(i, &fd);
    if (std::string(fd.name) == name)
      baseWidth = fd.width;
  }
  std::unique_ptr<OIIO::Filter2D, void (*)(OIIO::Filter2D*)> filter(baseWidth > 0.0f
      ? OIIO::Filter2D::create(
          name, baseWidth * std::max(1.0f, wratio), baseWidth * std::max(1.0f, hratio))
      : nullptr,
    OIIO::Filter2D::destroy);
  if (!filter || !filter->separable())
    throw Error(std::string("cannot resize the image: OpenImageIO has no separable ") + name);
  const AxisTaps xs = axisTaps(width, image.width, *filter, true);
  const AxisTaps ys = axisTaps(height, image.height, *filter, false);
  const int channels = image.channels, sw = image.width, sh = image.height;
  // rows first: every source row at the output's width
  std::vector<float> rows(static_cast<size_t>(sh) * width * channels, 0.0f);
  for (int y = 0; y < sh; ++y)
  {
    const float* in = image.pixels.data() + static_cast<size_t>(y) * sw * channels;
    float* out = rows.data() + static_cast<size_t>(y) * width * channels;
    for (int x = 0; x < width; ++x)
    {
      const float* w = xs.weights.data() + static_cast<size_t>(x) * xs.taps;
      const int* sx = xs.source.data() + static_cast<size_t>(x) * xs.taps;
      float* o = out + static_cast<size_t>(x) * channels;
      for (int i = 0; i < xs.taps; ++i)
      {
        if (w[i] == 0.0f)
          continue;
        const float* p = in + static_cast<size_t>(sx[i]) * channels;
        for (int c = 0; c < channels; ++c)
          o[c] += w[i] * p[c];
      }
    }
  }
  Image result(width, height, channels);
  const size_t rowSize = static_cast<size_t>(width) * channels;
  for (int y = 0; y < height; ++y)
  {
    const float* w = ys.weights.data() + static_cast<size_t>(y) * ys.taps;
    const int* sy = ys.source.data() + static_cast<size_t>(y) * ys.taps;
    float* out = result.pixels.data() + static_cast<size_t>(y) * rowSize;
    for (int j = 0; j < ys.taps; ++j)
    {
      if (w[j] == 0.0f)
        continue;
      const float* in = rows.data() + static_cast<size_t>(sy[j]) * rowSize;
      for (size_t k = 0; k < rowSize; ++k)
        out[k] += w[j] * in[k];
    }
  }
  return result;
}

namespace
{
// The image halved by 2 x 2 box averages (an odd last row or column left out); with
// `alphaWeighted`, the colour channels are averaged weighted by the last channel (straight alpha
// in, straight alpha out: a transparent pixel's colour does not count).
Image halve(const Image& image, bool alphaWeighted)
{
  const int hw = image.width / 2, hh = image.height / 2, channels = image.channels;
  const int alpha = channels - 1;
  Image half(hw, hh, channels);
  for (int y = 0; y < hh; ++y)
    for (int x = 0; x < hw; ++x)
    {
      // each of the block's four pixels weighs its alpha (or 1)
      std::array<float, 4> weight{ 1, 1, 1, 1 };
      float total = 4;
      if (alphaWeighted)
      {
        total = 0;
        for (int k = 0; k < 4; ++k)
          total += weight[k] = image.at(2 * x + k % 2, 2 * y + k / 2, alpha);
      }
      for (int c = 0; c < channels; ++c)
      {
        const bool weighted = alphaWeighted && c != alpha;
        float sum = 0;
        for (int k = 0; k < 4; ++k)
          sum += image.at(2 * x + k % 2, 2 * y + k / 2, c) * (weighted ? weight[k] : 1.0f);
        half.at(x, y, c) =
          weighted ? (total > 0 ? std::min(1.0f, sum / total) : 0.0f) : 0.25f * sum;
      }
    }
  return half;
}
} // namespace

Image shrinkImage(Image image, int width, int height, int halveFrom)
{
  if (image.empty() || width < 1 || height < 1 || halveFrom < 2)
    throw Error("cannot shrink an empty image, to an empty size or halving from under 2x");
  while (image.width >= halveFrom * width && image.height >= halveFrom * height)
    image = halve(image, false);
  return image.width == width && image.height == height ? image : resizeImage(image, width, height);
}

Image shrinkPicture(Image picture, int longest)
{
  Image shrunk;
  if (&shrinkPicture(picture, longest, shrunk) == &picture)
    return picture;
  return shrunk;
}

const Image& shrinkPicture(const Image& picture, int longest, Image& shrunk)
{
  const int k = halvings(picture.width, picture.height, longest);
  if (k == 0)
    return picture;
  const int w = picture.width >> k;
  // halved to exactly w x h (no filtered resize); the first halving reads the picture in place,
  // so a large picture is not copied whole
  const bool alpha = picture.channels == 2 || picture.channels == 4;
  shrunk = halve(picture, alpha);
  while (shrunk.width > w)
    shrunk = halve(shrunk, alpha);
  return shrunk;
}

Image tileImages(const std::vector<Image>& images, int columns, int gap, float background)
{
  if (images.empty() || columns < 1 || gap < 0)
    throw Error("a contact sheet needs images, at least one column and a gap >= 0");
  int cw = 0, ch = 0;
  for (const auto& img : images)
  {
    cw = std::max(cw, img.width);
    ch = std::max(ch, img.height);
  }
  const int cols = std::min(columns, static_cast<int>(images.size()));
  const int rows = (static_cast<int>(images.size()) + cols - 1) / cols;
  Image sheet(cols * (cw + gap) + gap, rows * (ch + gap) + gap, 3, background);
  for (size_t k = 0; k < images.size(); ++k)
  {
    const Image rgb = toChannels(images[k], 3);
    const int x0 = gap + static_cast<int>(k % cols) * (cw + gap);
    const int y0 = gap + static_cast<int>(k / cols) * (ch + gap);
    for (int y = 0; y < rgb.height; ++y)
      for (int x = 0; x < rgb.width; ++x)
        for (int c = 0; c < 3; ++c)
          sheet.at(x0 + x, y0 + y, c) = rgb.at(x, y, c);
  }
  return sheet;
}

Image tileRenders(
  const std::vector<const Image*>& renders, int columns, int rows, int cell, int gap)
{
  if (columns < 1 || rows < 1 || cell < 1 || gap < 0)
    throw Error("a sheet of renders needs columns, rows and a cell size >= 1 and a gap >= 0");
  if (renders.size() > static_cast<size_t>(columns) * static_cast<size_t>(rows))
    throw Error("a sheet of " + std::to_string(columns * rows) + " cells cannot hold " +
      std::to_string(renders.size()) + " renders");
  Image sheet(columns * (cell + gap) + gap, rows * (cell + gap) + gap, 4, 0.0f);
  for (size_t k = 0; k < renders.size(); ++k)
  {
    const Image& r = *renders[k];
    if (r.width != cell || r.height != cell || r.channels != 4)
      throw Error("a render of the sheet is " + std::to_string(r.width) + " x " +
        std::to_string(r.height) + " x " + std::to_string(r.channels) + ", not " +
        std::to_string(cell) + " x " + std::to_string(cell) + " RGBA");
    const int x0 = gap + static_cast<int>(k % columns) * (cell + gap);
    const int y0 = gap + static_cast<int>(k / columns) * (cell + gap);
    for (int y = 0; y < cell; ++y)
      std::copy_n(&r.pixels[static_cast<size_t>(y) * cell * 4], cell * 4, &sheet.at(x0, y0 + y, 0));
  }
  return sheet;
}

} // namespace ddg
