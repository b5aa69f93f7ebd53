// TestDesignSpace.cxx: feature regions on a volume with known materials, spec JSON errors,
// deterministic generation (alone and with workers rendering shares), datasets that are truncated,
// corrupt, cancelled or hit a full disk, and the decoder layout (targets round trip; image-loss
// gradient against finite differences).
#include "Common/FileUtil.h"
#include "Design/DecoderLayout.h"
#include "Design/ExemplarGenerator.h"

#include "TempDir.h"
#include "ThreadWorkers.h"
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <filesystem>
#include <fstream>
#include <random>

#include "FileSizeLimit.h"

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
  const std::string d = ddg::testing::tempDir() + "/ddg_" + name;
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

TEST(DesignSpace, LitExemplars)
{
  // "lighting" and "lit_fraction": round trip, errors, and the exemplars' views
  const auto s = parseDesignSpaceSpec(
    R"({"lighting": {"shade": true, "specular": 0.5, "specular_power": 30}, "lit_fraction": 0.5})");
  EXPECT_TRUE(s.lighting.shade);
  EXPECT_EQ(s.lighting.specularPower, 30);
  const auto again = parseDesignSpaceSpec(designSpaceSpecToJson(s));
  EXPECT_EQ(again.lighting, s.lighting);
  EXPECT_EQ(again.litFraction, 0.5);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"lighting": {"shade": true, "specular": 2}})"), Error);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"lighting": {"shine": 1}})"), Error);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"lit_fraction": 1.5})"), Error);

  const Volume vol = materials();
  const auto regions = findFeatureRegions(vol);
  int lit = 0;
  for (std::uint64_t i = 0; i < 200; ++i)
  {
    const Exemplar e = sampleExemplar(vol, s, regions, 7, i, 16);
    EXPECT_EQ(e.viewExp.lighting, e.viewView.lighting);
    if (e.viewExp.lighting.shade)
    {
      EXPECT_EQ(e.viewExp.lighting, s.lighting);
      ++lit;
    }
    // an unlit spec's exemplars are the lit spec's, lighting aside (the lit draw comes last)
    const Exemplar u = sampleExemplar(vol, DesignSpaceSpec{}, regions, 7, i, 16);
    EXPECT_FALSE(u.viewExp.lighting.shade);
    EXPECT_EQ(u.active, e.active);
    EXPECT_EQ(u.viewView.camera.position, e.viewView.camera.position);
    EXPECT_EQ(u.primitives.front().rgb, e.primitives.front().rgb);
  }
  EXPECT_GT(lit, 70); // about half of 200
  EXPECT_LT(lit, 130);

  // a lit exemplar renders lit: its RGB differs from the same design unlit
  GenerateOptions opt;
  opt.count = 8;
  opt.size = 24;
  DesignSpaceSpec all = s;
  all.litFraction = 1;
  const std::string a = tempDir("gen_lit"), b = tempDir("gen_unlit");
  generateExemplars(vol, all, a, opt);
  generateExemplars(vol, DesignSpaceSpec{}, b, opt);
  const ExemplarDataset la(a), lb(b);
  EXPECT_TRUE(la.exemplars()[0].viewExp.lighting.shade); // read back from the index
  std::vector<std::uint8_t> rgbA, vpA, gtA, rgbB, vpB, gtB;
  double diff = 0;
  for (int i = 0; i < 8; ++i)
  {
    la.load(i, rgbA, vpA, gtA);
    lb.load(i, rgbB, vpB, gtB);
    for (size_t k = 0; k < rgbA.size(); ++k)
      diff += std::abs(static_cast<int>(rgbA[k]) - static_cast<int>(rgbB[k]));
  }
  EXPECT_GT(diff, 0.0);
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

