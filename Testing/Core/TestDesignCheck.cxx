// TestDesignCheck.cxx: the design check (empty / flat box) and the screen built on it.
// Compared: the box's footprint with a naive slab test of every pixel's ray (at most 2 % of the
// footprint may differ, on its edge); the looks of TFs whose answer is known by construction (a
// fog filling the box, a sphere inside it, nothing); the screen's regions and exemplars against
// re-rendered checks of what it kept, and its counts against the candidates it examined.
#include "Design/DesignCheck.h"
#include "Design/ExemplarGenerator.h"

#include "TempDir.h"
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

using namespace ddg;
namespace fs = std::filesystem;

namespace
{
// A fog at 200 filling the whole box (the most frequent value, high in the range, so the
// histogram's air rule keeps it) around two spheres at 60 and 120; one voxel at 0 stretches the
// range.
Volume fogAndSphere()
{
  const int n = 32;
  std::mt19937 rng(2);
  std::normal_distribution<float> noise(0.0f, 3.0f);
  std::vector<float> v;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        auto r = [&](double cx) {
          return std::sqrt((i - cx) * (i - cx) + (j - 15.5) * (j - 15.5) + (k - 15.5) * (k - 15.5));
        };
        const float base = r(9.5) < 5.5 ? 60.0f : (r(21.5) < 5.5 ? 120.0f : 200.0f);
        v.push_back(std::clamp(base + noise(rng), 0.0f, 255.0f));
      }
  v[0] = 0;
  return Volume({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::Float32);
}

GaussianPrimitive at(double value, double opacity)
{
  GaussianPrimitive g;
  g.mean = { value, 0 };
  g.stddev = { 8, 1 };
  g.rgb = { 0.8, 0.6, 0.4 };
  g.opacity = opacity;
  return g;
}
} // namespace

