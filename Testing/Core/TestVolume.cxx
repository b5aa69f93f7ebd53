// TestVolume.cxx: trilinear sampling and gradient magnitude against hand-computed values on
// linear fields (exact), NaN handling, validation, and the raw+JSON reader on the shipped data.
// Tolerance 1e-9 (double arithmetic on float32 storage of small integers is exact).
#include "Common/Error.h"
#include "Volume/VolumeIO.h"

#include "TempDir.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>

using namespace ddg;

namespace
{
Volume linearVolume()
{
  // v = 2i + 3j + 5k on 4 x 5 x 6 points, spacing (0.5, 2, 1), origin (1, -1, 0)
  std::vector<float> v;
  for (int k = 0; k < 6; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 4; ++i)
        v.push_back(static_cast<float>(2 * i + 3 * j + 5 * k));
  return Volume({ 4, 5, 6 }, { 1, -1, 0 }, { 0.5, 2, 1 }, v, ScalarType::Int16);
}
} // namespace

TEST(Volume, TrilinearIsExactOnLinearFields)
{
  const Volume vol = linearVolume();
  EXPECT_NEAR(vol.sampleIndex(1.25, 2.5, 3.75), 2 * 1.25 + 3 * 2.5 + 5 * 3.75, 1e-9);
  // world (1 + 0.5 i, -1 + 2 j, k)
  EXPECT_NEAR(
    vol.sampleWorld(1.0 + 0.5 * 2.2, -1 + 2 * 0.3, 4.9), 2 * 2.2 + 3 * 0.3 + 5 * 4.9, 1e-9);
  // clamped outside
  EXPECT_NEAR(vol.sampleIndex(-3, 0, 0), 0.0, 1e-9);
  EXPECT_NEAR(vol.sampleIndex(10, 10, 10), 2 * 3 + 3 * 4 + 5 * 5, 1e-9);
  const auto b = vol.bounds();
  EXPECT_DOUBLE_EQ(b[1], 2.5);
  EXPECT_DOUBLE_EQ(b[3], 7.0);
}

TEST(Volume, GradientMagnitudeInWorldUnits)
{
  const Volume vol = linearVolume();
  // d/dx = 2 / 0.5 = 4, d/dy = 3 / 2 = 1.5, d/dz = 5 / 1 = 5, each times N/(N-1) (4, 5, 6
  // points) inside; on a face the clamped difference spans one cell, so that axis halves.
  const double gx = 4 * 4.0 / 3, gy = 1.5 * 5.0 / 4, gz = 5 * 6.0 / 5;
  const auto g = vol.gradientMagnitude();
  const auto& d = vol.dims();
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
      {
        const double fx = (i == 0 || i == d[0] - 1) ? 0.5 : 1.0;
        const double fy = (j == 0 || j == d[1] - 1) ? 0.5 : 1.0;
        const double fz = (k == 0 || k == d[2] - 1) ? 0.5 : 1.0;
        const double expected =
          std::sqrt(fx * fx * gx * gx + fy * fy * gy * gy + fz * fz * gz * gz);
        ASSERT_NEAR(g[static_cast<size_t>(i + d[0] * (j + d[1] * k))], expected, 1e-5)
          << i << " " << j << " " << k;
      }
}

