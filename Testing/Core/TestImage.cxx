// TestImage.cxx: ParaView's 8-bit compositing formula, PSNR/SSIM identities, PNG round trip.
#include "Image/ImageMetrics.h"

#include <gtest/gtest.h>

#include <cmath>

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

TEST(ImageIO, PngRoundTripIsExactOn8BitValues)
{
  Image a(7, 5, 4);
  for (size_t i = 0; i < a.pixels.size(); ++i)
    a.pixels[i] = static_cast<float>(i % 256) / 255.0f;
  const std::string path = ::testing::TempDir() + "/ddg_roundtrip.png";
  writeImage(a, path);
  const Image b = readImage(path);
  ASSERT_EQ(b.channels, 4);
  for (size_t i = 0; i < a.pixels.size(); ++i)
  {
    EXPECT_NEAR(a.pixels[i], b.pixels[i], 1e-6);
  }
  EXPECT_THROW(readImage(::testing::TempDir() + "/missing.png"), Error);
  EXPECT_THROW(writeImage(a, "/nonexistent-dir/x.png"), Error);
}
