// TestImage.cxx: ParaView's 8-bit compositing formula, PSNR/SSIM identities, colour-histogram
// EMD against the closed-form 1D case, PNG round trip, a sheet of renders (each cell the render
// it holds, the rest transparent), the resize against OpenImageIO's.
#include "Common/Error.h"
#include "Image/ImageMetrics.h"
#include "TransferFunction/ColorSpace.h"

#include "TempDir.h"
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>

using namespace ddg;

TEST(Image, CompositeMatchesParaViewFormula)
{
  Image rgba(1, 1, 4);
  rgba.pixels = { 0.2f, 0.1f, 0.0f, 0.5f };
  const Image out = compositeOverBackground(rgba, { 0.329, 0.349, 0.427 });
  // round(255 C) + round(bg8 (255 - round(255 A)) / 255): A8 = 128 (127.5 rounds up)
  const long bg8[3] = { 84, 89, 109 };
  const double c[3] = { 0.2, 0.1, 0.0 };
  for (int ch = 0; ch < 3; ++ch)
  {
    const long expected = std::lround(255 * c[ch]) + std::lround(bg8[ch] * (255 - 128) / 255.0);
    EXPECT_EQ(std::lround(out.pixels[ch] * 255), expected);
  }
}

TEST(ImageMetrics, IdentitiesAndKnownNoise)
{
  Image a(32, 24, 3);
  for (size_t i = 0; i < a.pixels.size(); ++i)
    a.pixels[i] = static_cast<float>((i * 37 % 101) / 100.0);
  EXPECT_TRUE(std::isinf(psnr(a, a)));
  EXPECT_NEAR(ssim(a, a), 1.0, 1e-12);
  Image b = a;
  for (float& v : b.pixels)
    v = std::min(1.0f, v + 0.01f);
  // almost everywhere +0.01 -> MSE ~ 1e-4 -> ~40 dB
  EXPECT_NEAR(psnr(a, b), 40.0, 0.5);
  EXPECT_LT(ssim(a, b), 1.0);
  Image c(31, 24, 3);
  EXPECT_THROW(psnr(a, c), Error);
}

TEST(ImageMetrics, PsnrLeavesOutTheMaskedPixels)
{
  Image a(4, 2, 3), b(4, 2, 3), ignore(4, 2, 1);
  b.pixels[3 * 5] = 0.5f; // pixel (1, 1) differs
  EXPECT_TRUE(std::isfinite(psnr(a, b, ignore)));
  EXPECT_NEAR(psnr(a, b, ignore), psnr(a, b), 1e-12); // nothing ignored: the plain PSNR
  ignore.pixels[5] = 1.0f;
  EXPECT_TRUE(std::isinf(psnr(a, b, ignore)));
  EXPECT_THROW(psnr(a, b, Image(3, 2, 1)), Error);
}

TEST(ImageIO, PngRoundTripIsExactOn8BitValues)
{
  Image a(7, 5, 4);
  for (size_t i = 0; i < a.pixels.size(); ++i)
    a.pixels[i] = static_cast<float>(i % 256) / 255.0f;
  const std::string path = ddg::testing::tempDir() + "/ddg_roundtrip.png";
  writeImage(a, path);
  const Image b = readImage(path);
  ASSERT_EQ(b.channels, 4);
  for (size_t i = 0; i < a.pixels.size(); ++i)
  {
    EXPECT_NEAR(a.pixels[i], b.pixels[i], 1e-6);
  }
  EXPECT_THROW(readImage(ddg::testing::tempDir() + "/missing.png"), Error);
  EXPECT_THROW(writeImage(a, "/nonexistent-dir/x.png"), Error);
}