TEST(ExemplarGenerator, WithoutViewportTheSameImagesForTheDecoder)
{
  const Volume vol = materials();
  GenerateOptions opt;
  opt.count = 6;
  opt.size = 16;
  const std::string a = tempDir("gen_vp"), b = tempDir("gen_novp");
  generateExemplars(vol, DesignSpaceSpec{}, a, opt);
  opt.viewport = false;
  generateExemplars(vol, DesignSpaceSpec{}, b, opt);
  const ExemplarDataset with(a), without(b);
  EXPECT_TRUE(with.hasViewport());
  EXPECT_FALSE(without.hasViewport());
  ASSERT_EQ(without.count(), 6);
  int viewportPixels = 0;
  for (int i = 0; i < 6; ++i)
  {
    std::vector<std::uint8_t> rgb1, vp1, gt1, rgb2, vp2, gt2;
    with.load(i, rgb1, vp1, gt1);
    without.load(i, rgb2, vp2, gt2);
    EXPECT_EQ(rgb1, rgb2) << "exemplar " << i;
    EXPECT_EQ(gt1, gt2) << "exemplar " << i;
    for (size_t p = 0; p < vp1.size(); ++p)
    {
      viewportPixels += vp1[p] > 0;
      ASSERT_EQ(vp2[p], 0);
    }
    EXPECT_EQ(with.exemplars()[static_cast<size_t>(i)].viewView.width,
      without.exemplars()[static_cast<size_t>(i)].viewView.width);
  }
  EXPECT_GT(viewportPixels, 0); // the viewport images that were left out are not empty
}

namespace
{
std::string fileText(const std::string& path)
{
  return readTextFile(path, "dataset file");
}
} // namespace

// Exemplars rendered in shares by other processes (here: threads serving as they would) are the
// same dataset, byte for byte, as one process's: screened (batches sized by the pass rate, junk
// passed over) and not, 1D and 2D, with users' pictures. A worker answers a message it cannot
// serve (before its setup, unreadable) with its reason; one that holds another volume refuses
// the setup, and the generation fails with that reason.
TEST(ExemplarGenerator, WorkersRenderTheSameDataset)
{
  const Volume vol = materials();
  for (const int dimensions : { 1, 2 })
    for (const bool screen : { false, true })
    {
      DesignSpaceSpec spec;
      spec.dimensions = dimensions;
      spec.pictureFraction = 0.3;
      GenerateOptions opt;
      opt.count = 11;
      opt.size = 16;
      opt.shardSize = 4;
      opt.screen = screen;
      const std::string name = "gen_workers_" + std::to_string(dimensions) + (screen ? "s" : "");
      const std::string alone = tempDir(name + "_alone"), shared = tempDir(name + "_shared");
      generateExemplars(vol, spec, alone, opt);
      ddg::testing::ThreadWorkers workers(vol, 2);
      opt.workers = &workers;
      generateExemplars(vol, spec, shared, opt);
      EXPECT_GE(workers.Messages, 2 * 4); // a setup and at least 3 batches each
      for (const char* f :
        { "shard-00000.bin", "shard-00001.bin", "shard-00002.bin", "dataset.json" })
      {
        const std::string a = fileText(alone + "/" + f);
        EXPECT_FALSE(a.empty()) << f;
        EXPECT_EQ(a, fileText(shared + "/" + f)) << f << " differs with workers (" << name << ")";
      }
    }
  // a worker answers what it cannot do with its reason and goes on serving
  std::deque<std::string> in{ "exemplars 0 1 0", "outline 0 x", "end" };
  std::vector<std::string> out;
  serveExemplars(
    vol,
    [&in]
    {
      std::string m = in.front();
      in.pop_front();
      return m;
    },
    [&out](const std::string& m) { out.push_back(m); });
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].rfind("error ", 0), 0u);
  EXPECT_NE(out[0].find("before its setup"), std::string::npos);
  EXPECT_EQ(out[1].rfind("error ", 0), 0u);
  // a worker holding another volume refuses the setup: the generation fails with its reason
  std::vector<float> other(static_cast<size_t>(vol.voxelCount()), 5.0f);
  other[0] = 1.0f;
  const Volume otherVolume(vol.dims(), vol.origin(), vol.spacing(), other);
  ddg::testing::ThreadWorkers wrong(otherVolume, 1);
  GenerateOptions opt;
  opt.count = 4;
  opt.size = 16;
  opt.workers = &wrong;
  try
  {
    generateExemplars(vol, DesignSpaceSpec{}, tempDir("gen_wrong_worker"), opt);
    ADD_FAILURE() << "a worker with another volume was used";
  }
  catch (const Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("is not the first process's"), std::string::npos)
      << e.what();
  }
}

