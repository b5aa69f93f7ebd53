// TestGallery.cxx: the outline (PCA plane, thumbnails, neighbours, principal-axis moves, view
// state, latent files), query-image preparation and TF export.
//
// What is compared with what:
//  - PCA: latents built from two planted directions of known spread plus small noise; the
//    recovered axes must match them (|cos| > 0.999) and the explained variances their spreads
//    (1 %). Points must equal project() of each row (1e-4).
//  - Neighbours: against a naive full sort.
//  - Thumbnails: farthest-point sampling must cover the box better (lower dispersion) than the
//    best of 20 random selections of the same size.
//  - Latent files: half-float round trip within 1e-3 relative; truncated/corrupt files refused.
//  - Query images: a disc drawn off-centre in a wide image keeps its size in a square of the
//    shorter side (1.5 pixels); a model-size image passes unchanged; bad images refused with
//    their reason.
//  - Export: the preset re-evaluates to the rasterized primitives within 1/256; the Slicer JSON
//    carries every field the published schema requires, with the TF's nodes.
#include "Common/Error.h"
#include "FileSizeLimit.h"
#include "Gallery/Edit.h"
#include "Gallery/Export.h"
#include "Gallery/Navigation.h"
#include "Gallery/Outline.h"
#include "Gallery/QueryImage.h"
#include "TransferFunction/ColorSpace.h"

#include "TempDir.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>

namespace
{

/// n latents of dim 16: 3 a u + 1 b v + 0.05 noise, a, b standard normal, u, v orthonormal.
ddg::LatentSet plantedLatents(int n, std::vector<double>& u, std::vector<double>& v)
{
  const int d = 16;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  u.assign(d, 0);
  v.assign(d, 0);
  for (int c = 0; c < d; ++c)
  {
    u[c] = normal(rng);
    v[c] = normal(rng);
  }
  auto normalize = [](std::vector<double>& x)
  {
    double s = 0;
    for (double e : x)
      s += e * e;
    for (double& e : x)
      e /= std::sqrt(s);
  };
  normalize(u);
  double dot = 0;
  for (int c = 0; c < d; ++c)
    dot += u[c] * v[c];
  for (int c = 0; c < d; ++c)
    v[c] -= dot * u[c];
  normalize(v);
  ddg::LatentSet set;
  set.dim = d;
  for (int i = 0; i < n; ++i)
  {
    const double a = normal(rng), b = normal(rng);
    for (int c = 0; c < d; ++c)
      set.values.push_back(static_cast<float>(3 * a * u[c] + b * v[c] + 0.05 * normal(rng) + 0.5));
    set.indices.push_back(static_cast<std::uint64_t>(i));
  }
  return set;
}

std::string tempPath(const std::string& name)
{
  return (std::filesystem::path(ddg::testing::tempDir()) / ("ddg_gallery_" + name)).string();
}

} // namespace

TEST(Outline, PcaRecoversPlantedAxes)
{
  std::vector<double> u, v;
  const ddg::DesignOutline outline(plantedLatents(4000, u, v));
  const int d = 16;
  std::vector<float> mean(d, 0.5f), e0 = mean, e1 = mean;
  // the axes through moveAlongAxes from the mean direction
  e0 = outline.moveAlongAxes(mean, { 1.0 });
  e1 = outline.moveAlongAxes(mean, { 0.0, 1.0 });
  double c0 = 0, c1 = 0, n0 = 0, n1 = 0;
  for (int c = 0; c < d; ++c)
  {
    c0 += (e0[c] - mean[c]) * u[c];
    c1 += (e1[c] - mean[c]) * v[c];
    n0 += (e0[c] - mean[c]) * (e0[c] - mean[c]);
    n1 += (e1[c] - mean[c]) * (e1[c] - mean[c]);
  }
  EXPECT_GT(std::abs(c0) / std::sqrt(n0), 0.999);
  EXPECT_GT(std::abs(c1) / std::sqrt(n1), 0.999);
  EXPECT_NEAR(outline.axisStddev(0), 3.0, 0.03 * 3);
  EXPECT_NEAR(outline.axisStddev(1), 1.0, 0.03);
  const double total = 9 + 1 + 16 * 0.0025;
  EXPECT_NEAR(outline.explainedVariance(0), 9 / total, 0.01);
  EXPECT_NEAR(outline.explainedVariance(1), 1 / total, 0.01);
  for (int i = 0; i < outline.count(); i += 397)
  {
    const auto p = outline.project(outline.latents().row(i));
    EXPECT_NEAR(p[0], outline.point(i)[0], 1e-4);
    EXPECT_NEAR(p[1], outline.point(i)[1], 1e-4);
  }
  // one step along axis 0 moves the point by one stddev along x only
  const auto a = outline.project(outline.latents().row(5));
  const float* r5 = outline.latents().row(5);
  const auto moved = outline.moveAlongAxes(std::vector<float>(r5, r5 + d), { 1.0 });
  const auto b = outline.project(moved.data());
  EXPECT_NEAR(std::abs(b[0] - a[0]), outline.axisStddev(0), 1e-3);
  EXPECT_NEAR(b[1], a[1], 1e-3);
  EXPECT_THROW(outline.axisStddev(16), ddg::Error);
  EXPECT_THROW(outline.moveAlongAxes(std::vector<float>(3), { 1.0 }), ddg::Error);
}