// A picture a user has as BMP, GIF or WebP (the panel reads them through Qt) is read from memory
// as a file of it is: pvpython and the filters send a file's bytes
TEST(ImageIO, BmpGifAndWebPAreReadFromMemoryAsFromTheirFiles)
{
  Image a(64, 48, 3);
  const float colours[3][3] = { { 0, 0, 0 }, { 1, 0.5f, 0 }, { 0.2f, 0.4f, 1 } };
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c)
        a.at(x, y, c) = std::round(colours[(x / 16 + y / 16) % 3][c] * 255.0f) / 255.0f;
  for (const char* ext : { ".bmp", ".gif", ".webp" })
  {
    const std::string path = ddg::testing::tempDir() + "/ddg_memory" + ext;
    writeImage(a, path);
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const Image file = readImage(path);
    const Image memory = decodeImage(bytes, "the picture");
    ASSERT_EQ(memory.width, a.width) << ext;
    ASSERT_EQ(memory.height, a.height) << ext;
    ASSERT_EQ(memory.channels, file.channels) << ext;
    EXPECT_EQ(memory.pixels, file.pixels) << ext;
    float worst = 0.0f, sum = 0.0f; // BMP and GIF (three colours) keep the pixels; WebP is lossy
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x)
        for (int c = 0; c < 3; ++c)
        {
          const float d = std::abs(memory.at(x, y, c) - a.at(x, y, c));
          worst = std::max(worst, d);
          sum += d;
        }
    if (std::string(ext) == ".webp")
      EXPECT_LE(sum / (a.width * a.height * 3), 0.05f);
    else
      EXPECT_LE(worst, 1e-6f) << ext;
  }
}

