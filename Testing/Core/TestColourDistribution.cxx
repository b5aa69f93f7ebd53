// TestColourDistribution.cxx: comparing colours without pixel correspondence — rgbToLab's
// Jacobian and the sliced Wasserstein distance's gradient against finite differences, and the
// reconstruction from colour targets (a picture of the same look from another camera).
#include "Image/ImageMetrics.h"
#include "Reconstruct/CarryLook.h"
#include "Reconstruct/Reconstruction.h"
#include "TransferFunction/ColorSpace.h"
#include "VolumePieces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

using namespace ddg;

namespace
{
// A chart: a frame and a curve, lines 2 pixels wide on white.
Image lineChart()
{
  Image chart(160, 120, 3);
  std::fill(chart.pixels.begin(), chart.pixels.end(), 1.0f);
  auto ink = [&](int x, int y, RGB c)
  {
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        for (int k = 0; k < 3; ++k)
          chart.at(std::min(159, x + dx), std::min(119, y + dy), k) = static_cast<float>(c[k]);
  };
  for (int x = 20; x < 150; ++x)
  {
    ink(x, 100, { 0, 0, 0 });
    ink(x, 10, { 0, 0, 0 });
    ink(x, static_cast<int>(55 + 35 * std::sin(x / 12.0)), { 0.1, 0.3, 0.9 });
  }
  for (int y = 10; y < 101; ++y)
  {
    ink(20, y, { 0, 0, 0 });
    ink(149, y, { 0, 0, 0 });
  }
  return chart;
}
} // namespace

TEST(ColourDistribution, LabJacobianMatchesFiniteDifferences)
{
  // both pieces of sRGB's curve and of Lab's f
  for (const RGB c : { RGB{ 0.8, 0.4, 0.1 }, RGB{ 0.02, 0.03, 0.5 }, RGB{ 0.01, 0.02, 0.015 } })
  {
    double J[3][3];
    const RGB lab = rgbToLab(c, J);
    const RGB plain = rgbToLab(c);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(lab[i], plain[i], 1e-12);
    for (int j = 0; j < 3; ++j)
    {
      constexpr double h = 1e-7;
      RGB up = c, down = c;
      up[j] += h;
      down[j] -= h;
      const RGB a = rgbToLab(up), b = rgbToLab(down);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(J[i][j], (a[i] - b[i]) / (2 * h), 1e-4 * std::max(1.0, std::abs(J[i][j])));
    }
  }
}

namespace
{
// slicedWasserstein's gradient `g` of a against b (its points or their pooled projections; 8
// directions of seed 7) against central differences of step h with the same directions, at
// points 0, 7 and 23.
template <size_t D, typename B>
void expectGradientMatches(const std::vector<std::array<float, D>>& a, const B& b,
  const std::vector<std::array<float, D>>& g, float h)
{
  for (size_t i : { 0, 7, 23 })
    for (size_t c = 0; c < D; ++c)
    {
      auto up = a, down = a;
      up[i][c] += h;
      down[i][c] -= h;
      std::mt19937_64 r1(7), r2(7);
      const double fd =
        (slicedWasserstein(up, b, 8, r1) - slicedWasserstein(down, b, 8, r2)) / (2.0 * h);
      EXPECT_NEAR(g[i][c], fd, 1e-3 + 1e-3 * std::abs(fd));
    }
}
// Points uniform in [0, 50)^3 from `seed`: a (40) and b (70, its first coordinate shifted by 10);
// a2 and b2 the same points' first coordinates with another uniform one (2D).
struct PointSets
{
  std::vector<std::array<float, 3>> a, b;
  std::vector<std::array<float, 2>> a2, b2;
};
PointSets pointSets(unsigned seed)
{
  std::mt19937 pick(seed);
  std::uniform_real_distribution<float> u(0.0f, 50.0f);
  PointSets s{ std::vector<std::array<float, 3>>(40), std::vector<std::array<float, 3>>(70), {},
    {} };
  for (auto& p : s.a)
    p = { u(pick), u(pick), u(pick) };
  for (auto& p : s.b)
    p = { u(pick) + 10, u(pick), u(pick) };
  for (const auto& p : s.a)
    s.a2.push_back({ p[0], u(pick) });
  for (const auto& p : s.b)
    s.b2.push_back({ p[0], u(pick) });
  return s;
}
} // namespace