TEST(Outline, RefusesTooFewOrBadLatents)
{
  ddg::LatentSet s;
  s.dim = 4;
  s.values = { 1, 2, 3, 4, 5, 6, 7, 8 };
  s.indices = { 0, 1 };
  EXPECT_THROW(ddg::DesignOutline{ s }, ddg::Error);
  s.values.push_back(1);
  s.indices.push_back(2);
  EXPECT_THROW(ddg::DesignOutline{ s }, ddg::Error); // 9 values for 3 latents of 4
  s.values = std::vector<float>(12, 0.f);
  s.values[5] = std::nanf("");
  EXPECT_THROW(ddg::DesignOutline{ s }, ddg::Error);
}

TEST(Outline, NearestMatchesNaiveSort)
{
  std::vector<double> u, v;
  const ddg::DesignOutline outline(plantedLatents(500, u, v));
  const float* q = outline.latents().row(17);
  const auto nn = outline.nearest(q, 7);
  std::vector<std::pair<double, int>> all;
  for (int i = 0; i < outline.count(); ++i)
  {
    double s = 0;
    for (int c = 0; c < 16; ++c)
      s += (outline.latents().row(i)[c] - q[c]) * (outline.latents().row(i)[c] - q[c]);
    all.push_back({ std::sqrt(s), i });
  }
  std::sort(all.begin(), all.end());
  ASSERT_EQ(nn.size(), 7u);
  EXPECT_EQ(nn[0].row, 17);
  for (size_t k = 0; k < nn.size(); ++k)
  {
    EXPECT_EQ(nn[k].row, all[k].second);
    EXPECT_NEAR(nn[k].distance, all[k].first, 1e-5);
  }
  EXPECT_EQ(outline.nearest(q, 100000).size(), 500u);
  EXPECT_TRUE(outline.nearest(q, 0).empty());
}

TEST(Outline, ThumbnailsCoverBetterThanRandom)
{
  std::vector<double> u, v;
  const ddg::DesignOutline outline(plantedLatents(5000, u, v));
  const auto box = outline.bounds();
  const auto rows = ddg::selectThumbnails(outline, box, 64, 1);
  ASSERT_EQ(rows.size(), 64u);
  std::vector<int> sorted = rows;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::unique(sorted.begin(), sorted.end()), sorted.end()) << "rows repeat";
  const double ours = ddg::dispersion(outline, box, rows);
  std::mt19937_64 rng(3);
  double bestRandom = 1e9;
  for (int trial = 0; trial < 20; ++trial)
  {
    std::vector<int> all(outline.count());
    std::iota(all.begin(), all.end(), 0);
    std::shuffle(all.begin(), all.end(), rng);
    all.resize(64);
    bestRandom = std::min(bestRandom, ddg::dispersion(outline, box, all));
  }
  EXPECT_LT(ours, 0.75 * bestRandom) << "farthest-point " << ours << ", random " << bestRandom;
  // another seed resamples, same coverage quality
  const auto again = ddg::selectThumbnails(outline, box, 64, 2);
  EXPECT_NE(again, rows);
  EXPECT_LT(ddg::dispersion(outline, box, again), 0.75 * bestRandom);
  // a sub-box: only points inside it
  const ddg::OutlineBox sub{ box.x0, box.y0, 0.5 * (box.x0 + box.x1), 0.5 * (box.y0 + box.y1) };
  for (int r : ddg::selectThumbnails(outline, sub, 16, 1))
    EXPECT_TRUE(sub.contains(outline.point(r)[0], outline.point(r)[1]));
  // K = 0, K larger than the points inside, a box beside the plane, bad input
  EXPECT_TRUE(ddg::selectThumbnails(outline, box, 0, 1).empty());
  const ddg::OutlineBox beside{ box.x1 + 1, box.y1 + 1, box.x1 + 2, box.y1 + 2 };
  EXPECT_TRUE(ddg::selectThumbnails(outline, beside, 8, 1).empty());
  EXPECT_THROW(ddg::selectThumbnails(outline, box, -1, 1), ddg::Error);
  EXPECT_THROW(ddg::selectThumbnails(outline, ddg::OutlineBox{ 1, 1, 0, 2 }, 4, 1), ddg::Error);
}