TEST(ImageIO, UnreadablePicturesGiveOneLineNamingTheirOrigin)
{
  auto message = [](auto read)
  {
    try
    {
      read();
    }
    catch (const Error& e)
    {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([&] { decodeImage("hello", "the picture"); }),
    "the picture is not a PNG, JPEG, TIFF, BMP, GIF or WebP file (5 bytes)");
#if defined(__SANITIZE_ADDRESS__)
  // libpng leaves a truncated file by longjmp, past OpenImageIO's error string (31 bytes a read,
  // outside this project): LeakSanitizer would fail the run; the optimised build checks it
  GTEST_SKIP() << "a truncated PNG leaks in OpenImageIO's libpng error path under LeakSanitizer";
#endif
  // a truncated PNG: OpenImageIO's reason is libpng's several lines; the error keeps the first
  Image a(64, 48, 3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> noise(0.0f, 1.0f);
  for (float& v : a.pixels)
    v = noise(rng); // incompressible: the file is larger than its cut
  const std::string path = ddg::testing::tempDir() + "/ddg_truncated.png";
  writeImage(a, path);
  std::ifstream in(path, std::ios::binary);
  const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(whole.size(), 4000u);
  const std::string cut = whole.substr(0, 3000);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << cut;
  const std::string fromFile = message([&] { readImage(path); });
  EXPECT_EQ(fromFile.rfind("cannot read image '" + path + "': ", 0), 0u) << fromFile;
  EXPECT_EQ(fromFile.find('\n'), std::string::npos) << fromFile;
  const std::string fromMemory = message([&] { decodeImage(cut, "the picture"); });
  EXPECT_EQ(fromMemory.rfind("cannot read the picture: ", 0), 0u) << fromMemory;
  EXPECT_EQ(fromMemory.find('\n'), std::string::npos) << fromMemory;
}

TEST(ImageMetrics, ColorHistogramEMD)
{
  // Identical distributions: 0, whatever the layout and size.
  Image a(8, 4, 3, 0.2f), b(2, 16, 3, 0.2f);
  EXPECT_NEAR(colorHistogramEMD(a, b), 0.0, 1e-12);
  // Grey pixels only differ in L (a = b = 0 exactly in vtkMath's Lab), so the exact EMD is the
  // 1D one: sum over L bins of |CDF_A - CDF_B| times the bin width 12.5.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> grey(0.0f, 1.0f);
  Image g1(20, 10, 3), g2(25, 8, 3);
  auto fill = [&](Image& img, float lo, float hi)
  {
    for (size_t p = 0; p < img.pixels.size(); p += 3)
    {
      const float v = lo + (hi - lo) * grey(rng);
      img.pixels[p] = img.pixels[p + 1] = img.pixels[p + 2] = v;
    }
  };
  fill(g1, 0.0f, 0.6f);
  fill(g2, 0.3f, 1.0f);
  auto lBins = [](const Image& img)
  {
    std::vector<double> h(8, 0.0);
    const size_t n = img.pixels.size() / 3;
    for (size_t p = 0; p < n; ++p)
    {
      const double L = rgbToLab({ img.pixels[3 * p], img.pixels[3 * p], img.pixels[3 * p] })[0];
      h[std::clamp(static_cast<int>(L / 12.5), 0, 7)] += 1.0 / n;
    }
    return h;
  };
  const auto h1 = lBins(g1), h2 = lBins(g2);
  double cdf = 0, expected = 0;
  for (int k = 0; k < 8; ++k)
  {
    cdf += h1[k] - h2[k];
    expected += std::abs(cdf) * 12.5;
  }
  EXPECT_NEAR(colorHistogramEMD(g1, g2), expected, 1e-9);
  EXPECT_NEAR(colorHistogramEMD(g2, g1), expected, 1e-9);
  // One colour against another: the distance of their bin centres (> 0).
  Image red(4, 4, 3), blue(4, 4, 3);
  for (size_t p = 0; p < red.pixels.size(); p += 3)
  {
    red.pixels[p] = 1.0f;
    blue.pixels[p + 2] = 1.0f;
  }
  EXPECT_GT(colorHistogramEMD(red, blue), 100.0);
}

TEST(ImageMetrics, SsimGradientMatchesFiniteDifferences)
{
  // ssimWithGradient agrees with ssim() and its gradient with central differences (h = 1e-4,
  // tolerance 1e-5 absolute on a mean over 3 * 12 * 10 windows).
  const int w = 22, h = 20;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> x(static_cast<size_t>(w) * h * 3), y(x.size());
  for (size_t i = 0; i < x.size(); ++i)
  {
    y[i] = u(rng);
    x[i] = std::clamp(y[i] + 0.2f * (u(rng) - 0.5f), 0.0f, 1.0f);
  }
  std::vector<double> grad(x.size());
  const double s = ssimWithGradient(x.data(), y.data(), w, h, grad.data());
  Image ix(w, h, 3), iy(w, h, 3);
  ix.pixels = x;
  iy.pixels = y;
  EXPECT_NEAR(s, ssim(ix, iy), 1e-9);
  for (size_t p : { size_t(0), size_t(100), size_t(3 * (w * 10 + 11) + 1), x.size() - 1 })
  {
    std::vector<float> xp = x, xm = x;
    xp[p] += 1e-3f;
    xm[p] -= 1e-3f;
    std::vector<double> dummy(x.size());
    const double fp = ssimWithGradient(xp.data(), y.data(), w, h, dummy.data());
    const double fm = ssimWithGradient(xm.data(), y.data(), w, h, dummy.data());
    const double numeric = (fp - fm) / ((xp[p] - x[p]) + (x[p] - xm[p]));
    EXPECT_NEAR(grad[p], numeric, 1e-5) << p;
  }
}

// Straight <-> premultiplied alpha: C * A forward, C / A (clamped to 1, 0 where A = 0) back;
// exact on these values; RGB images are refused.
TEST(ImageAlpha, PremultiplyAndBack)
{
  ddg::Image straight(2, 1, 4, 0.0f);
  straight.pixels = { 0.5f, 1.0f, 0.25f, 0.5f, 0.9f, 0.8f, 0.7f, 0.0f };
  const ddg::Image pre = ddg::premultiplyAlpha(straight);
  EXPECT_FLOAT_EQ(pre.pixels[0], 0.25f);
  EXPECT_FLOAT_EQ(pre.pixels[1], 0.5f);
  EXPECT_FLOAT_EQ(pre.pixels[3], 0.5f);
  EXPECT_FLOAT_EQ(pre.pixels[4], 0.0f);
  const ddg::Image back = ddg::unpremultiplyAlpha(pre);
  EXPECT_FLOAT_EQ(back.pixels[0], 0.5f);
  EXPECT_FLOAT_EQ(back.pixels[2], 0.25f);
  EXPECT_FLOAT_EQ(back.pixels[4], 0.0f); // alpha 0: colour 0
  ddg::Image over(1, 1, 4, 0.0f);
  over.pixels = { 0.6f, 0.1f, 0.1f, 0.5f }; // colour > alpha: clamped to 1
  EXPECT_FLOAT_EQ(ddg::unpremultiplyAlpha(over).pixels[0], 1.0f);
  EXPECT_THROW(ddg::premultiplyAlpha(ddg::Image(1, 1, 3, 0.0f)), ddg::Error);
  EXPECT_THROW(ddg::unpremultiplyAlpha(ddg::Image(1, 1, 3, 0.0f)), ddg::Error);
}

TEST(Image, InColourSpreadsGreyAndKeepsColour)
{
  ddg::Image grey(2, 1, 1, 0.0f);
  grey.pixels = { 0.25f, 0.75f };
  const ddg::Image rgb = ddg::inColour(grey);
  ASSERT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.pixels, std::vector<float>({ 0.25f, 0.25f, 0.25f, 0.75f, 0.75f, 0.75f }));
  ddg::Image greyAlpha(1, 1, 2, 0.0f);
  greyAlpha.pixels = { 0.5f, 0.2f };
  const ddg::Image rgba = ddg::inColour(greyAlpha);
  ASSERT_EQ(rgba.channels, 4);
  EXPECT_EQ(rgba.pixels, std::vector<float>({ 0.5f, 0.5f, 0.5f, 0.2f }));
  for (int channels : { 3, 4 })
  {
    ddg::Image colour(1, 1, channels, 0.0f);
    for (int c = 0; c < channels; ++c)
      colour.pixels[c] = 0.1f * (c + 1);
    const ddg::Image same = ddg::inColour(colour);
    EXPECT_EQ(same.channels, channels);
    EXPECT_EQ(same.pixels, colour.pixels);
  }
}

TEST(ImageSheet, RendersTiledRowByRowOverTransparentGaps)
{
  std::vector<ddg::Image> renders;
  for (int k = 0; k < 3; ++k)
  {
    ddg::Image r(4, 4, 4, 0.0f);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 4; ++c)
          r.at(x, y, c) = 0.01f * (k * 64 + y * 16 + x * 4 + c + 1);
    renders.push_back(r);
  }
  const std::vector<const ddg::Image*> cells{ &renders[0], &renders[1], &renders[2] };
  const ddg::Image sheet = ddg::tileRenders(cells, 2, 2, 4, 2);
  ASSERT_EQ(sheet.width, 2 * (4 + 2) + 2);
  ASSERT_EQ(sheet.height, 2 * (4 + 2) + 2);
  ASSERT_EQ(sheet.channels, 4);
  for (int k = 0; k < 3; ++k) // cell k at column k % 2, row k / 2
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 4; ++c)
          EXPECT_EQ(sheet.at(2 + (k % 2) * 6 + x, 2 + (k / 2) * 6 + y, c), renders[k].at(x, y, c));
  EXPECT_EQ(sheet.at(0, 0, 3), 0.0f);                         // the border
  EXPECT_EQ(sheet.at(6, 3, 3), 0.0f);                         // the gap between the first two cells
  EXPECT_EQ(sheet.at(10, 10, 3), 0.0f);                       // the unused fourth cell
  EXPECT_EQ(ddg::tileRenders({}, 3, 1, 4).width, 3 * 6 + 2);  // no renders: an empty sheet
  EXPECT_THROW(ddg::tileRenders(cells, 1, 2, 4), ddg::Error); // three renders, two cells
  EXPECT_THROW(ddg::tileRenders(cells, 2, 2, 5), ddg::Error); // not the cell size
  const ddg::Image rgb(4, 4, 3, 0.0f);
  EXPECT_THROW(ddg::tileRenders({ &rgb }, 1, 1, 4), ddg::Error); // not RGBA
  EXPECT_THROW(ddg::tileRenders({}, 0, 1, 4), ddg::Error);
}