TEST(ColourDistribution, SlicedWassersteinAndItsGradient)
{
  const auto [a, b, a2, b2] = pointSets(3);
  // a set against itself, and against itself repeated (another size, the same distribution)
  std::mt19937_64 rng(1);
  EXPECT_NEAR(slicedWasserstein(a, a, 16, rng), 0.0, 1e-9);
  std::vector<std::array<float, 3>> twice = a;
  twice.insert(twice.end(), a.begin(), a.end());
  std::mt19937_64 rng2(1);
  EXPECT_LT(slicedWasserstein(a, twice, 16, rng2), 1.0); // quantiles between equal pairs
  // the gradient: central differences with the same directions
  std::vector<std::array<float, 3>> g;
  std::mt19937_64 r0(7);
  const double d0 = slicedWasserstein(a, b, 8, r0, &g);
  EXPECT_GT(d0, 10.0);
  expectGradientMatches(a, b, g, 1e-2f);
  // the directions shared among threads: the same gradient, the same distance
  std::vector<std::array<float, 3>> gThreads;
  std::mt19937_64 r6(7);
  EXPECT_NEAR(slicedWasserstein(a, b, 8, r6, &gThreads, 3), d0, 1e-12 * d0);
  for (size_t i = 0; i < g.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(gThreads[i][static_cast<size_t>(c)], g[i][static_cast<size_t>(c)]);
  std::mt19937_64 r3(1);
  EXPECT_THROW(slicedWasserstein({}, b, 8, r3), Error);
  EXPECT_THROW(slicedWasserstein(a, b, 0, r3), Error);

  // in 2D (a lightness and where it lies): the same gradient check
  std::vector<std::array<float, 2>> g2;
  std::mt19937_64 r4(7);
  EXPECT_GT(slicedWasserstein(a2, b2, 8, r4, &g2), 10.0);
  std::mt19937_64 r5(1);
  EXPECT_NEAR(slicedWasserstein(a2, a2, 16, r5), 0.0, 1e-9);
  expectGradientMatches(a2, b2, g2, 1e-3f);
}

TEST(ColourDistribution, PooledDirectionsSortTheTargetOnce)
{
  const auto [a, b, a2, b2] = pointSets(5);
  // a pool of 12 is the 12 directions slicedWasserstein draws from the same seed: drawing all of
  // it gives the same distance (b's projections kept as floats)
  std::mt19937_64 poolRng(5), freshRng(5), drawRng(1);
  const auto pool = sortedProjections(b, 12, poolRng);
  ASSERT_EQ(pool.directions.size(), 12u);
  ASSERT_EQ(pool.sorted.size(), 12u * b.size());
  for (size_t d = 0; d < 12; ++d)
    EXPECT_TRUE(
      std::is_sorted(pool.sorted.begin() + d * b.size(), pool.sorted.begin() + (d + 1) * b.size()));
  const double fresh = slicedWasserstein(a, b, 12, freshRng);
  EXPECT_NEAR(slicedWasserstein(a, pool, 12, drawRng), fresh, 1e-5 * fresh);
  std::mt19937_64 moreRng(1); // more directions than the pool holds: all of them
  EXPECT_NEAR(slicedWasserstein(a, pool, 40, moreRng), fresh, 1e-5 * fresh);
  // a set against its own pool
  std::mt19937_64 selfPool(2), selfDraw(3);
  EXPECT_NEAR(slicedWasserstein(a, sortedProjections(a, 16, selfPool), 8, selfDraw), 0.0, 1e-6);
  // 8 of the 12 drawn: the gradient against central differences with the same draw, and the
  // same distance and gradient for any thread count
  std::vector<std::array<float, 3>> g, gThreads;
  std::mt19937_64 r0(7), r1(7);
  const double d0 = slicedWasserstein(a, pool, 8, r0, &g);
  EXPECT_GT(d0, 10.0);
  expectGradientMatches(a, pool, g, 1e-2f);
  EXPECT_NEAR(slicedWasserstein(a, pool, 8, r1, &gThreads, 3), d0, 1e-12 * d0);
  for (size_t i = 0; i < g.size(); ++i)
    for (size_t c = 0; c < 3; ++c)
      EXPECT_EQ(gThreads[i][c], g[i][c]);
  // in 2D
  std::vector<std::array<float, 2>> g2;
  std::mt19937_64 pool2Rng(6), r2(7);
  const auto pool2 = sortedProjections(b2, 12, pool2Rng, 2);
  EXPECT_GT(slicedWasserstein(a2, pool2, 8, r2, &g2), 10.0);
  expectGradientMatches(a2, pool2, g2, 1e-3f);
  std::mt19937_64 r3(1);
  EXPECT_THROW(sortedProjections(std::vector<std::array<float, 3>>{}, 8, r3), Error);
  EXPECT_THROW(sortedProjections(b, 0, r3), Error);
  EXPECT_THROW(slicedWasserstein(std::vector<std::array<float, 3>>{}, pool, 8, r3), Error);
  EXPECT_THROW(slicedWasserstein(a, pool, 0, r3), Error);
  SortedProjections<3> broken = pool; // not count projections per direction
  broken.sorted.pop_back();
  EXPECT_THROW(slicedWasserstein(a, broken, 8, r3), Error);
  broken.directions.clear();
  EXPECT_THROW(slicedWasserstein(a, broken, 8, r3), Error);
}

TEST(ColourDistribution, FramesTheContentWithoutItsOverlays)
{
  // a 20 x 20 red square in the middle of a grey 100 x 100 picture, a white 6 x 6 "axes" mark
  // in the lower left corner: left out, it widens neither the square nor the colours
  View view;
  view.width = view.height = 100;
  view.background = { 0.3, 0.3, 0.4 };
  Image picture(100, 100, 3), leaveOut(100, 100, 1);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x)
    {
      const bool object = x >= 40 && x < 60 && y >= 40 && y < 60;
      const bool mark = x >= 2 && x < 8 && y >= 92 && y < 98;
      const RGB c = object ? RGB{ 0.9, 0.1, 0.1 } : mark ? RGB{ 1, 1, 1 } : view.background;
      for (int k = 0; k < 3; ++k)
        picture.at(x, y, k) = static_cast<float>(c[static_cast<size_t>(k)]);
      leaveOut.at(x, y, 0) = mark ? 1.0f : 0.0f;
    }
  const auto colours = framedColours(picture, view, leaveOut);
  // the square 10 % larger than the object's 20 x 20 box: 22 x 22, of which 400 red pixels
  ASSERT_EQ(colours.size(), 22u * 22u);
  size_t red = 0;
  for (const auto& c : colours)
  {
    EXPECT_LT(c[0] + c[1] + c[2], 2.5f) << "an overlay pixel was kept";
    red += c[0] > 0.8f;
  }
  EXPECT_EQ(red, 400u);
  // without the mask the mark is content: the square reaches the corner
  EXPECT_GT(framedColours(picture, view).size(), 60u * 60u);
  // where each colour lies: its distance from the square's centre in half-sides (11 pixels)
  std::vector<float> radii;
  const size_t framed = framedColours(picture, view, leaveOut, &radii).size();
  ASSERT_EQ(framed, radii.size());
  EXPECT_NEAR(*std::min_element(radii.begin(), radii.end()), std::hypot(0.5, 0.5) / 11, 1e-5);
  EXPECT_NEAR(*std::max_element(radii.begin(), radii.end()), std::hypot(10.5, 10.5) / 11, 1e-5);
}