TEST(Outline, ViewStateNavigatesAndRoundTrips)
{
  ddg::OutlineViewState s;
  EXPECT_THROW(s.current(), ddg::Error);
  s.boxes = { { -4, -2, 4, 2 } };
  s.drillIn({ -1, -1, 10, 1 }); // clipped to the box shown
  EXPECT_DOUBLE_EQ(s.current().x1, 4);
  EXPECT_EQ(s.boxes.size(), 2u);
  EXPECT_THROW(s.drillIn({ 20, 20, 30, 30 }), ddg::Error);
  s.zoom(2, 0, 0);
  EXPECT_DOUBLE_EQ(s.current().x0, -0.5);
  EXPECT_DOUBLE_EQ(s.current().x1, 2);
  s.pan(1, 0);
  EXPECT_DOUBLE_EQ(s.current().x0, 0.5);
  s.resample();
  const auto back = ddg::OutlineViewState::fromJson(s.toJson());
  EXPECT_EQ(back.boxes.size(), 2u);
  EXPECT_DOUBLE_EQ(back.current().x0, 0.5);
  EXPECT_EQ(back.seed, 2u);
  s.back();
  s.back(); // no-op at the whole outline
  EXPECT_EQ(s.boxes.size(), 1u);
  EXPECT_THROW(ddg::OutlineViewState::fromJson("{\"boxes\": []}"), ddg::Error);
  EXPECT_THROW(ddg::OutlineViewState::fromJson("{\"boxes\": [[0, 0, 1]]}"), ddg::Error);
  EXPECT_THROW(ddg::OutlineViewState::fromJson("{\"boxes\": [[1, 0, 0, 1]]}"), ddg::Error);
  EXPECT_THROW(ddg::OutlineViewState::fromJson("not json"), ddg::Error);
  EXPECT_THROW(s.zoom(0, 0, 0), ddg::Error);
}