TEST(Image, ShrinkHalvesByBoxAveragesThenResizes)
{
  // a 1024 x 768 picture of random values to 512 x 384: one halving, each pixel the mean of its
  // 2 x 2 block (no filtered resize)
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image big(1024, 768, 3);
  for (float& v : big.pixels)
    v = u(rng);
  const Image half = shrinkImage(big, 512, 384);
  ASSERT_EQ(half.width, 512);
  ASSERT_EQ(half.height, 384);
  for (int y : { 0, 191, 383 })
    for (int x : { 0, 300, 511 })
      for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(half.at(x, y, c),
          0.25f *
            (big.at(2 * x, 2 * y, c) + big.at(2 * x + 1, 2 * y, c) + big.at(2 * x, 2 * y + 1, c) +
              big.at(2 * x + 1, 2 * y + 1, c)));
  // 800 x 600 to 512 x 384: under twice the size, so the filtered resize alone
  Image mid(800, 600, 3);
  for (float& v : mid.pixels)
    v = u(rng);
  EXPECT_EQ(shrinkImage(mid, 512, 384).pixels, resizeImage(mid, 512, 384).pixels);
  // a flat colour stays flat through halvings (an odd column left out) and the last resize
  const Image flat = shrinkImage(Image(1001, 500, 4, 0.25f), 100, 50, 4);
  ASSERT_EQ(flat.width, 100);
  ASSERT_EQ(flat.height, 50);
  for (float v : flat.pixels)
    EXPECT_NEAR(v, 0.25f, 1e-5f);
  EXPECT_THROW(shrinkImage(big, 0, 10), Error);
  EXPECT_THROW(shrinkImage(Image(), 10, 10), Error);
}