namespace
{
// 24^3 points: a core of 220 (radius 5) in a shell of 120 (radius 10) in air (0).
Volume coreInShell()
{
  const int n = 24;
  std::vector<float> v;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const double r = std::hypot(i - 11.5, j - 11.5, k - 11.5);
        v.push_back(r < 5 ? 220.0f : (r < 10 ? 120.0f : 0.0f));
      }
  return Volume({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::UInt8);
}
} // namespace

TEST(ColourDistribution, ReconstructsALookFromAnotherCamera)
{
  // a sphere whose shell and core take two colours; the picture is from the other side
  const Volume vol = coreInShell();
  const DifferentiableRenderer renderer(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 0, 0, 0 }, { 120, 0.9, 0.3, 0.1 }, { 220, 0.2, 0.8, 0.9 } };
  tf.opacity = { { 0, 0 }, { 100, 0 }, { 120, 0.05 }, { 140, 0 }, { 200, 0 }, { 220, 0.8 } };
  View picture = defaultView(vol, 40, 40);
  picture.background = { 0.32, 0.34, 0.43 };
  picture.camera.position =
    picture.camera.focalPoint + (picture.camera.focalPoint - picture.camera.position); // the back
  const Image shot = compositeOverBackground(
    renderer.caster().render(renderer.caster().paraviewTable(tf), picture), picture.background);
  ColourTarget target;
  target.view = defaultView(vol, 40, 40);
  target.view.background = picture.background;
  target.colours = framedColours(shot, picture);
  EXPECT_LT(target.colours.size(), shot.pixels.size() / 3); // the square on the sphere

  ReconstructionOptions opt;
  opt.primitives = 2;
  opt.initialPrimitives = { GaussianPrimitive{ { 120, 0 }, { 10, 1 }, { 0.5, 0.5, 0.5 }, 0.2 },
    GaussianPrimitive{ { 220, 0 }, { 10, 1 }, { 0.5, 0.5, 0.5 }, 0.2 } };
  opt.iterations = 150;
  opt.learningRate = 0.1;
  const auto result = reconstructFromColours(renderer, { target }, opt);
  EXPECT_LT(result.loss.back(), 0.2 * result.loss.front());
  // the found look from the picture's own camera is close to the picture
  const Image found =
    compositeOverBackground(renderResult(renderer.caster(), result, picture), picture.background);
  EXPECT_GT(psnr(found, shot), 25.0);
  // the core's primitive took the core's colour (blue-green), the shell's its orange
  ASSERT_EQ(result.primitives.size(), 2u);
  EXPECT_GT(result.primitives[1].rgb[2], result.primitives[1].rgb[0]);
  // the same with its directions drawn from a pool (the target sorted once): the same look
  ReconstructionOptions pooled = opt;
  pooled.directionPool = 256;
  const auto fromPool = reconstructFromColours(renderer, { target, target }, pooled);
  EXPECT_LT(fromPool.loss.back(), 0.2 * fromPool.loss.front());
  EXPECT_GT(psnr(compositeOverBackground(
                   renderResult(renderer.caster(), fromPool, picture), picture.background),
              shot),
    25.0);
  pooled.directionPool = -1;
  EXPECT_THROW(reconstructFromColours(renderer, { target }, pooled), Error);

  EXPECT_THROW(reconstructFromColours(renderer, { ColourTarget{ target.view, {} } }, opt), Error);
  opt.initialPrimitives.pop_back();
  EXPECT_THROW(reconstructFromColours(renderer, { target }, opt), Error);
}