TEST(Outline, LatentFileRoundTripAndCorruption)
{
  std::vector<double> u, v;
  auto set = plantedLatents(300, u, v);
  set.seed = 42;
  const auto path = tempPath("latents.bin");
  ddg::writeLatentSet(set, path);
  const auto back = ddg::readLatentSet(path);
  EXPECT_EQ(back.dim, set.dim);
  EXPECT_EQ(back.seed, 42u);
  EXPECT_EQ(back.indices, set.indices);
  for (size_t i = 0; i < set.values.size(); ++i)
    EXPECT_NEAR(back.values[i], set.values[i], 1e-3 * std::max(1.0f, std::abs(set.values[i])));
  // truncated
  const auto size = std::filesystem::file_size(path);
  std::filesystem::resize_file(path, size - 3);
  EXPECT_THROW(ddg::readLatentSet(path), ddg::Error);
  // not a latent set
  {
    std::ofstream(path) << "DDGXSHRD and something else entirely, long enough for a header";
  }
  EXPECT_THROW(ddg::readLatentSet(path), ddg::Error);
  std::filesystem::remove(path);
  EXPECT_THROW(ddg::readLatentSet(path), ddg::Error);
  // a full disk leaves no file behind
  {
    FileSizeLimit limit(1000);
    EXPECT_THROW(ddg::writeLatentSet(set, path), ddg::Error);
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(QueryImage, FramesContentAnywhere)
{
  // a white disc of radius 20 at (260, 40) in a 300 x 100 black image
  ddg::Image im(300, 100, 3, 0.0f);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 300; ++x)
      if ((x - 260) * (x - 260) + (y - 40) * (y - 40) <= 400)
        for (int c = 0; c < 3; ++c)
          im.at(x, y, c) = 1.0f;
  const auto out = ddg::prepareQueryImage(im, 64);
  ASSERT_EQ(out.width, 64);
  ASSERT_EQ(out.channels, 3);
  // the 100 x 100 square on the disc, moved inside the image: columns 200..299; the disc keeps
  // its size (radius 20 of 100 -> 12.8 of 64) at (60, 40) of 100 -> (38.4, 25.6) of 64
  int x0 = 64, x1 = -1, y0 = 64, y1 = -1;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      if (out.at(x, y, 0) > 0.5f)
      {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  EXPECT_NEAR(x0, 25.6, 1.5);
  EXPECT_NEAR(x1, 51.2, 1.5);
  EXPECT_NEAR(y0, 12.8, 1.5);
  EXPECT_NEAR(y1, 38.4, 1.5);
  // a square image of the model's size (8-bit values) is used as it is
  ddg::Image same(64, 64, 3, 0.0f);
  for (int y = 20; y < 40; ++y)
    for (int x = 10; x < 30; ++x)
      same.at(x, y, 1) = 200.0f / 255.0f;
  EXPECT_EQ(ddg::prepareQueryImage(same, 64).pixels, same.pixels);
  // content larger than the shorter side: the square grows and pads with the background
  ddg::Image wide(200, 20, 3, 1.0f);
  for (int x = 10; x < 190; ++x)
    wide.at(x, 10, 0) = 0.0f;
  const auto padded = ddg::prepareQueryImage(wide, 64);
  EXPECT_FLOAT_EQ(padded.at(32, 2, 1), 1.0f); // white padding above
  // white background, gray, gray + alpha and RGBA are accepted
  ddg::Image gray(50, 50, 1, 1.0f);
  gray.at(25, 25, 0) = 0.0f;
  EXPECT_NO_THROW(ddg::prepareQueryImage(gray, 32));
  ddg::Image ga(50, 50, 2, 1.0f);
  EXPECT_NO_THROW({
    ga.at(10, 10, 1) = 0.0f; // one transparent pixel over black differs from white
    ddg::prepareQueryImage(ga, 32);
  });
}

TEST(QueryImage, OtherBackgroundsAndTheirOverlaysBecomeBlackOrWhite)
{
  // an amber disc (radius 30 at (200, 100)) and a second part a third of its area, over a
  // background; orientation axes drawn as a small red L in the lower left corner
  auto picture = [](std::array<float, 3> background, bool axes)
  {
    ddg::Image im(320, 240, 3, 0.0f);
    for (int y = 0; y < 240; ++y)
      for (int x = 0; x < 320; ++x)
      {
        std::array<float, 3> c = background;
        if ((x - 200) * (x - 200) + (y - 100) * (y - 100) <= 900)
          c = { 0.9f, 0.55f, 0.2f };
        else if ((x - 110) * (x - 110) + (y - 150) * (y - 150) <= 300)
          c = { 0.3f, 0.6f, 0.9f };
        else if (axes &&
          ((x >= 15 && x < 18 && y >= 205 && y < 225) ||
            (y >= 222 && y < 225 && x >= 15 && x < 35)))
          c = { 0.9f, 0.1f, 0.1f };
        for (int k = 0; k < 3; ++k)
          im.at(x, y, k) = c[k];
      }
    return im;
  };
  // ParaView's palette grey-blue with the axes: as the same picture over black without them
  // (the framing too: the axes no longer pull the square towards the corner)
  const auto palette = ddg::prepareQueryImage(picture({ 0.32f, 0.34f, 0.43f }, true), 64);
  const auto black = ddg::prepareQueryImage(picture({ 0, 0, 0 }, false), 64);
  EXPECT_EQ(palette.pixels, black.pixels);
  // a light background becomes white
  const auto light = ddg::prepareQueryImage(picture({ 0.85f, 0.85f, 0.8f }, true), 64);
  EXPECT_EQ(light.pixels, ddg::prepareQueryImage(picture({ 1, 1, 1 }, false), 64).pixels);
  // the second part (over a fifth of the disc's area) is kept, not taken for an overlay
  int blue = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      blue += palette.at(x, y, 2) > 0.8f && palette.at(x, y, 0) < 0.4f;
  EXPECT_GT(blue, 20);
  // black and white backgrounds are kept with whatever is drawn over them
  const auto blackAxes = ddg::prepareQueryImage(picture({ 0, 0, 0 }, true), 64);
  EXPECT_NE(blackAxes.pixels, black.pixels);
  // content wider than the picture is high, over the palette: the square is padded with black
  ddg::Image wide(200, 20, 3, 0.0f);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 200; ++x)
      for (int c = 0; c < 3; ++c)
        wide.at(x, y, c) = std::array<float, 3>{ 0.32f, 0.34f, 0.43f }[c];
  for (int y = 8; y < 12; ++y)
    for (int x = 10; x < 190; ++x)
      wide.at(x, y, 0) = 0.9f;
  const auto padded = ddg::prepareQueryImage(wide, 64);
  EXPECT_FLOAT_EQ(padded.at(32, 2, 2), 0.0f);
  EXPECT_FLOAT_EQ(padded.at(32, 61, 2), 0.0f);
  // a vertical gradient (ParaView's default pair) is kept as it is: no band of the border's
  // median colour painted black, the disc kept
  ddg::Image gradient = picture({ 0, 0, 0 }, false);
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x)
      if (gradient.at(x, y, 0) == 0.0f && gradient.at(x, y, 1) == 0.0f)
      {
        const float t = y / 239.0f; // 0 at the top
        const std::array<float, 3> top{ 0.0f, 0.0f, 0.16f }, bottom{ 0.32f, 0.34f, 0.43f };
        for (int c = 0; c < 3; ++c)
          gradient.at(x, y, c) = (1 - t) * top[c] + t * bottom[c];
      }
  const auto keptGradient = ddg::prepareQueryImage(gradient, 64);
  int band = 0, disc = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
    {
      band += keptGradient.at(x, y, 2) == 0.0f;
      disc += keptGradient.at(x, y, 0) > 0.8f;
    }
  EXPECT_EQ(band, 0);
  EXPECT_GT(disc, 60); // smaller than over black (181): the gradient counts as content, as before
  // a volume as dark as black over the palette: the picture as it was, not an empty square
  const auto dark = ddg::prepareQueryImage(
    [&]
    {
      ddg::Image im(100, 80, 3, 0.0f);
      for (int y = 0; y < 80; ++y)
        for (int x = 0; x < 100; ++x)
          for (int c = 0; c < 3; ++c)
            im.at(x, y, c) = (x - 50) * (x - 50) + (y - 40) * (y - 40) <= 400
              ? 0.01f
              : std::array<float, 3>{ 0.32f, 0.34f, 0.43f }[c];
      return im;
    }(),
    32);
  EXPECT_GT(dark.at(1, 1, 2), 0.3f);
}