TEST(Image, ShrinkPictureHalvesLargePicturesOnly)
{
  // under the limit, or a strip whose shorter side is under 32: unchanged
  const Image small(800, 600, 3, 0.3f);
  EXPECT_EQ(shrinkPicture(small, 2048).pixels, small.pixels);
  const Image strip(5000, 20, 3, 0.3f);
  EXPECT_EQ(shrinkPicture(strip, 2048).width, 5000);
  // 4100 x 3000: halved twice (2050 is still over 2048) to 1025 x 750, each pixel the mean of
  // its 4 x 4 block
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image big(4100, 3000, 3);
  for (float& v : big.pixels)
    v = u(rng);
  const Image quarter = shrinkPicture(big, 2048);
  ASSERT_EQ(quarter.width, 1025);
  ASSERT_EQ(quarter.height, 750);
  for (int y : { 0, 400, 749 })
    for (int x : { 0, 512, 1024 })
    {
      float mean = 0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
          mean += big.at(4 * x + i, 4 * y + j, 1) / 16;
      EXPECT_NEAR(quarter.at(x, y, 1), mean, 1e-5f);
    }
  // straight alpha (RGBA, grey + alpha) is averaged premultiplied: a transparent pixel's colour
  // (here a garbage red, a garbage white) does not bleed into its opaque neighbours' colour,
  // through one halving (64 to 32) or several (256 to 32)
  for (const int side : { 64, 256 })
  {
    Image rgba(side, side, 4, 0.0f), greyAlpha(side, side, 2, 0.0f);
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x)
      {
        const bool opaque = x % 2 == 0;
        rgba.at(x, y, 0) = opaque ? 0.0f : 1.0f;
        rgba.at(x, y, 1) = opaque ? 0.5f : 0.0f;
        rgba.at(x, y, 3) = opaque ? 1.0f : 0.0f;
        greyAlpha.at(x, y, 0) = opaque ? 0.25f : 1.0f;
        greyAlpha.at(x, y, 1) = opaque ? 1.0f : 0.0f;
      }
    const Image smallRGBA = shrinkPicture(rgba, 32), smallGrey = shrinkPicture(greyAlpha, 32);
    ASSERT_EQ(smallRGBA.width, 32);
    ASSERT_EQ(smallGrey.height, 32);
    EXPECT_NEAR(smallRGBA.at(5, 7, 0), 0.0f, 1e-6f) << side;
    EXPECT_NEAR(smallRGBA.at(5, 7, 1), 0.5f, 1e-6f) << side;
    EXPECT_NEAR(smallRGBA.at(5, 7, 3), 0.5f, 1e-6f) << side;
    EXPECT_NEAR(smallGrey.at(9, 3, 0), 0.25f, 1e-6f) << side;
    EXPECT_NEAR(smallGrey.at(9, 3, 1), 0.5f, 1e-6f) << side;
  }
  EXPECT_THROW(shrinkPicture(small, 0), Error);
}