TEST(ColourDistribution, PlacementTellsACoreFromARim)
{
  // a bright blue core inside a faint orange shell: the picture shows blue in the middle and
  // orange around it. The same two colours the other way round (an orange core in a blue shell)
  // are told apart far better when where the colours lie counts (colourPlacement)
  const Volume vol = coreInShell();
  const DifferentiableRenderer renderer(vol);
  const RGB orange{ 0.9, 0.45, 0.1 }, blue{ 0.15, 0.35, 0.9 };
  const auto primitives = [](const RGB& shell, const RGB& core)
  {
    return std::vector<GaussianPrimitive>{ GaussianPrimitive{ { 120, 0 }, { 8, 1 }, shell, 0.1 },
      GaussianPrimitive{ { 220, 0 }, { 8, 1 }, core, 0.9 } };
  };
  ReconstructionOptions opt;
  opt.primitives = 2;
  opt.initialPrimitives = primitives(orange, blue);
  opt.iterations = 1;
  opt.learningRate = 1e-12;
  opt.directions = 256;
  View view = defaultView(vol, 48, 48);
  view.background = { 0, 0, 0 };
  const ReconstructionResult truth = reconstructFromColours(
    renderer, { ColourTarget{ view, { { 0.5f, 0.5f, 0.5f } }, { 0.0f } } }, opt);
  const Image shot =
    compositeOverBackground(renderResult(renderer.caster(), truth, view), view.background);
  ColourTarget target{ view, {}, {} };
  target.colours = framedColours(shot, view, {}, &target.radii);
  const auto distance = [&](const RGB& shell, const RGB& core, double placement)
  {
    ReconstructionOptions o = opt;
    o.initialPrimitives = primitives(shell, core);
    o.colourPlacement = placement;
    return reconstructFromColours(renderer, { target }, o).loss.front();
  };
  EXPECT_LT(distance(orange, blue, 0), 0.1);
  EXPECT_LT(distance(orange, blue, 100), 0.2);
  // against a start in the right places whose colours are off
  const RGB red{ 0.95, 0.2, 0.2 }, violet{ 0.5, 0.3, 0.9 };
  const double swapped0 = distance(blue, orange, 0), swapped100 = distance(blue, orange, 100);
  const double off0 = distance(red, violet, 0), off100 = distance(red, violet, 100);
  std::printf("the other way round: %.2f, %.2f with placement; colours off: %.2f, %.2f\n", swapped0,
    swapped100, off0, off100);
  // placement adds to the swapped start's distance far more than to the merely off one's
  EXPECT_GT(swapped100 - swapped0, 3 * (off100 - off0));
  // placement needs the target's radii
  target.radii.clear();
  opt.colourPlacement = 25;
  EXPECT_THROW(reconstructFromColours(renderer, { target }, opt), Error);
}