TEST(ExemplarGenerator, FullDiskLeavesNothingThatLooksValid)
{
  const Volume vol = materials();
  GenerateOptions opt;
  opt.count = 10;
  opt.size = 16;
  opt.shardSize = 1;
  const std::string ok = tempDir("gen_full_ok");
  generateExemplars(vol, DesignSpaceSpec{}, ok, opt);
  const auto shard = fs::file_size(ok + "/shard-00000.bin");
  const auto index = fs::file_size(ok + "/dataset.json");
  ASSERT_GT(index, shard); // so that a limit of one shard's size fails at the index
  auto temporaries = [](const std::string& dir)
  {
    int n = 0;
    for (const auto& f : fs::directory_iterator(dir))
      n += f.path().filename().string().find(".tmp") != std::string::npos;
    return n;
  };
  // the disk fills up while writing the first shard, then while writing the index (into the
  // directory of the earlier, complete dataset: it is replaced, not left describing new shards)
  for (const auto limit : { shard - 1, shard })
  {
    const std::string dir = tempDir("gen_full_" + std::to_string(limit));
    fs::copy(ok, dir);
    {
      FileSizeLimit full(limit);
      try
      {
        generateExemplars(vol, DesignSpaceSpec{}, dir, opt);
        ADD_FAILURE() << "generation into a full disk did not fail";
      }
      catch (const Error& e)
      {
        EXPECT_NE(std::string(e.what()).find("disk full"), std::string::npos) << e.what();
      }
    }
    EXPECT_FALSE(fs::exists(dir + "/dataset.json"));
    EXPECT_THROW(ExemplarDataset{ dir }, Error);
    EXPECT_EQ(temporaries(dir), 0) << "temporary files left in " << dir;
  }
}

TEST(DecoderLayout, TargetsDecodeBackToTheExemplar)
{
  const Volume vol = materials();
  DecoderLayout layout{ findFeatureRegions(vol), DesignSpaceSpec{} };
  for (std::uint64_t index = 0; index < 20; ++index)
  {
    const Exemplar e = sampleExemplar(vol, layout.spec, layout.regions, 3, index, 16);
    auto t = layout.targets(e);
    for (size_t k = 0; k < t.size(); k += layout.outputs())
      t[k] = t[k] > 0.5f ? 40.0f : -40.0f; // activity probability -> a decisive logit
    const auto prims = layout.decode(t.data());
    ASSERT_EQ(prims.size(), e.primitives.size());
    for (size_t q = 0; q < prims.size(); ++q)
    {
      EXPECT_NEAR(prims[q].mean[0], e.primitives[q].mean[0], 1e-4);
      EXPECT_NEAR(prims[q].stddev[0], e.primitives[q].stddev[0], 1e-4);
      EXPECT_NEAR(prims[q].opacity, e.primitives[q].opacity, 1e-6);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(prims[q].rgb[c], e.primitives[q].rgb[c], 1e-6);
    }
  }
}