TEST(Volume, NonFiniteVoxelsBecomeTheMinimum)
{
  std::vector<float> v(8, 3.0f);
  v[1] = std::numeric_limits<float>::quiet_NaN();
  v[2] = -1.0f;
  v[5] = std::numeric_limits<float>::infinity();
  const Volume vol({ 2, 2, 2 }, { 0, 0, 0 }, { 1, 1, 1 }, v);
  EXPECT_EQ(vol.nonFiniteCount(), 2);
  EXPECT_EQ(vol.range()[0], -1.0);
  EXPECT_EQ(vol.range()[1], 3.0);
  EXPECT_EQ(vol.at(1, 0, 0), -1.0f);
  std::vector<float> allNaN(8, std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(Volume({ 2, 2, 2 }, { 0, 0, 0 }, { 1, 1, 1 }, allNaN), Error);
}

TEST(Volume, Validation)
{
  EXPECT_THROW(Volume({ 0, 2, 2 }, { 0, 0, 0 }, { 1, 1, 1 }, {}), Error);
  EXPECT_THROW(Volume({ 2, 2, 2 }, { 0, 0, 0 }, { 1, 0, 1 }, std::vector<float>(8)), Error);
  EXPECT_THROW(Volume({ 2, 2, 2 }, { 0, 0, 0 }, { 1, 1, 1 }, std::vector<float>(7)), Error);
}

// 8/16-bit and float32 scalars stay in their own type; copies and RayCasters share them; a
// volume over another owner's memory reads it in place (and copies only to replace non-finite
// values); a value that is not one of the type is refused.
TEST(Volume, KeepsItsScalarsInTheirOwnTypeAndSharesThem)
{
  const Volume vol = linearVolume();
  EXPECT_EQ(vol.storageType(), ScalarType::Int16);
  EXPECT_EQ(vol.scalarBytes(), 2 * vol.voxelCount());
  const void* data = vol.visit([](const auto* p) { return static_cast<const void*>(p); });
  const Volume copy = vol; // NOLINT: the copy is the point
  EXPECT_EQ(copy.visit([](const auto* p) { return static_cast<const void*>(p); }), data);
  EXPECT_FLOAT_EQ(copy.at(1, 2, 3), 2 + 6 + 15);
  const auto floats = vol.floatValues();
  ASSERT_EQ(floats.size(), static_cast<size_t>(vol.voxelCount()));
  EXPECT_FLOAT_EQ(floats[1 + 4 * (2 + 5 * 3)], 2 + 6 + 15);

  for (ScalarType t : { ScalarType::UInt32, ScalarType::Int32, ScalarType::Float64 })
    EXPECT_EQ(storageTypeFor(t), ScalarType::Float32) << scalarTypeName(t);
  EXPECT_EQ(
    Volume({ 2, 1, 1 }, { 0, 0, 0 }, { 1, 1, 1 }, { 1, 70000 }, ScalarType::UInt32).storageType(),
    ScalarType::Float32);
  EXPECT_THROW(
    Volume({ 2, 1, 1 }, { 0, 0, 0 }, { 1, 1, 1 }, { 1, 3.5f }, ScalarType::UInt8), Error);
  EXPECT_THROW(Volume({ 2, 1, 1 }, { 0, 0, 0 }, { 1, 1, 1 }, { 1, 300 }, ScalarType::UInt8), Error);

  auto owned =
    std::make_shared<std::vector<std::uint16_t>>(std::vector<std::uint16_t>{ 5, 9, 7, 1 });
  const Volume shared = Volume::sharing(
    { 2, 2, 1 }, { 0, 0, 0 }, { 1, 1, 1 }, ScalarType::UInt16, owned->data(), owned);
  EXPECT_TRUE(shared.sharesScalars());
  EXPECT_EQ(shared.visit([](const auto* p) { return static_cast<const void*>(p); }),
    static_cast<const void*>(owned->data()));
  EXPECT_EQ(shared.range()[0], 1);
  EXPECT_EQ(shared.range()[1], 9);
  owned.reset(); // the volume keeps the owner alive
  EXPECT_FLOAT_EQ(shared.at(1, 0, 0), 9);

  auto floatsOwned = std::make_shared<std::vector<float>>(
    std::vector<float>{ 2, std::numeric_limits<float>::quiet_NaN(), 4, 3 });
  const Volume cleaned = Volume::sharing(
    { 2, 2, 1 }, { 0, 0, 0 }, { 1, 1, 1 }, ScalarType::Float32, floatsOwned->data(), floatsOwned);
  EXPECT_FALSE(cleaned.sharesScalars()); // copied to replace the NaN
  EXPECT_EQ(cleaned.nonFiniteCount(), 1);
  EXPECT_FLOAT_EQ(cleaned.at(1, 0, 0), 2);
  EXPECT_TRUE(std::isnan((*floatsOwned)[1])); // the owner's memory is not written

  // the gradient range is the maximum of the per-point magnitudes, kept for copies
  const auto g = vol.gradientMagnitude();
  EXPECT_DOUBLE_EQ(vol.gradientMagnitudeRange()[1], *std::max_element(g.begin(), g.end()));
  EXPECT_DOUBLE_EQ(copy.gradientMagnitudeRange()[1], vol.gradientMagnitudeRange()[1]);
}

TEST(VolumeIO, RawJsonPairs)
{
  const std::string dir = ddg::testing::tempDir();
  const std::string raw = dir + "/ddg_small.raw";
  {
    std::ofstream f(raw, std::ios::binary);
    const unsigned short data[8] = { 0, 1, 2, 3, 256, 5, 6, 65535 };
    f.write(reinterpret_cast<const char*>(data), sizeof(data));
  }
  {
    std::ofstream f(dir + "/ddg_small.json");
    f << R"({"dims": [2, 2, 2], "dtype": "uint16", "spacing": [1, 2, 3], "origin": [4, 5, 6]})";
  }
  const Volume v = readRawVolume(dir + "/ddg_small.json");
  EXPECT_EQ(v.originalType(), ScalarType::UInt16);
  EXPECT_EQ(v.at(0, 0, 1), 256.0f);
  EXPECT_EQ(v.range()[1], 65535.0);
  EXPECT_EQ(v.origin()[2], 6.0);
  {
    std::ofstream f(dir + "/ddg_short.json");
    f << R"({"dims": [3, 2, 2], "dtype": "uint16", "file": "ddg_small.raw"})";
  }
  EXPECT_THROW(readRawVolume(dir + "/ddg_short.json"), Error); // size mismatch
  {
    std::ofstream f(dir + "/ddg_bad.json");
    f << R"({"dims": [2, 2], "dtype": "uint16"})";
  }
  EXPECT_THROW(readRawVolume(dir + "/ddg_bad.json"), Error);
  EXPECT_THROW(readRawVolume(dir + "/does_not_exist.json"), Error);
}