namespace
{
// A core in a shell in air (n^3 points).
Volume sphere(int n, float shell, float core, double coreRadius, ScalarType type)
{
  std::vector<float> v;
  const double c = 0.5 * (n - 1);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const double r = std::hypot(i - c, j - c, k - c) / c;
        v.push_back(r < coreRadius ? core : (r < 0.85 ? shell : 0.0f));
      }
  return Volume({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, type);
}

// A faint orange shell, a white core, at the given values.
TransferFunction1D look(double shell, double core)
{
  TransferFunction1D tf;
  tf.color = { { 0, 0, 0, 0 }, { shell, 0.9, 0.5, 0.2 }, { core, 1, 1, 0.95 } };
  tf.opacity = { { 0, 0 }, { 0.8 * shell, 0 }, { shell, 0.03 }, { 1.2 * shell, 0 },
    { 0.9 * core, 0 }, { core, 0.9 } };
  return tf;
}
} // namespace

TEST(ColourDistribution, CarriesALookToAnotherVolume)
{
  // A and B of the same kind: a core in a shell in air, at other values, sizes and proportions
  const Volume a = sphere(24, 100, 200, 0.45, ScalarType::UInt8);
  const Volume b = sphere(28, 1000, 3000, 0.55, ScalarType::UInt16);
  // A's look; B's reference: the same TF at B's values
  const DifferentiableRenderer ra(a), rb(b);
  View shotView = orbitView(a, 64, 200, -10, 1.1);
  shotView.width = 80; // a landscape picture, another camera than the fit's views
  shotView.background = { 0.32, 0.34, 0.43 };
  const Image shot = compositeOverBackground(
    ra.caster().render(ra.caster().paraviewTable(look(100, 200)), shotView), shotView.background);

  CarryLookOptions opt;
  opt.size = 40;
  opt.fit.iterations = 120;
  const auto r = carryLook(rb, shot, opt);
  EXPECT_LT(r.distanceEnd, 0.5 * r.distanceStart);
  ASSERT_EQ(r.regions.size(), 2u); // the shell and the core, by value
  EXPECT_LT(r.regions[0].region.peak, r.regions[1].region.peak);
  // the core's colour is lighter than the shell's
  EXPECT_GT(r.regions[1].colour[2], r.regions[0].colour[2]);
  // B with the carried look against B with A's TF at B's values, at a view the fit never saw
  View check = orbitView(b, 64, 90, 40, 1.0);
  check.background = shotView.background;
  const Image reference = compositeOverBackground(
    rb.caster().render(rb.caster().paraviewTable(look(1000, 3000)), check), check.background);
  const Image carried =
    compositeOverBackground(renderResult(rb.caster(), r.fit, check), check.background);
  const double db = psnr(carried, reference);
  EXPECT_GT(db, 22.0);
  // two spheres: the shapes agree
  EXPECT_GT(r.shapeAgreement, 0.8);
  EXPECT_TRUE(r.shapesAgree);
  // a picture with nothing in it is refused
  Image empty(40, 30, 3);
  std::fill(empty.pixels.begin(), empty.pixels.end(), 0.3f);
  EXPECT_THROW(carryLook(rb, empty, opt), Error);
  // a chart (a frame, a curve, tick marks: lines 2 pixels wide on white) is refused
  const Image chart = lineChart();
  try
  {
    carryLook(rb, chart, opt);
    ADD_FAILURE() << "a chart's look was carried";
  }
  catch (const Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("lines or text"), std::string::npos) << e.what();
  }
  // a picture of a long thin rod (another kind of volume): answered, the shapes disagree
  std::vector<float> rod(48 * 48 * 48, 0.0f);
  for (int k = 0; k < 48; ++k)
    for (int j = 0; j < 48; ++j)
      for (int i = 0; i < 48; ++i)
        if (std::hypot(i - 23.5, j - 23.5) < 3 && k > 2 && k < 45)
          rod[static_cast<size_t>((k * 48 + j) * 48 + i)] = 200;
  const Volume rodVolume({ 48, 48, 48 }, { 0, 0, 0 }, { 1, 1, 1 }, rod, ScalarType::UInt8);
  const DifferentiableRenderer rr(rodVolume);
  View side = orbitView(rodVolume, 64, 90, 0, 1.0);
  side.background = shotView.background;
  TransferFunction1D white;
  white.color = { { 0, 1, 1, 1 }, { 200, 1, 1, 1 } };
  white.opacity = { { 0, 0 }, { 100, 0 }, { 200, 0.9 } };
  const Image rodShot = compositeOverBackground(
    rr.caster().render(rr.caster().paraviewTable(white), side), side.background);
  opt.fit.iterations = 5;
  const auto other = carryLook(rb, rodShot, opt);
  EXPECT_LT(other.shapeAgreement, 0.6) << "a rod's picture agrees with a sphere";
  EXPECT_FALSE(other.shapesAgree);
}