// The decoder's image loss: its gradient through the ray caster's adjoint, the rasterization
// adjoint and the output squashing, against central differences of the loss (double renderer,
// h = 2e-4 on float outputs; tolerance 0.2 % of the largest derivative + 2 % relative, for the
// L1 kinks), for 1D and 2D design spaces.
void checkImageLossGradient(int dimensions, double sampleScale = 1.0)
{
  const Volume vol = materials();
  DecoderLayout layout;
  layout.spec.dimensions = dimensions;
  layout.regions = dimensions == 2 ? findFeatureRegions2D(vol) : findFeatureRegions(vol);
  if (dimensions == 2)
    layout.gradientRange = vol.gradientMagnitudeRange();
  const DifferentiableRendererT<double> renderer(vol);
  const Exemplar truthDesign = sampleExemplar(vol, layout.spec, layout.regions, 5, 1, 16);
  const View& view = truthDesign.viewView;
  const Image truthImage =
    renderDesign(renderer.caster(), truthDesign.primitives, dimensions, layout.gradientRange, view);
  std::vector<std::uint8_t> truth(truthImage.pixels.size());
  for (size_t k = 0; k < truth.size(); ++k)
    truth[k] =
      static_cast<std::uint8_t>(std::lround(std::clamp(truthImage.pixels[k], 0.0f, 1.0f) * 255));
  std::vector<int> pixels;
  for (int p = 0; p < view.width * view.height; ++p)
    pixels.push_back(p);

  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.1f, 0.9f);
  const int m = layout.outputs();
  std::vector<float> o(static_cast<size_t>(layout.size()));
  for (size_t k = 0; k < o.size(); ++k)
  {
    const int c = static_cast<int>(k % m);
    o[k] = c == 0 ? 4 * u(rng) - 2 : (c == 1 || c == 7 ? 2 * u(rng) - 1 : u(rng));
  }
  std::vector<float> grad(o.size()), scratch(o.size());
  const double loss =
    layout.imageLoss(renderer, o.data(), view, truth.data(), pixels, grad.data(), sampleScale);
  EXPECT_GT(loss, 0.0);
  if (sampleScale != 1.0) // the coarser step is taken: another loss, close to the fine one's
  {
    const double fine =
      layout.imageLoss(renderer, o.data(), view, truth.data(), pixels, scratch.data());
    EXPECT_NE(loss, fine);
    EXPECT_NEAR(loss, fine, 0.1 * fine);
  }
  std::vector<double> fd(o.size());
  for (size_t k = 0; k < o.size(); ++k)
  {
    const float h = 2e-4f;
    auto at = [&](float delta)
    {
      auto q = o;
      q[k] += delta;
      return layout.imageLoss(
        renderer, q.data(), view, truth.data(), pixels, scratch.data(), sampleScale);
    };
    fd[k] = (at(h) - at(-h)) / (2.0 * h);
  }
  double largest = 0, largestGradient = 0;
  for (size_t k = 0; k < o.size(); ++k)
  {
    largest = std::max(largest, std::abs(fd[k]));
    if (k % m >= 7)
      largestGradient = std::max(largestGradient, std::abs(fd[k]));
  }
  for (size_t k = 0; k < o.size(); ++k)
    EXPECT_NEAR(grad[k], fd[k], 2e-3 * largest + 0.02 * std::abs(fd[k]))
      << "output " << k << " (" << k % m << ")";
  EXPECT_GT(largest, 1e-3); // the check is not vacuous
  if (dimensions == 2)
    EXPECT_GT(largestGradient, 20 * 2e-3 * largest); // nor along gradient magnitude
}

TEST(DecoderLayout, ImageLossGradientMatchesFiniteDifferences)
{
  checkImageLossGradient(1);
}

TEST(DecoderLayout, ImageLossGradientMatchesFiniteDifferences2D)
{
  checkImageLossGradient(2);
}

// A training's image loss can sample every 2 x ParaView's step (--image-sample-scale): its
// adjoint is checked alike.
TEST(DecoderLayout, ImageLossAtACoarserStepMatchesFiniteDifferences)
{
  checkImageLossGradient(1, 2.0);
}