TEST(QueryImage, FramedPSNRIgnoresFramingAndBackground)
{
  // an orange disc with a red core (radius r at (cx, cy)) as premultiplied RGBA (a render) or
  // over `bg` (a picture)
  auto disc = [](int w, int h, double cx, double cy, double r, bool rgba, float bg)
  {
    ddg::Image im(w, h, rgba ? 4 : 3, rgba ? 0.0f : bg);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
      {
        const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy) / r;
        if (d > 1)
          continue;
        const float colour[3] = { 1.0f, d < 0.5 ? 0.1f : 0.6f, 0.1f };
        for (int c = 0; c < 3; ++c)
          im.at(x, y, c) = colour[c];
        if (rgba)
          im.at(x, y, 3) = 1.0f;
      }
    return im;
  };
  // the same disc, smaller and off-centre in a wide white picture, centred in a square render
  const ddg::Image picture = disc(400, 200, 300, 80, 40, false, 1.0f);
  const ddg::Image same = disc(192, 192, 96, 96, 70, true, 0);
  const double p = ddg::framedPSNR(picture, same);
  EXPECT_GT(p, 25);
  // another look: a disc of one colour scores lower; a render showing nothing scores lower still
  ddg::Image other = same;
  for (int i = 0; i < other.width * other.height; ++i)
    if (other.pixels[static_cast<size_t>(i) * 4 + 3] > 0)
      other.pixels[static_cast<size_t>(i) * 4 + 1] = 0.6f;
  const double q = ddg::framedPSNR(picture, other);
  const double none = ddg::framedPSNR(picture, ddg::Image(192, 192, 4, 0.0f));
  EXPECT_LT(q, p - 5);
  EXPECT_LT(none, q);
  EXPECT_THROW(ddg::framedPSNR(picture, picture), ddg::Error); // the render must be RGBA
  // orientation axes in the corner of a screenshot (a small red L over ParaView's palette
  // grey-blue) neither widen the picture's frame nor count: as the picture without them
  auto palette = [&disc](bool axes)
  {
    ddg::Image im = disc(400, 300, 260, 120, 60, false, 0);
    for (int y = 0; y < 300; ++y)
      for (int x = 0; x < 400; ++x)
      {
        const bool background = im.at(x, y, 0) == 0 && im.at(x, y, 1) == 0;
        const bool axis =
          (x >= 15 && x < 18 && y >= 260 && y < 285) || (y >= 282 && y < 285 && x >= 15 && x < 40);
        const std::array<float, 3> c = axes && axis ? std::array<float, 3>{ 0.9f, 0.1f, 0.1f }
                                                    : std::array<float, 3>{ 0.32f, 0.34f, 0.43f };
        if (background || (axes && axis))
          for (int k = 0; k < 3; ++k)
            im.at(x, y, k) = c[k];
      }
    return im;
  };
  const double withAxes = ddg::framedPSNR(palette(true), same);
  EXPECT_DOUBLE_EQ(withAxes, ddg::framedPSNR(palette(false), same));
  EXPECT_GT(withAxes, 25);
  // a design with a small part of its own (a disc a sixteenth of the large one's area, far from
  // it): left out of the picture and of the render alike, so its own render still matches it
  auto twoParts = [&disc](bool rgba)
  {
    ddg::Image im = disc(400, 300, 260, 120, 60, rgba, 0);
    const ddg::Image small = disc(400, 300, 60, 240, 15, rgba, 0);
    for (size_t i = 0; i < im.pixels.size(); ++i)
      im.pixels[i] = std::max(im.pixels[i], small.pixels[i]);
    if (!rgba)
      for (int y = 0; y < 300; ++y)
        for (int x = 0; x < 400; ++x)
          if (im.at(x, y, 0) == 0)
            for (int k = 0; k < 3; ++k)
              im.at(x, y, k) = std::array<float, 3>{ 0.32f, 0.34f, 0.43f }[k];
    return im;
  };
  EXPECT_GT(ddg::framedPSNR(twoParts(false), twoParts(true)), 40);
}