// Carrying a look over pieces of the volume (ParaView's ranks; here threads exchanging through a
// ThreadBoard): the pieces find the whole's feature regions (the histogram's counts summed, each
// point counted once) and shape agreement exactly, and a look that renders as the whole's; on 2
// and 3 pieces and an uneven split with a piece that owns no cell.
TEST(ColourDistribution, CarriesALookOverPieces)
{
  const Volume a = sphere(24, 100, 200, 0.45, ScalarType::UInt8);
  const Volume b = sphere(28, 1000, 3000, 0.55, ScalarType::UInt16);
  const DifferentiableRenderer ra(a), rb(b);
  View shotView = orbitView(a, 64, 200, -10, 1.1);
  shotView.background = { 0.32, 0.34, 0.43 };
  const Image shot = compositeOverBackground(
    ra.caster().render(ra.caster().paraviewTable(look(100, 200)), shotView), shotView.background);
  CarryLookOptions opt;
  opt.size = 40;
  opt.fit.iterations = 60;
  opt.fit.render.terminationOpacity = 1.0; // the pieces' composite is the whole's
  const auto whole = carryLook(rb, shot, opt);
  const auto& d = b.dims();
#if defined(__SANITIZE_ADDRESS__)
  const std::vector<int> splits{ 0 }; // the uneven split alone: 4 carried looks are slow there
#else
  const std::vector<int> splits{ 2, 3, 0 };
#endif
  for (int split : splits)
  {
    std::vector<ddg::testing::Box> boxes = ddg::testing::unevenSplit(b); // 0: with an empty piece
    if (split > 0)
    {
      boxes.clear();
      ddg::testing::bisect({ 0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1 }, split, boxes);
    }
    const int n = static_cast<int>(boxes.size());
    std::vector<CarryLookResult> each(static_cast<size_t>(n));
    ddg::testing::onPieces(b, boxes,
      [&](int p, const DifferentiableRenderer& r)
      { each[static_cast<size_t>(p)] = carryLook(r, shot, opt); });
    View check = orbitView(b, 64, 90, 40, 1.0);
    for (const auto& r : each)
    {
      ASSERT_EQ(r.regions.size(), whole.regions.size());
      for (size_t k = 0; k < r.regions.size(); ++k)
      {
        EXPECT_EQ(r.regions[k].region.lo, whole.regions[k].region.lo);
        EXPECT_EQ(r.regions[k].region.hi, whole.regions[k].region.hi);
        EXPECT_EQ(r.regions[k].region.mass, whole.regions[k].region.mass);
      }
      EXPECT_EQ(r.shapeAgreement, whole.shapeAgreement);
      const double db =
        psnr(renderResult(rb.caster(), r.fit, check), renderResult(rb.caster(), whole.fit, check));
      std::printf("%d pieces: the carried look at PSNR %.1f dB against one process's\n", n, db);
      EXPECT_GT(db, 30.0) << n << " pieces";
      EXPECT_EQ(r.fit.table1D.rgba, each[0].fit.table1D.rgba); // the same on every piece
    }
  }
}