TEST(DesignCheck, FootprintMatchesSlabTest)
{
  const Volume volume = fogAndSphere();
  const RayCaster caster(volume);
  const View view = orbitView(volume, 64, 30, 20, 1);
  const Image mask = boxFootprint(caster, view);
  const RayGenerator rays(view);
  int footprint = 0, differ = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
    {
      Eigen::Vector3d o, d;
      rays.ray(x, y, o, d);
      double t0 = -1e30, t1 = 1e30;
      for (int a = 0; a < 3; ++a)
      {
        const double lo = 0, hi = 31; // point bounds
        if (std::abs(d[a]) < 1e-12)
        {
          if (o[a] < lo || o[a] > hi)
            t0 = 1e30;
          continue;
        }
        double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
        if (ta > tb)
          std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      const bool hit = t1 > std::max(t0, 0.0);
      footprint += hit;
      differ += hit != (mask.at(x, y, 0) > 0.5f);
    }
  ASSERT_GT(footprint, 500);
  EXPECT_LE(differ, 0.02 * footprint);
}

TEST(DesignCheck, LooksOfKnownDesigns)
{
  const Volume volume = fogAndSphere();
  const RayCaster caster(volume);
  const View view = orbitView(volume, 48, 0, 20, 1);
  const std::array<double, 2> none{ 0.0, 1.0 };
  const DesignLook fog = lookOfPrimitives(caster, { at(200, 0.5) }, 1, none, view);
  EXPECT_TRUE(fog.flatBox());
  EXPECT_GT(fog.coverage, 0.99);
  const DesignLook sphere = lookOfPrimitives(caster, { at(60, 0.5) }, 1, none, view);
  EXPECT_FALSE(sphere.junk());
  EXPECT_LT(sphere.coverage, 0.6);
  EXPECT_LT(sphere.ringCoverage, 0.05);
  const DesignLook nothing = lookOfPrimitives(caster, {}, 1, none, view);
  EXPECT_TRUE(nothing.empty());
  EXPECT_GT(nothing.footprint, 0);
  // a faint fog (alpha under the visible level everywhere) is empty, not a box
  const DesignLook faint = lookOfPrimitives(caster, { at(200, 0.0005) }, 1, none, view);
  EXPECT_TRUE(faint.empty());
  const BoxCorners corners(volume, 1, caster.defaultOpacityUnitDistance());
  EXPECT_TRUE(judgeDesign(caster, corners, { at(200, 0.5) }, 1, none).flatBox);
  EXPECT_FALSE(judgeDesign(caster, corners, { at(60, 0.5) }, 1, none).junk());
  // a haze: too faint at the box's silhouette for the footprint's ring, plain across the box
  // (mean opacity 0.01 over 31 voxels at a unit distance of ~1.7: alpha ~0.17)
  const DesignLook haze = lookOfPrimitives(caster, { at(200, 0.01) }, 1, none, view);
  EXPECT_FALSE(haze.flatBox());
  EXPECT_FALSE(haze.empty());
  EXPECT_TRUE(corners.hazy({ at(200, 0.01) }));
  EXPECT_TRUE(judgeDesign(caster, corners, { at(200, 0.01) }, 1, none).flatBox);
  EXPECT_FALSE(corners.hazy({ at(60, 0.9), at(120, 0.9) }));
  EXPECT_FALSE(corners.hazy({ at(200, 0.0005) })); // alpha ~0.009 across the box: not seen
  EXPECT_FALSE(corners.hazy({}));
  EXPECT_THROW(lookOfDesign(Image(8, 8, 4), Image(9, 8, 1)), Error);
}

TEST(DesignCheck, RegionsLeaveOutTheFog)
{
  const Volume volume = fogAndSphere();
  const auto plain = findFeatureRegions(volume);
  ASSERT_EQ(plain.size(), 3u); // the histogram alone takes the fog
  EXPECT_NEAR(plain[2].peak, 200, 6);
  int left = -1;
  const RayCaster caster(volume);
  const BoxCorners corners(volume, 1, caster.defaultOpacityUnitDistance());
  const auto screened = findDesignRegions(volume, caster, corners, DesignSpaceSpec{}, &left);
  ASSERT_EQ(screened.size(), 2u);
  EXPECT_NEAR(screened[0].peak, 60, 6);
  EXPECT_NEAR(screened[1].peak, 120, 6);
  EXPECT_EQ(left, 1);
  // the spec's own regions are kept as given
  DesignSpaceSpec given;
  given.regions = plain;
  EXPECT_EQ(findDesignRegions(volume, caster, corners, given, &left).size(), 3u);
  EXPECT_EQ(left, 0);
}

TEST(DesignCheck, ScreenedExemplarsShowStructure)
{
  const Volume volume = fogAndSphere();
  DesignSpaceSpec spec;
  spec.regions = findFeatureRegions(volume); // fog included: 2 in 3 designs paint the box
  GenerateOptions o;
  o.count = 24;
  o.size = 24;
  o.shardSize = 10;
  o.screen = true;
  o.threads = 2;
  const std::string dir = ddg::testing::tempDir() + "/ddg_screened";
  fs::remove_all(dir);
  const auto report = generateExemplars(volume, spec, dir, o);
  EXPECT_GT(report.flatBox, 0);
  EXPECT_EQ(report.candidates, o.count + report.empty + report.flatBox);
  EXPECT_FALSE(report.screenExhausted);
  const ExemplarDataset data(dir);
  const RayCaster caster(volume);
  for (const auto& e : data.exemplars())
    EXPECT_FALSE(lookOfPrimitives(caster, e.primitives, 1, { 0.0, 1.0 }, e.viewExp).junk());
  // the same indices for any thread count
  o.threads = 1;
  const std::string dir1 = dir + "_1";
  fs::remove_all(dir1);
  generateExemplars(volume, spec, dir1, o);
  const ExemplarDataset data1(dir1);
  for (int i = 0; i < o.count; ++i)
    EXPECT_EQ(data.exemplars()[i].seed, data1.exemplars()[i].seed);
  // unscreened: every index in turn, as before
  o.screen = false;
  fs::remove_all(dir1);
  const auto plain = generateExemplars(volume, spec, dir1, o);
  EXPECT_EQ(plain.candidates, 0);
  const ExemplarDataset data2(dir1);
  EXPECT_EQ(data2.exemplars()[5].seed, 1 * 0x9E3779B97F4A7C15ull + 5);
  // candidates run out (one region, the fog): the rest are kept as drawn, and said so
  spec.regions = { spec.regions[2] };
  o.screen = true;
  o.count = 6;
  fs::remove_all(dir1);
  const auto fog = generateExemplars(volume, spec, dir1, o);
  EXPECT_TRUE(fog.screenExhausted);
  EXPECT_GE(fog.candidates, 4 * o.count);
  EXPECT_EQ(ExemplarDataset(dir1).count(), o.count);
  fs::remove_all(dir);
  fs::remove_all(dir1);
}