TEST(QueryImage, RefusesUnusableImages)
{
  auto message = [](const ddg::Image& im)
  {
    try
    {
      ddg::prepareQueryImage(im, 64);
    }
    catch (const ddg::Error& e)
    {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(ddg::Image(4, 100, 3, 0.5f)).find("too small"), std::string::npos);
  EXPECT_NE(message(ddg::Image(100, 100, 3, 0.5f)).find("background"), std::string::npos);
  EXPECT_NE(message(ddg::Image(100, 100, 4, 0.0f)).find("transparent"), std::string::npos);
  EXPECT_NE(message(ddg::Image(20000, 8, 1, 0.0f)).find("too large"), std::string::npos);
  EXPECT_NE(message(ddg::Image()).find("too small"), std::string::npos);
  ddg::Image nan(20, 20, 3, 0.0f);
  nan.pixels[7] = std::nanf("");
  EXPECT_NE(message(nan).find("non-finite"), std::string::npos);
}

TEST(Export, PresetReproducesTheDesign)
{
  std::vector<ddg::GaussianPrimitive> prims(2);
  prims[0].mean = { 80, 0 };
  prims[0].stddev = { 10, 1 };
  prims[0].rgb = { 0.9, 0.3, 0.1 };
  prims[0].opacity = 0.6;
  prims[1].mean = { 200, 0 };
  prims[1].stddev = { 6, 1 };
  prims[1].rgb = { 0.2, 0.4, 1.0 };
  prims[1].opacity = 0.3;
  const auto tf = ddg::primitivesToTransferFunction(prims, 1, { 0, 255 }, { 0, 1 });
  ASSERT_FALSE(tf.is2D);
  const auto table = ddg::rasterize1D(prims, 0, 255, 1024);
  for (int i = 0; i < 1024; i += 7)
  {
    const double x = 255.0 * i / 1023;
    EXPECT_NEAR(tf.tf1D.evaluateOpacity(x), table.rgba[4 * i + 3], 1.0 / 256);
    if (table.rgba[4 * i + 3] > 0.01)
      EXPECT_NEAR(tf.tf1D.evaluateColor(x)[0], table.rgba[4 * i], 1.0 / 256);
  }
  const auto twoD = ddg::primitivesToTransferFunction(prims, 2, { 0, 255 }, { 0, 50 });
  EXPECT_TRUE(twoD.is2D);
  EXPECT_EQ(twoD.tf2D.primitives.size(), 2u);
  prims[0].stddev[0] = -1;
  EXPECT_THROW(ddg::primitivesToTransferFunction(prims, 1, { 0, 255 }, { 0, 1 }), ddg::Error);
  EXPECT_THROW(ddg::primitivesToTransferFunction({}, 3, { 0, 255 }, { 0, 1 }), ddg::Error);
  EXPECT_THROW(ddg::primitivesToTransferFunction({}, 1, { 5, 5 }, { 0, 1 }), ddg::Error);
}

TEST(Export, SlicerJsonHasTheSchemaFields)
{
  ddg::TransferFunction1D tf;
  tf.color = { { 0, 1, 0, 0 }, { 255, 0, 0, 1 } };
  tf.opacity = { { 0, 0 }, { 100, 0.5 }, { 255, 1 } };
  const auto j = nlohmann::json::parse(ddg::slicerVolumePropertyJson(tf, { 0, 255 }, 2.5));
  ASSERT_TRUE(j.at("@schema").is_string());
  EXPECT_NE(
    j["@schema"].get<std::string>().find("volume-property-schema-v1.0.0.json"), std::string::npos);
  const auto& p = j.at("volumeProperties").at(0);
  EXPECT_EQ(p.at("effectiveRange"), nlohmann::json({ 0.0, 255.0 }));
  EXPECT_EQ(p.at("interpolationType"), "linear");
  const auto& c = p.at("components").at(0);
  EXPECT_DOUBLE_EQ(c.at("scalarOpacityUnitDistance").get<double>(), 2.5);
  const auto& op = c.at("scalarOpacity").at("points");
  ASSERT_EQ(op.size(), 3u);
  for (const char* key : { "x", "y", "midpoint", "sharpness" })
    EXPECT_TRUE(op[1].contains(key)) << key;
  EXPECT_DOUBLE_EQ(op[1]["y"].get<double>(), 0.5);
  const auto& col = c.at("rgbTransferFunction").at("points");
  ASSERT_EQ(col.size(), 2u);
  EXPECT_EQ(col[1].at("color"), nlohmann::json({ 0.0, 0.0, 1.0 }));
  for (const char* key : { "ambient", "diffuse", "specular", "specularPower" })
    EXPECT_TRUE(c.at("lighting").contains(key)) << key;
  EXPECT_THROW(ddg::slicerVolumePropertyJson(tf, { 1, 1 }, 1), ddg::Error);
  EXPECT_THROW(ddg::slicerVolumePropertyJson(tf, { 0, 1 }, 0), ddg::Error);
  ddg::TransferFunctionFile twoD;
  twoD.is2D = true;
  EXPECT_THROW(
    ddg::exportTransferFunction(twoD, tempPath("x.vp.json"), "slicer", { 0, 1 }, 1), ddg::Error);
  ddg::TransferFunctionFile oneD;
  oneD.tf1D = tf;
  EXPECT_THROW(
    ddg::exportTransferFunction(oneD, tempPath("x.json"), "vtk", { 0, 1 }, 1), ddg::Error);
}

TEST(Navigation, GridsReproduceTheirAnchorsAndStayInTheTriangle)
{
  const ddg::Latent a{ 1, 0, 0 }, b{ 0, 1, 0 }, c{ 0, 0, 1 }, d{ 1, 1, 1 };
  // corners reproduce the anchors exactly
  EXPECT_EQ(ddg::blendLatents({ a, b }, 0, 0), a);
  EXPECT_EQ(ddg::blendLatents({ a, b }, 1, 0.7), b);
  EXPECT_EQ(ddg::blendLatents({ a, b, c }, 0, 1), c);
  EXPECT_EQ(ddg::blendLatents({ a, b, c, d }, 1, 1), d);
  const auto mid = ddg::blendLatents({ a, b, c, d }, 0.5, 0.5);
  EXPECT_FLOAT_EQ(mid[0], 0.5f);
  EXPECT_FLOAT_EQ(mid[2], 0.5f);
  const auto grid = ddg::navigationGrid({ a, b, c, d }, 3, 3);
  ASSERT_EQ(grid.size(), 9u);
  EXPECT_EQ(grid[0].latent, a);
  EXPECT_EQ(grid[2].latent, b);
  EXPECT_EQ(grid[6].latent, c);
  EXPECT_EQ(grid[8].latent, d);
  // triangle: cells beyond u + v = 1 are empty
  const auto tri = ddg::navigationGrid({ a, b, c }, 3, 3);
  EXPECT_TRUE(tri[8].latent.empty());
  EXPECT_FALSE(tri[4].latent.empty()); // u = v = 0.5 is on the edge
  // zoom and pan inside the sub-space
  const ddg::NavigationWindow w = ddg::NavigationWindow{}.zoomed(2, 0.5, 0.5).panned(0.25, 0);
  EXPECT_DOUBLE_EQ(w.u0, 0.5);
  EXPECT_DOUBLE_EQ(w.u1, 1.0);
  const auto zoomed = ddg::navigationGrid({ a, b }, 1, 2, w);
  EXPECT_FLOAT_EQ(zoomed[0].latent[0], 0.5f);
  EXPECT_EQ(zoomed[1].latent, b);
  EXPECT_THROW(ddg::blendLatents({ a }, 0, 0), ddg::Error);
  EXPECT_THROW(ddg::blendLatents({ a, b, c, d, a }, 0, 0), ddg::Error);
  EXPECT_THROW(ddg::blendLatents({ a, ddg::Latent{ 1, 2 } }, 0, 0), ddg::Error);
  EXPECT_THROW(ddg::navigationGrid({ a, b }, 0, 3), ddg::Error);
  EXPECT_THROW(ddg::navigationGrid({ a, b }, 1, 3, { 1, 0, 0, 1 }), ddg::Error);
}

TEST(Navigation, EasedPathsStartAndEndOnTheDesigns)
{
  const ddg::Latent a{ 0, 10 }, b{ 1, 20 };
  for (const char* easing : { "linear", "smoothstep", "cosine" })
  {
    const auto path = ddg::latentPath(a, b, 9, easing);
    ASSERT_EQ(path.size(), 9u);
    EXPECT_EQ(path.front(), a);
    EXPECT_EQ(path.back(), b);
    for (size_t f = 1; f < path.size(); ++f)
      EXPECT_GE(path[f][0], path[f - 1][0]) << easing << " is not monotone";
    EXPECT_NEAR(path[4][0], 0.5, 1e-6) << easing << " is not symmetric";
  }
  // smoothstep starts slower than linear
  EXPECT_LT(ddg::ease(0.1, "smoothstep"), 0.1);
  EXPECT_THROW(ddg::ease(0.5, "bounce"), ddg::Error);
  EXPECT_THROW(ddg::latentPath(a, b, 1), ddg::Error);
}

namespace
{
/// 40 x 20 premultiplied RGBA: left half red at alpha 0.8, right half blue at alpha 0.4,
/// a transparent top row.
ddg::Image twoFeatures()
{
  ddg::Image im(40, 20, 4, 0.0f);
  for (int y = 1; y < 20; ++y)
    for (int x = 0; x < 40; ++x)
    {
      const bool left = x < 20;
      const float a = left ? 0.8f : 0.4f;
      im.at(x, y, 0) = left ? 0.9f * a : 0.1f * a;
      im.at(x, y, 1) = 0.1f * a;
      im.at(x, y, 2) = left ? 0.1f * a : 0.9f * a;
      im.at(x, y, 3) = a;
    }
  return im;
}
} // namespace

TEST(Edit, ClustersSeparateFeaturesAndEditsTouchOnlyOne)
{
  const auto im = twoFeatures();
  const auto cl = ddg::colorClusters(im, 4);
  ASSERT_EQ(cl.count(), 2);   // two distinct colours, not four
  EXPECT_EQ(cl.at(5, 0), -1); // transparent
  const int red = cl.at(5, 10), blue = cl.at(30, 10);
  EXPECT_NE(red, blue);
  EXPECT_NEAR(cl.share[0], 0.5, 1e-9);
  EXPECT_NEAR(cl.rgb[red][0], 0.9, 1e-6); // mean straight colour of each cluster
  EXPECT_NEAR(cl.rgb[blue][2], 0.9, 1e-6);
  EXPECT_NEAR(cl.rgb[blue][1], 0.1, 1e-6);
  // rotate the red feature's hue by +120 degrees: red -> green; blue untouched
  const auto green = ddg::recolour(im, cl, { red, {} }, 120);
  EXPECT_NEAR(green.at(5, 10, 1) / green.at(5, 10, 3), 0.9, 0.02);
  EXPECT_NEAR(green.at(5, 10, 0) / green.at(5, 10, 3), 0.1, 0.02);
  EXPECT_FLOAT_EQ(green.at(5, 10, 3), 0.8f);
  EXPECT_FLOAT_EQ(green.at(30, 10, 2), im.at(30, 10, 2));
  // lightness up brightens it (L* +20 asked; a saturated red leaves the sRGB gamut on the way and
  // is clipped, so at least +8 arrives), saturation 0 greys it
  const auto light = ddg::recolour(im, cl, { red, {} }, 0, 1, 20);
  EXPECT_GT(ddg::rgbToLab(
              { light.at(5, 10, 0) / 0.8, light.at(5, 10, 1) / 0.8, light.at(5, 10, 2) / 0.8 })[0],
    ddg::rgbToLab({ 0.9, 0.1, 0.1 })[0] + 8);
  const auto grey = ddg::recolour(im, cl, { red, {} }, 0, 0, 0);
  EXPECT_NEAR(grey.at(5, 10, 0), grey.at(5, 10, 1), 1e-4); // through CIELAB and back
  // visibility: the blue feature doubled (0.4 -> 0.8), the red one halved
  const auto more = ddg::changeVisibility(im, cl, { blue, {} }, 2);
  EXPECT_FLOAT_EQ(more.at(30, 10, 3), 0.8f);
  EXPECT_NEAR(more.at(30, 10, 2) / more.at(30, 10, 3), 0.9, 1e-5);
  EXPECT_FLOAT_EQ(more.at(5, 10, 3), 0.8f);
  EXPECT_FLOAT_EQ(ddg::changeVisibility(im, cl, { red, {} }, 0.5).at(5, 10, 3), 0.4f);
  // a brushed mask instead of a cluster: only the masked columns change
  ddg::Image mask(40, 20, 1, 0.0f);
  for (int y = 0; y < 20; ++y)
    mask.at(35, y, 0) = 1.0f;
  const auto brushed = ddg::changeVisibility(im, cl, { -1, mask }, 0.0);
  EXPECT_FLOAT_EQ(brushed.at(35, 10, 3), 0.0f);
  EXPECT_FLOAT_EQ(brushed.at(34, 10, 3), 0.4f);
  // bad input
  EXPECT_THROW(ddg::colorClusters(ddg::Image(8, 8, 4, 0.0f), 3), ddg::Error); // nothing visible
  EXPECT_THROW(ddg::colorClusters(ddg::Image(8, 8, 3, 1.0f), 3), ddg::Error); // not RGBA
  EXPECT_THROW(ddg::colorClusters(im, 0), ddg::Error);
  EXPECT_THROW(ddg::recolour(im, cl, { 5, {} }, 10), ddg::Error);
  EXPECT_THROW(ddg::recolour(im, cl, { -1, ddg::Image(3, 3, 1) }, 10), ddg::Error);
  EXPECT_THROW(ddg::changeVisibility(im, cl, { red, {} }, -1), ddg::Error);
  EXPECT_THROW(cl.at(40, 0), ddg::Error);
}

// Exported presets' names: volume, origin, the file's stem and the local time; unique per file
// and per second; the origin left out when it is the stem; the Name written into the file.
TEST(Export, PresetNames)
{
  std::tm t{};
  t.tm_year = 2026 - 1900;
  t.tm_mon = 10;
  t.tm_mday = 24;
  t.tm_hour = 5;
  t.tm_min = 12;
  t.tm_sec = 7;
  t.tm_isdst = -1;
  const std::time_t when = std::mktime(&t);
  EXPECT_EQ(ddg::exportName("/data/tooth.vti", "query", "/tmp/out/design.json", when),
    "DDG tooth query design 2026-11-24 05:12:07");
  EXPECT_EQ(ddg::exportName("", "design", "design.json", when), "DDG design 2026-11-24 05:12:07");
  EXPECT_NE(ddg::exportName("tooth", "query", "a.json", when),
    ddg::exportName("tooth", "query", "b.json", when));
  EXPECT_NE(ddg::exportName("tooth", "query", "a.json", when),
    ddg::exportName("tooth", "query", "a.json", when + 1));
  EXPECT_EQ(ddg::designOrigin("pick"), "outline design");
  EXPECT_EQ(ddg::designOrigin("query"), "query");

  ddg::TransferFunctionFile tf;
  tf.tf1D.color = { { 0, 0, 0, 0 }, { 1, 1, 1, 1 } };
  tf.tf1D.opacity = { { 0, 0 }, { 1, 1 } };
  const std::string path =
    (std::filesystem::path(ddg::testing::tempDir()) / "export_name.json").string();
  ddg::exportTransferFunction(
    ddg::renamed(tf, "DDG tooth query x 2026-11-24 05:12:07"), path, "paraview", { 0, 1 }, 1.0);
  EXPECT_EQ(ddg::readPreset(path).name, "DDG tooth query x 2026-11-24 05:12:07");
}