// What a query accepts: a rendered volume as users save it (palette background, orientation axes
// in a corner, letterboxed) answers without a warning, and so does an object too small to tell
// lines from a solid; a chart is refused as lines or text; a photograph-like picture (no one
// colour along its border) gets a warning.
TEST(ColourDistribution, QueryPictureCheck)
{
  const Volume v = sphere(24, 100, 200, 0.45, ScalarType::UInt8);
  const DifferentiableRenderer r(v);
  View view = orbitView(v, 120, 30, 20, 1.1);
  view.width = 160;
  view.background = { 0.32, 0.34, 0.43 };
  Image shot = compositeOverBackground(
    r.caster().render(r.caster().paraviewTable(look(100, 200)), view), view.background);
  for (int k = 0; k < 14; ++k) // orientation axes in the corner: three short lines
  {
    shot.at(8 + k, 110, 0) = 1.0f;
    shot.at(8, 110 - k, 1) = 1.0f;
    shot.at(8 + k / 2, 110 - k / 2, 2) = 1.0f;
  }
  EXPECT_EQ(checkQueryPicture(shot), "");
  // letterboxed: black bands above and below
  Image boxed(160, 160, 3);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      for (int c = 0; c < 3; ++c)
        boxed.at(x, y + 20, c) = shot.at(x, y, c);
  EXPECT_EQ(checkQueryPicture(boxed), "");
  // a ring of 2-pixel strokes: 12 pixels across, too small to tell from a solid (answered);
  // 100 pixels across, lines (refused)
  auto ring = [](int w, int h, double radius)
  {
    Image img(w, h, 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
      {
        const double d = std::hypot(x - w / 2.0, y - h / 2.0);
        const bool ink = d < radius && d >= radius - 2;
        for (int c = 0; c < 3; ++c)
          img.at(x, y, c) = ink ? 0.9f : 0.33f;
      }
    return img;
  };
  EXPECT_EQ(checkQueryPicture(ring(32, 24, 6)), "");
  EXPECT_THROW(checkQueryPicture(ring(160, 120, 50)), Error);
  // a chart: refused
  try
  {
    checkQueryPicture(lineChart());
    ADD_FAILURE() << "a chart was taken for a rendered volume";
  }
  catch (const Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("lines or text"), std::string::npos) << e.what();
  }
  // a photograph-like picture: smooth colours to every edge, no one background colour
  Image photo(160, 120, 3);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      for (int c = 0; c < 3; ++c)
        photo.at(x, y, c) =
          static_cast<float>(0.5 + 0.4 * std::sin(0.05 * x * (c + 1) + 0.07 * y * (3 - c)));
  const std::string warning = checkQueryPicture(photo);
  EXPECT_NE(warning.find("cannot be read as a rendered volume"), std::string::npos) << warning;
}

