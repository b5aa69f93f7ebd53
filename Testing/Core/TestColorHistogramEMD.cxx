// TestColorHistogramEMD.cxx: colorHistogramEMD on real and synthetic image pairs against the
// values recorded before its transport solver changed.
//
// Compared: the EMD of each pair below, now computed with LEMON's network simplex, against the
// value the previous hand-written solver (successive shortest paths with potentials, in double;
// Core/Image/ImageMetrics.cxx at commit 3e9875e) gave for the same pair, recorded to 17 digits.
// Tolerance: kRelTol relative (the old solver agreed with itself to ~1e-12 across the two
// orders of a pair). Pairs: the three shipped ParaView screenshots (Data/Screenshots, 400 x 320
// and 320 x 320) with each other and with two small test targets (Testing/Data, 32 x 24 and
// 40 x 30), both orders; synthetic images of different sizes drawn by a fixed LCG (uniform
// random colours, two-colour halves, a hue ramp).
#include "Image/ImageMetrics.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

using namespace ddg;

namespace
{
constexpr double kRelTol = 1e-6;

const std::string kData = DDG_DATA_DIR;

Image load(const std::string& relative)
{
  return readImage(kData + "/" + relative);
}

// A fixed 64-bit LCG (Knuth's MMIX constants), so the images do not depend on the standard
// library's distributions.
struct Lcg
{
  std::uint64_t state;
  float next()
  {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<float>((state >> 40) & 0xFFFFFF) / static_cast<float>(0x1000000);
  }
};

Image noise(int w, int h, std::uint64_t seed, float lo, float hi)
{
  Lcg g{ seed };
  Image img(w, h, 3);
  for (auto& v : img.pixels)
    v = lo + (hi - lo) * g.next();
  return img;
}

Image halves(int w, int h, std::array<float, 3> left, std::array<float, 3> right)
{
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        img.pixels[(static_cast<size_t>(y) * w + x) * 3 + c] = x < w / 2 ? left[c] : right[c];
  return img;
}

Image ramp(int w, int h)
{
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      const float t = static_cast<float>(x) / (w - 1), s = static_cast<float>(y) / (h - 1);
      float* p = &img.pixels[(static_cast<size_t>(y) * w + x) * 3];
      p[0] = t;
      p[1] = 1 - t;
      p[2] = 0.5f * s;
    }
  return img;
}

std::string printed(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

void expectRecorded(const Image& a, const Image& b, double recorded, const std::string& what)
{
  const double now = colorHistogramEMD(a, b);
  EXPECT_NEAR(now, recorded, kRelTol * recorded) << what << ": now " << printed(now);
}
} // namespace

TEST(ColorHistogramEMD, ShippedScreenshotsAndTargetsMatchTheRecordedValues)
{
  const std::vector<std::string> files{ "Screenshots/engine_block_oblique.png",
    "Screenshots/tooth_cool_warm_side.png", "Screenshots/tooth_dentin_enamel_oblique.png",
    "../Testing/Data/small_target.png", "../Testing/Data/small_target_40x30.png" };
  std::vector<Image> im;
  for (const auto& f : files)
    im.push_back(load(f));
  // recorded[i][j] = EMD(files[i], files[j]) with the previous solver
  const double recorded[5][5] = {
    { 0, 74.680623202668158, 4.726815732977669, 53.392843349826862, 53.466843516395393 },
    { 74.680623202668116, 0, 76.420075358406564, 43.734914379866268, 43.761457116615595 },
    { 4.7268157329751288, 76.420075358403551, 0, 53.086654607204565, 53.143066172969824 },
    { 53.392843349837264, 43.734914379864115, 53.086654607212132, 0, 0.14685510080624137 },
    { 53.466843516398832, 43.761457116613393, 53.143066172975793, 0.14685510080624145, 0 },
  };
  for (size_t i = 0; i < im.size(); ++i)
    for (size_t j = 0; j < im.size(); ++j)
      if (i != j)
        expectRecorded(im[i], im[j], recorded[i][j], files[i] + " vs " + files[j]);
}

TEST(ColorHistogramEMD, SyntheticPairsMatchTheRecordedValues)
{
  const Image n1 = noise(37, 23, 1, 0.0f, 1.0f), n2 = noise(50, 40, 2, 0.0f, 1.0f);
  const Image dark = noise(31, 17, 3, 0.0f, 0.4f), light = noise(19, 29, 4, 0.5f, 1.0f);
  const Image two = halves(24, 16, { 0.9f, 0.1f, 0.1f }, { 0.1f, 0.2f, 0.8f });
  const Image three = halves(10, 30, { 0.2f, 0.7f, 0.2f }, { 0.9f, 0.9f, 0.1f });
  const Image r = ramp(64, 48);
  struct Pair
  {
    const Image *a, *b;
    double recorded;
    const char* what;
  };
  const Pair pairs[] = {
    { &n1, &n2, 6.4004916200183999, "noise 37x23 vs noise 50x40" },
    { &dark, &light, 55.782123738461834, "dark noise 31x17 vs light noise 19x29" },
    { &two, &three, 143.38247682192727, "red|blue 24x16 vs green|yellow 10x30" },
    { &r, &n1, 43.556247729842539, "hue ramp 64x48 vs noise 37x23" },
    { &r, &two, 104.30238887332636, "hue ramp 64x48 vs red|blue 24x16" },
    { &light, &r, 55.700178893655433, "light noise 19x29 vs hue ramp 64x48" },
  };
  for (const auto& p : pairs)
    expectRecorded(*p.a, *p.b, p.recorded, p.what);
}
