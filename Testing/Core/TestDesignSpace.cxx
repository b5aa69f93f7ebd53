// TestDesignSpace.cxx: feature regions on a volume with known materials, spec JSON errors,
// deterministic generation, and datasets that are truncated, corrupt or cancelled.
#include "Design/ExemplarGenerator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

using namespace ddg;
namespace fs = std::filesystem;

namespace
{
// Air (value 10, most voxels) around two nested materials at 100 and 200, with noise.
Volume materials()
{
  const int n = 32;
  std::mt19937 rng(1);
  std::normal_distribution<float> noise(0.0f, 3.0f);
  std::vector<float> v;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const double r =
          std::sqrt((i - 15.5) * (i - 15.5) + (j - 15.5) * (j - 15.5) + (k - 15.5) * (k - 15.5));
        const float base = r < 6 ? 200.0f : (r < 11 ? 100.0f : 10.0f);
        v.push_back(std::clamp(base + noise(rng), 0.0f, 255.0f));
      }
  return Volume({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::Float32);
}

std::string tempDir(const std::string& name)
{
  const std::string d = ::testing::TempDir() + "/ddg_" + name;
  fs::remove_all(d);
  return d;
}
} // namespace

TEST(DesignSpace, FindsMaterialsNotAir)
{
  const auto regions = findFeatureRegions(materials());
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_NEAR(regions[0].peak, 100.0, 6.0);
  EXPECT_NEAR(regions[1].peak, 200.0, 6.0);
  EXPECT_GT(regions[0].lo, 10.0); // air excluded
}

TEST(DesignSpace, SpecJsonDefaultsAndErrors)
{
  const auto s = parseDesignSpaceSpec("{}");
  EXPECT_EQ(s.maxRegions, 4);
  const auto again = parseDesignSpaceSpec(designSpaceSpecToJson(s));
  EXPECT_EQ(again.opacity, s.opacity);
  EXPECT_THROW(parseDesignSpaceSpec("{"), Error);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"opacity": [0.5, 0.2]})"), Error);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"max_regions": 0})"), Error);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"colour": 1})"), Error); // unknown key
  EXPECT_THROW(parseDesignSpaceSpec(R"({"regions": [{"lo": 5, "hi": 1}]})"), Error);
}

TEST(ExemplarGenerator, DeterministicReadableAndGuarded)
{
  const Volume vol = materials();
  GenerateOptions opt;
  opt.count = 10;
  opt.size = 16;
  opt.shardSize = 4;
  const std::string a = tempDir("gen_a"), b = tempDir("gen_b");
  generateExemplars(vol, DesignSpaceSpec{}, a, opt);
  opt.threads = 1;
  generateExemplars(vol, DesignSpaceSpec{}, b, opt);
  for (const char* f : { "shard-00000.bin", "shard-00002.bin", "dataset.json" })
  {
    std::ifstream fa(a + "/" + f, std::ios::binary), fb(b + "/" + f, std::ios::binary);
    const std::string ca((std::istreambuf_iterator<char>(fa)), {}),
      cb((std::istreambuf_iterator<char>(fb)), {});
    EXPECT_FALSE(ca.empty());
    EXPECT_EQ(ca, cb) << f << " differs between runs (threads 0 vs 1)";
  }
  const ExemplarDataset data(a);
  EXPECT_EQ(data.count(), 10);
  std::vector<std::uint8_t> rgb, vp, gt;
  data.load(9, rgb, vp, gt);
  EXPECT_EQ(gt.size(), 16u * 16u * 4u);
  int visible = 0;
  for (size_t i = 3; i < gt.size(); i += 4)
    visible += gt[i] > 0;
  EXPECT_GT(visible, 0);

  // truncated shard, corrupt index, missing index (an incomplete dataset)
  fs::resize_file(a + "/shard-00001.bin", 100);
  EXPECT_THROW(ExemplarDataset{ a }, Error);
  {
    std::ofstream(b + "/dataset.json") << "{\"format\": \"ddg-exem";
  }
  EXPECT_THROW(ExemplarDataset{ b }, Error);

  // cancelled: nothing left that looks like a dataset
  const std::string c = tempDir("gen_c");
  EXPECT_THROW(
    generateExemplars(vol, DesignSpaceSpec{}, c, opt, [](double) { return false; }), Cancelled);
  EXPECT_FALSE(fs::exists(c + "/dataset.json"));
  EXPECT_FALSE(fs::exists(c + "/shard-00000.bin"));
  // an unwritable place
  EXPECT_THROW(generateExemplars(vol, DesignSpaceSpec{}, "/proc/ddg_no_such_dir", opt), Error);
}