// A picture over 512 pixels on its longer side is read at its halves (shrinkImage's 2 x 2 box
// averages): the same scene drawn at 1024 x 768 and at 512 x 384 gives the same background,
// object, overlays and solidity, and nearly the same pixels; 800 x 600 is read at exactly its
// 2 x 2 averages (not resized to 512 x 384), 1001 x 701 at 500 x 350.
TEST(ColourDistribution, ReadsALargePictureAsItsHalf)
{
  const Volume v = sphere(24, 100, 200, 0.45, ScalarType::UInt8);
  const DifferentiableRenderer r(v);
  auto plain = [&](int w, int h)
  {
    View view = orbitView(v, 120, 30, 20, 1.1);
    view.width = w;
    view.height = h;
    view.background = { 0.32, 0.34, 0.43 };
    return compositeOverBackground(
      r.caster().render(r.caster().paraviewTable(look(100, 200)), view), view.background);
  };
  auto shot = [&](int scale)
  {
    Image img = plain(512 * scale, 384 * scale);
    // orientation axes in the lower left corner, 2 pixels wide at 512
    for (int k = 0; k < 30 * scale; ++k)
      for (int t = 0; t < 2 * scale; ++t)
      {
        img.at(20 * scale + k, 360 * scale + t, 0) = 1.0f;
        img.at(20 * scale + t, 360 * scale - k, 1) = 1.0f;
      }
    return img;
  };
  const PictureObject large = readPictureObject(shot(2)), small = readPictureObject(shot(1));
  ASSERT_EQ(large.picture.width, 512);
  ASSERT_EQ(large.picture.height, 384);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(large.background.bottom[static_cast<size_t>(c)],
      small.background.bottom[static_cast<size_t>(c)], 0.005);
  auto count = [](const std::vector<std::uint8_t>& m)
  { return static_cast<double>(std::count(m.begin(), m.end(), 1)); };
  EXPECT_GT(count(small.object), 0.05 * 512 * 384);
  EXPECT_NEAR(count(large.object) / count(small.object), 1.0, 0.02);
  EXPECT_GT(count(small.overlay), 0);
  EXPECT_NEAR(count(large.overlay) / count(small.overlay), 1.0, 0.1);
  EXPECT_NEAR(large.solidShare, small.solidShare, 0.02);
  EXPECT_GT(psnr(large.picture, small.picture), 30.0);
  // at sizes that are not twice 512 too: halved until at most 512 on the longer side, each pixel
  // the exact 2 x 2 average of the picture's, never a filtered resize
  const Image odd = plain(800, 600);
  const PictureObject read = readPictureObject(odd);
  ASSERT_EQ(read.picture.width, 400);
  ASSERT_EQ(read.picture.height, 300);
  int unlike = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x)
      for (int c = 0; c < 3; ++c)
      {
        const float average = 0.25f *
          (odd.at(2 * x, 2 * y, c) + odd.at(2 * x + 1, 2 * y, c) + odd.at(2 * x, 2 * y + 1, c) +
            odd.at(2 * x + 1, 2 * y + 1, c));
        unlike += read.picture.at(x, y, c) == average ? 0 : 1;
      }
  EXPECT_EQ(unlike, 0);
  const PictureObject odder = readPictureObject(plain(1001, 701));
  EXPECT_EQ(odder.picture.width, 500);
  EXPECT_EQ(odder.picture.height, 350);
}