TEST(Image, ShrinkPictureKeepsASmallPictureWithoutACopy)
{
  // into a caller's storage: a picture small enough is the picture itself, a larger one the
  // storage, holding what the by-value form gives
  Image big(300, 200, 3), shrunk;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float& v : big.pixels)
    v = u(rng);
  const Image small(100, 80, 4, 0.3f);
  EXPECT_EQ(&shrinkPicture(small, 100, shrunk), &small);
  EXPECT_TRUE(shrunk.empty());
  const Image& half = shrinkPicture(big, 150, shrunk);
  EXPECT_EQ(&half, &shrunk);
  EXPECT_EQ(half.width, 150);
  EXPECT_EQ(half.pixels, shrinkPicture(big, 150).pixels);
  EXPECT_THROW(shrinkPicture(small, 0, shrunk), Error);
  // by value: a small picture passed with std::move is handed back, its pixels not copied
  Image moved(small);
  const float* data = moved.pixels.data();
  const Image back = shrinkPicture(std::move(moved), 100);
  EXPECT_EQ(back.pixels.data(), data);
  EXPECT_EQ(back.pixels, small.pixels);
}

// readShrunkPicture reads a file strip by strip as shrinkPicture(readImage(file)) gives it, to the
// bit: RGB PNG and JPEG, straight-alpha RGBA and grey + alpha, odd sizes (rows and columns left
// over at every halving), a picture small enough (read whole), a strip under 32 pixels, a tiled
// TIFF (read whole, then shrunk), and a longest side under 1 refused
TEST(Image, ReadShrunkPictureIsTheShrunkReadStripByStrip)
{
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  auto noise = [&](int w, int h, int channels)
  {
    Image image(w, h, channels);
    for (float& v : image.pixels)
      v = u(rng);
    if (channels == 2 || channels == 4) // some transparent, some half-transparent pixels
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          image.at(x, y, channels - 1) = (x + y) % 5 == 0 ? 0.0f : ((x * y) % 3 == 0 ? 0.5f : 1.0f);
    return image;
  };
  struct Case
  {
    int w, h, channels, longest;
    const char* ext;
  };
  for (const Case c : { Case{ 1031, 517, 3, 256, ".png" }, Case{ 1031, 517, 3, 256, ".jpg" },
         Case{ 999, 1201, 4, 200, ".png" }, Case{ 515, 259, 2, 100, ".png" },
         Case{ 300, 200, 3, 512, ".png" }, Case{ 3000, 20, 3, 256, ".png" },
         Case{ 777, 333, 3, 128, ".tif" } })
  {
    const std::string path = ddg::testing::tempDir() + "/ddg_shrunk" + std::to_string(c.w) + "x" +
      std::to_string(c.channels) + c.ext;
    { // 8-bit, as OpenImageIO writes it (grey + alpha too); the TIFF in 64-pixel tiles
      const Image image = noise(c.w, c.h, c.channels);
      OIIO::ImageSpec spec(c.w, c.h, c.channels, OIIO::TypeDesc::UINT8);
      if (std::string(c.ext) == ".tif")
        spec.tile_width = spec.tile_height = 64;
      auto out = OIIO::ImageOutput::create(path);
      ASSERT_TRUE(out && out->open(path, spec)) << path;
      ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data())) << path;
      out->close();
    }
    const Image expected = shrinkPicture(readImage(path), c.longest);
    ImageFileInfo info;
    const Image read = readShrunkPicture(path, c.longest, &info);
    EXPECT_EQ(read.width, expected.width) << path;
    EXPECT_EQ(read.height, expected.height) << path;
    EXPECT_EQ(read.channels, c.channels) << path;
    EXPECT_EQ(info.channels, c.channels) << path;
    EXPECT_TRUE(read.pixels == expected.pixels) << path;
  }
  EXPECT_THROW(readShrunkPicture(ddg::testing::tempDir() + "/missing.png", 256), Error);
  EXPECT_THROW(readShrunkPicture(ddg::testing::tempDir() + "/ddg_shrunk300x3.png", 0), Error);
}