TEST(DesignSpace, FindsMaterialsAndBoundariesIn2D)
{
  const auto regions = findFeatureRegions2D(materials());
  ASSERT_GE(regions.size(), 2u);
  const auto gmax = materials().gradientMagnitudeRange()[1];
  int materialsFound = 0, boundaries = 0;
  for (const auto& r : regions)
  {
    EXPECT_TRUE(r.twoD());
    EXPECT_GT(r.peak, 30.0) << "air is excluded";
    if (r.gradientPeak < 0.2 * gmax && (std::abs(r.peak - 100) < 8 || std::abs(r.peak - 200) < 8))
      ++materialsFound;
    if (r.gradientPeak > 0.3 * gmax)
      ++boundaries;
  }
  EXPECT_EQ(materialsFound, 2) << "both materials at low gradient magnitude";
  EXPECT_GE(boundaries, 1) << "a boundary at high gradient magnitude";
  // a 2D spec generates 2D exemplars; spec errors name the key
  DesignSpaceSpec spec;
  spec.dimensions = 2;
  const Exemplar e = sampleExemplar(materials(), spec, regions, 1, 0, 16);
  for (const auto& g : e.primitives)
    EXPECT_GT(g.stddev[1], 0.0);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"dimensions": 3})"), Error);
  EXPECT_THROW(
    parseDesignSpaceSpec(R"({"dimensions": 2, "regions": [{"lo": 1, "hi": 5}]})"), Error);
  const auto custom = parseDesignSpaceSpec(
    R"({"dimensions": 2, "regions": [{"lo": 1, "hi": 5, "gradient_lo": 0, "gradient_hi": 3}]})");
  EXPECT_DOUBLE_EQ(custom.regions[0].gradientPeak, 1.5);
}

TEST(DesignSpace, FingerprintInWords)
{
  EXPECT_EQ(
    describeFingerprint(volumeFingerprint(materials())),
    "32 x 32 x 32 voxels, values " +
      []
      {
        char b[64];
        const auto r = materials().range();
        std::snprintf(b, sizeof(b), "%.6g to %.6g", r[0], r[1]);
        return std::string(b);
      }());
  EXPECT_EQ(describeFingerprint("64x64x93 spacing 3.2,3.2,1.5 range -1024..3071 fnv1a 00ff"),
    "64 x 64 x 93 voxels, values -1024 to 3071");
  EXPECT_EQ(describeFingerprint("garbage"), "an unknown volume");
}

// The fingerprint fed in parts (a volume split over ranks streams its planes) is the whole's,
// and its text is the one bundles record (pinned: FNV-1a over the float bits, computed apart).
TEST(DesignSpace, FingerprintFedInPartsIsTheWholes)
{
  std::vector<float> v;
  for (int i = 0; i < 12; ++i)
    v.push_back(0.5f * static_cast<float>(i));
  const Volume small({ 3, 2, 2 }, { 0, 0, 0 }, { 1, 2, 0.5 }, v, ScalarType::Float32);
  EXPECT_EQ(volumeFingerprint(small), "3x2x2 spacing 1,2,0.5 range 0..5.5 fnv1a f4cd8a25a05bf89a");
  VolumeHash parts;
  parts.add(v.data(), 5);
  parts.add(v.data() + 5, 0);
  parts.add(v.data() + 5, 7);
  EXPECT_EQ(volumeFingerprint(small.dims(), small.spacing(), small.range(), parts.value()),
    volumeFingerprint(small));
  const Volume big = materials(); // over the 4096-value chunks of the whole's own pass
  VolumeHash planes;
  std::vector<float> plane(32 * 32);
  big.visit(
    [&](const auto* p)
    {
      for (int k = 0; k < 32; ++k)
      {
        for (int q = 0; q < 32 * 32; ++q)
          plane[static_cast<size_t>(q)] = static_cast<float>(p[k * 32 * 32 + q]);
        planes.add(plane.data(), 32 * 32);
      }
    });
  EXPECT_EQ(volumeFingerprint(big.dims(), big.spacing(), big.range(), planes.value()),
    volumeFingerprint(big));
}