// resizeImage applies OpenImageIO's resize (its default filter, its taps, its clamped edges) one
// axis at a time: equal to ImageBufAlgo::resize to float rounding, shrinking, enlarging, both at
// once, from 1-pixel sources, for 1 to 4 channels (2x2 -> 2x3 and 4x2 -> 4x3: a filter taller
// than wide, whose radius OpenImageIO takes from its width)
TEST(Image, ResizeIsOpenImageIOsResize)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  struct Case
  {
    int sw, sh, dw, dh, channels;
  };
  for (const Case& k :
    { Case{ 150, 150, 128, 128, 4 }, Case{ 512, 384, 64, 64, 3 }, Case{ 64, 64, 192, 192, 3 },
      Case{ 97, 61, 128, 40, 1 }, Case{ 300, 200, 301, 77, 4 }, Case{ 5, 3, 2, 7, 3 },
      Case{ 2, 2, 2, 3, 2 }, Case{ 4, 2, 4, 3, 1 }, Case{ 1, 5, 3, 5, 1 }, Case{ 1, 1, 4, 4, 3 } })
  {
    Image in(k.sw, k.sh, k.channels);
    for (float& v : in.pixels)
      v = u(rng);
    const Image ours = resizeImage(in, k.dw, k.dh);
    OIIO::ImageBuf src(OIIO::ImageSpec(k.sw, k.sh, k.channels, OIIO::TypeDesc::FLOAT),
      const_cast<float*>(in.pixels.data()));
    OIIO::ImageBuf dst(OIIO::ImageSpec(k.dw, k.dh, k.channels, OIIO::TypeDesc::FLOAT));
    ASSERT_TRUE(OIIO::ImageBufAlgo::resize(dst, src));
    std::vector<float> theirs(static_cast<size_t>(k.dw) * k.dh * k.channels);
    dst.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, theirs.data());
    ASSERT_EQ(ours.width, k.dw);
    ASSERT_EQ(ours.height, k.dh);
    ASSERT_EQ(ours.channels, k.channels);
    float worst = 0.0f;
    for (size_t i = 0; i < theirs.size(); ++i)
      worst = std::max(worst, std::abs(ours.pixels[i] - theirs[i]));
    EXPECT_LT(worst, 1e-5f) << k.sw << "x" << k.sh << " -> " << k.dw << "x" << k.dh;
  }
  EXPECT_THROW(resizeImage(Image(4, 4, 3), 0, 4), Error);
}
