// TestBuildBudget.cxx: a design-space build's budget, input checks and cancel — Core's
// planBuild, designSpaceVolume, checkBuildVolume, checkBuildOutput and buildDesignSpace on a
// synthetic 24^3 volume of nested blobs. Compared: the plan of a larger budget with a smaller
// one (more of everything, estimated total within 95 % + 0.5 s of the budget); the downsampled
// volume with a naive block average (exact to 1e-5); bad volumes and folders with the messages
// the user reads, nothing written; a build cancelled at each stage leaves the folder exactly as
// it was (listing and file contents); a downsampled build's bundle records the original
// volume's fingerprint; the downsampled volume assembled from slabs is designSpaceVolume's, bit
// for bit. No wall-clock assertions (the latency of cancel is measured by
// Testing/Benchmarks/BenchBuildCancel).
#include "Common/FileUtil.h"
#include "Gallery/BuildDesignSpace.h"
#include "Gallery/BundleSession.h"
#include "Gallery/Gallery.h"
#include "Gallery/Outline.h"
#include "Gallery/QueryKey.h"

#include "Design/DesignSpace.h"
#include "Render/RayCaster.h"

#include "FileSizeLimit.h"
#include "TempDir.h"
#include "ThreadWorkers.h"
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sys/stat.h>
#include <unistd.h>

using namespace ddg;
namespace fs = std::filesystem;

namespace
{
Volume blobs(int n = 24)
{
  std::vector<float> v;
  const double c = (n - 1) / 2.0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const double r = std::sqrt((i - c) * (i - c) + (j - c) * (j - c) + (k - c) * (k - c));
        v.push_back(r < n / 5.0 ? 200.0f : (r < n / 2.7 ? 100.0f : 10.0f + (i % 3)));
      }
  return Volume({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::Float32);
}

BuildOptions tiny()
{
  BuildOptions o;
  o.count = 16;
  o.heldout = 4;
  o.size = 16;
  o.iterations = 10;
  o.minutes = 1;
  o.outlineCount = 20;
  o.width = 4;
  o.threads = 1;
  return o;
}

// Every file under `dir` with its contents (the folder "as it was").
std::map<std::string, std::string> snapshot(const fs::path& dir)
{
  std::map<std::string, std::string> files;
  if (!fs::exists(dir))
    return files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
  {
    std::string content;
    if (e.is_regular_file())
    {
      std::ifstream in(e.path(), std::ios::binary);
      content.assign(std::istreambuf_iterator<char>(in), {});
    }
    files[fs::relative(e.path(), dir).string()] = content;
  }
  return files;
}

std::string message(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const Error& e)
  {
    return e.what();
  }
  return "(no error)";
}
} // namespace

TEST(BuildBudget, LargerBudgetsPlanMoreAndFitTheBudget)
{
  const Volume v = blobs();
  const BuildRates rates = measureBuildRates(v, 64, 1);
  const BuildPlan p2 = planBuild(v, 2, 64, 1, rates);
  const BuildPlan p10 = planBuild(v, 10, 64, 1, rates);
  for (const BuildPlan* p : { &p2, &p10 })
  {
    EXPECT_LE(p->totalSeconds, kBuildBudgetShare * 60 * p->budgetMinutes + 0.5) << p->toJson();
    EXPECT_GE(p->trainingSeconds, 0.3 * 60 * p->budgetMinutes) << p->toJson();
    EXPECT_GT(p->rates.exemplarSeconds, 0);
    EXPECT_GT(p->rates.analyzeSeconds, 0);
    EXPECT_GT(p->diskBytes, p->bundleBytes);
    EXPECT_EQ(p->downsample, 1);
    EXPECT_NE(p->describe().find("outline: "), std::string::npos);
  }
  EXPECT_GE(p10.count, p2.count);
  EXPECT_GE(p10.outlineCount, p2.outlineCount);
  EXPECT_GT(p10.trainingMinutes, p2.trainingMinutes);
  EXPECT_NE(message([&] { planBuild(v, 0.5); }).find("at least 1 minute"), std::string::npos);
}

// A budgeted build trains until the plan's end of training: exemplars that took longer than
// estimated shorten the training, faster ones lengthen it, down to half the planned minutes.
TEST(BuildBudget, TrainingEndsWhenThePlanHasItEnd)
{
  const Volume v = blobs();
  const BuildPlan p = planBuild(v, 10, 64, 1, measureBuildRates(v, 64, 1));
  const double asPlanned = p.totalSeconds - p.evaluationSeconds - p.outlineSeconds -
    p.trainingSeconds; // the overhead and the exemplars
  EXPECT_NEAR(p.trainingMinutesAfter(asPlanned), p.trainingMinutes, 1e-9);
  EXPECT_NEAR(p.trainingMinutesAfter(asPlanned + 30), p.trainingMinutes - 0.5, 1e-9);
  EXPECT_NEAR(p.trainingMinutesAfter(asPlanned - 30), p.trainingMinutes + 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(
    p.trainingMinutesAfter(asPlanned + 60 * p.trainingMinutes), 0.5 * p.trainingMinutes);
}

TEST(BuildBudget, DownsamplesLargeVolumesByBlockAverage)
{
  const Volume v = blobs(21);
  int factor = 0;
  const Volume d = designSpaceVolume(v, 1000, &factor);
  EXPECT_EQ(factor, 3); // 21^3 -> 7^3 = 343 <= 1000 (f = 2 gives 11^3 = 1331)
  ASSERT_EQ(d.dims(), (std::array<int, 3>{ 7, 7, 7 }));
  EXPECT_DOUBLE_EQ(d.spacing()[0], 3.0);
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 7; ++i)
      {
        double sum = 0;
        for (int c = 0; c < 3; ++c)
          for (int b = 0; b < 3; ++b)
            for (int a = 0; a < 3; ++a)
              sum += v.at(3 * i + a, 3 * j + b, 3 * k + c);
        EXPECT_NEAR(d.at(i, j, k), sum / 27, 1e-5);
      }
  EXPECT_EQ(designSpaceVolume(v, 1 << 20, &factor).voxelCount(), v.voxelCount());
  EXPECT_EQ(factor, 1);
  // an 8-bit volume stays 8-bit: its averages rounded to the nearest level (a 512^3 uint8
  // volume could not be built before: "value 40.125 is not a uint8")
  std::vector<std::uint8_t> bytes(static_cast<size_t>(v.voxelCount()));
  for (size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<std::uint8_t>(v.value(static_cast<std::int64_t>(i)));
  const Volume u8 =
    Volume::fromVector({ 21, 21, 21 }, { 0, 0, 0 }, { 1, 1, 1 }, bytes, ScalarType::UInt8);
  const Volume d8 = designSpaceVolume(u8, 1000, &factor);
  EXPECT_EQ(factor, 3);
  EXPECT_EQ(d8.originalType(), ScalarType::UInt8);
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 7; ++i)
        EXPECT_NEAR(d8.at(i, j, k), d.at(i, j, k), 0.5 + 1e-4);
}

// The design-space volume of a volume that arrives in slabs (a volume split over MPI ranks
// streams its points to the first rank so): bit for bit designSpaceVolume's, for a float and an
// 8-bit volume, downsampled (factor 3, a last slab of 1 plane) and not (factor 1); slabs out of
// order, not whole blocks or missing are refused.
TEST(BuildBudget, DesignSpaceFromSlabsIsTheWholes)
{
  const Volume f32 = blobs(22);
  std::vector<std::uint8_t> bytes(static_cast<size_t>(f32.voxelCount()));
  for (size_t i = 0; i < bytes.size(); ++i)
    bytes[i] = static_cast<std::uint8_t>(f32.value(static_cast<std::int64_t>(i)) * 1.1);
  const Volume u8 =
    Volume::fromVector({ 22, 22, 22 }, { 1, 2, 3 }, { 0.5, 1, 2 }, bytes, ScalarType::UInt8);
  for (const Volume* v : { &f32, &u8 })
    for (const std::int64_t cap : { std::int64_t(1000), std::int64_t(1) << 20 })
    {
      int factor = 0;
      const Volume whole = designSpaceVolume(*v, cap, &factor);
      DesignSpaceAssembler a(v->dims(), v->origin(), v->spacing(), v->originalType(), cap);
      ASSERT_EQ(a.factor(), factor);
      const int planes = a.slabPlanes(22 * 22 * 7); // 6 (factor 3) or 7 planes a slab
      EXPECT_EQ(planes % factor, 0);
      const std::int64_t plane = 22 * 22;
      std::vector<float> slab;
      for (int z0 = 0; z0 < 22; z0 += planes)
      {
        const int n = std::min(planes, 22 - z0);
        slab.resize(static_cast<size_t>(plane * n));
        for (std::int64_t q = 0; q < plane * n; ++q)
          slab[static_cast<size_t>(q)] = v->value(plane * z0 + q);
        a.add(z0, n, slab.data());
      }
      const DesignSpaceInput in = a.finish("fp");
      EXPECT_EQ(in.factor, factor);
      EXPECT_EQ(in.fingerprint, "fp");
      ASSERT_EQ(in.volume.dims(), whole.dims());
      EXPECT_EQ(in.volume.originalType(), whole.originalType());
      EXPECT_EQ(in.volume.spacing(), whole.spacing());
      EXPECT_EQ(in.volume.origin(), whole.origin());
      EXPECT_EQ(volumeFingerprint(in.volume), volumeFingerprint(whole)); // every value's bits
    }
  DesignSpaceAssembler a(f32.dims(), f32.origin(), f32.spacing(), f32.originalType(), 1000);
  const std::vector<float> slab(22 * 22 * 6, 1.0f);
  EXPECT_THROW(a.add(3, 3, slab.data()), Error); // out of order
  EXPECT_THROW(a.add(0, 4, slab.data()), Error); // not whole blocks of 3 planes
  a.add(0, 6, slab.data());
  EXPECT_NE(message([&] { a.finish(""); }).find("missing planes 6"), std::string::npos);
}

TEST(BuildBudget, RefusesVolumesWithoutADesignSpace)
{
  const Volume constant({ 8, 8, 8 }, { 0, 0, 0 }, { 1, 1, 1 }, std::vector<float>(512, 42.0f));
  EXPECT_NE(message([&] { checkBuildVolume(constant); }).find("one value (42) everywhere"),
    std::string::npos);
  std::vector<float> slab(64 * 64 * 2);
  for (size_t i = 0; i < slab.size(); ++i)
    slab[i] = static_cast<float>(i % 97);
  const Volume thin({ 64, 64, 2 }, { 0, 0, 0 }, { 1, 1, 1 }, slab);
  EXPECT_NE(message([&] { checkBuildVolume(thin); }).find("64x64x2 voxels"), std::string::npos);
  // and buildDesignSpace refuses them before writing anything
  const fs::path dir = fs::path(ddg::testing::tempDir()) / "refused_volume";
  EXPECT_NE(
    message([&] { buildDesignSpace(thin, "", dir.string(), tiny()); }).find("at least 4 voxels"),
    std::string::npos);
  EXPECT_FALSE(fs::exists(dir));
}

TEST(BuildBudget, RefusesFoldersBeforeWriting)
{
  const fs::path root = fs::path(ddg::testing::tempDir()) / "folders";
  fs::create_directories(root / "holds_bundle");
  std::ofstream(root / "holds_bundle" / "bundle.json") << "{\"another\": \"bundle\"}";
  std::ofstream(root / "a_file") << "x";
  const auto before = snapshot(root);
  const Volume v = blobs();
  EXPECT_NE(message([&] { buildDesignSpace(v, "", (root / "holds_bundle").string(), tiny()); })
              .find("already holds a model bundle"),
    std::string::npos);
  EXPECT_NO_THROW(checkBuildOutput((root / "holds_bundle").string(), 1000, true));
  EXPECT_NE(
    message([&] { checkBuildOutput((root / "a_file").string(), 1000, false); }).find("is a file"),
    std::string::npos);
  // more than the disk holds (an exabyte)
  EXPECT_NE(message([&] { checkBuildOutput((root / "new").string(), 1ll << 60, false); })
              .find("not enough free space"),
    std::string::npos);
  EXPECT_EQ(snapshot(root), before);
}

TEST(BuildBudget, RefusesReadOnlyFolders)
{
  const fs::path root = fs::path(ddg::testing::tempDir()) / "folders";
  const Volume v = blobs();
  if (::geteuid() == 0)
    GTEST_SKIP() << "root writes to read-only folders: that case is checked by hand (ro tmpfs)";
  fs::create_directories(root / "read_only");
  ::chmod((root / "read_only").c_str(), 0555);
  EXPECT_NE(message([&] { buildDesignSpace(v, "", (root / "read_only" / "b").string(), tiny()); })
              .find("cannot write in"),
    std::string::npos);
  ::chmod((root / "read_only").c_str(), 0755);
}

TEST(BuildBudget, CancelAtEveryStageLeavesTheFolderAsItWas)
{
  const Volume v = blobs();
  const fs::path root = fs::path(ddg::testing::tempDir()) / "cancel";
  fs::create_directories(root / "existing");
  std::ofstream(root / "existing" / "notes.txt") << "mine";
  for (const std::string stage : { "exemplars", "training", "evaluation", "outline" })
    for (const fs::path& dir : { root / "existing", root / ("new_" + stage) })
    {
      const auto before = snapshot(dir);
      std::set<std::string> seen;
      EXPECT_THROW(buildDesignSpace(v, "", dir.string(), tiny(),
                     [&](const std::string& s, double)
                     {
                       seen.insert(s);
                       return s != stage;
                     }),
        Cancelled)
        << stage;
      EXPECT_TRUE(seen.count(stage)) << stage;
      EXPECT_EQ(snapshot(dir), before) << stage << " in " << dir;
      EXPECT_EQ(fs::exists(dir), !before.empty() || dir == root / "existing");
    }
}

TEST(BuildBudget, BuildsIntoAFolderAndRecordsTheOriginalVolume)
{
  const Volume v = blobs();
  const fs::path dir = fs::path(ddg::testing::tempDir()) / "built";
  fs::create_directories(dir);
  std::ofstream(dir / "notes.txt") << "mine";
  BuildOptions o = tiny();
  o.maxDesignVoxels = 4000; // 24^3 -> 12^3: the design space on a downsampled copy
  std::vector<double> fractions;
  const BuildReport r = buildDesignSpace(v, "", dir.string(), o,
    [&](const std::string&, double f)
    {
      fractions.push_back(f);
      return true;
    });
  EXPECT_EQ(r.plan.downsample, 2);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    names.insert(e.path().filename().string());
  EXPECT_EQ(names,
    (std::set<std::string>{
      "bundle.json", "exemplars.json", "latents.bin", "model.pt", "notes.txt", "outline.bin" }));
  std::ifstream in(dir / "bundle.json");
  EXPECT_EQ(nlohmann::json::parse(in)["volume"].get<std::string>(), volumeFingerprint(v));
  // the same folder again: refused, then replaced when asked
  EXPECT_THROW(buildDesignSpace(v, "", dir.string(), o), Error);
  o.overwrite = true;
  EXPECT_NO_THROW(buildDesignSpace(v, "", dir.string(), o));
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
}

// A build of enough exemplars fits a query key (2 x latent view pairs at least) and the gallery
// opened on the bundle finds nearest designs by it; rebuilt with too few for one, the old key
// (of other weights) goes.
TEST(BuildBudget, WritesAQueryKeyAndDropsAStaleOne)
{
  const Volume v = blobs();
  const fs::path dir = fs::path(ddg::testing::tempDir()) / "keyed";
  BuildOptions o = tiny();
  o.count = 160;
  o.outlineCount = 200;
  const BuildReport built = buildDesignSpace(v, "", dir.string(), o);
  ASSERT_TRUE(fs::exists(queryKeyFile(dir.string()))) << built.queryKeyNote;
  const QueryKey key = readQueryKey(queryKeyFile(dir.string()));
  EXPECT_EQ(key.dim, 64);
  EXPECT_EQ(key.method, "lda"); // under kContrastiveKeyPairs
  EXPECT_EQ(key.components, kQueryKeyComponents);
  EXPECT_GE(key.pairs, 128);
  EXPECT_EQ(built.queryKeyPairs, key.pairs);
  EXPECT_LE(key.pairs, 160);
  const BundleSession session(
    dir.string(), volumeFingerprint(v), std::make_shared<LocalDesignVolume>(v), "");
  EXPECT_EQ(session.gallery().outline().queryKey().layers[0].weights, key.layers[0].weights);
  o.count = 16;
  o.outlineCount = 20;
  o.overwrite = true;
  const BuildReport rebuilt = buildDesignSpace(v, "", dir.string(), o);
  EXPECT_FALSE(fs::exists(queryKeyFile(dir.string())));
  EXPECT_EQ(rebuilt.queryKeyPairs, 0);
  EXPECT_NE(rebuilt.queryKeyNote.find("too few exemplars"), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "bundle.json"));
}

// From kContrastiveKeyPairs usable pairs the build's key is the contrastive network.
TEST(BuildBudget, FitsTheContrastiveKeyFromEnoughPairs)
{
  const Volume v = blobs();
  const fs::path dir = fs::path(ddg::testing::tempDir()) / "keyed_contrastive";
  fs::remove_all(dir);
  BuildOptions o = tiny();
  o.count = kContrastiveKeyPairs + 200;
  o.outlineCount = o.count;
  const BuildReport built = buildDesignSpace(v, "", dir.string(), o);
  ASSERT_TRUE(fs::exists(queryKeyFile(dir.string()))) << built.queryKeyNote;
  const QueryKey key = readQueryKey(queryKeyFile(dir.string()));
  EXPECT_EQ(key.method, "contrastive");
  EXPECT_EQ(key.components, ContrastiveKeyOptions{}.components);
  EXPECT_GE(key.pairs, kContrastiveKeyPairs);
  EXPECT_EQ(built.queryKeyPairs, key.pairs);
  fs::remove_all(dir);
}

// A build whose exemplars and outline designs are rendered in shares by workers (other
// processes under MPI; threads here) writes the same bundle: the training exemplars' designs, the
// training latents and the outline, byte for byte.
TEST(BuildBudget, WorkersBuildTheSameBundle)
{
  const Volume v = blobs();
  const fs::path alone = fs::path(ddg::testing::tempDir()) / "built_alone";
  const fs::path shared = fs::path(ddg::testing::tempDir()) / "built_shared";
  fs::remove_all(alone);
  fs::remove_all(shared);
  BuildOptions o = tiny();
  const BuildReport a = buildDesignSpace(v, "", alone.string(), o);
  EXPECT_EQ(a.workerCandidates, 0);
  ddg::testing::ThreadWorkers workers(v, 2);
  o.workers = &workers;
  const BuildReport b = buildDesignSpace(v, "", shared.string(), o);
  EXPECT_GT(b.workerCandidates, 0);
  EXPECT_GE(workers.Messages, 2 * 3); // each: three setups (training, held-out, outline) at least
  for (const char* f : { "exemplars.json", "latents.bin", "outline.bin" })
  {
    const std::string own = readTextFile((alone / f).string(), "bundle file");
    EXPECT_FALSE(own.empty()) << f;
    EXPECT_EQ(own, readTextFile((shared / f).string(), "bundle file"))
      << f << " differs with workers";
  }
  EXPECT_DOUBLE_EQ(a.evaluation.psnr, b.evaluation.psnr);
}

// The outline's first designs are the training exemplars: the build analyses the images it trained
// on instead of rendering those designs again (workers get no outline request when the outline is
// no larger than the training set). Indices as buildOutlineLatents draws them, latents as its
// renders give them up to the images' 8-bit rounding; an outline larger than the training set
// goes on with rendered designs after the last exemplar.
TEST(BuildBudget, TheOutlineAnalysesTheTrainingExemplarsWithoutRenderingThem)
{
  const Volume v = blobs();
  for (const int outline : { 12, 20 }) // the training set: 16
  {
    const fs::path dir =
      fs::path(ddg::testing::tempDir()) / ("built_outline_" + std::to_string(outline));
    fs::remove_all(dir);
    BuildOptions o = tiny();
    o.outlineCount = outline;
    ddg::testing::ThreadWorkers workers(v, 2);
    o.workers = &workers;
    const BuildReport r = buildDesignSpace(v, "", dir.string(), o);
    EXPECT_EQ(workers.OutlineRequests > 0, outline > o.count) << outline;
    const LatentSet built = readLatentSet(outlineFile(dir.string()));
    const NeuralDesignModel model = NeuralDesignModel::loadBundle(dir.string());
    const LatentSet rendered = buildOutlineLatents(model, v, outline, o.seed, 0, 1, {}, o.screen);
    ASSERT_EQ(built.indices, rendered.indices) << outline;
    ASSERT_EQ(built.values.size(), rendered.values.size());
    double scale = 0, most = 0;
    for (size_t i = 0; i < built.values.size(); ++i)
    {
      scale = std::max(scale, static_cast<double>(std::abs(rendered.values[i])));
      most = std::max(most, static_cast<double>(std::abs(built.values[i] - rendered.values[i])));
    }
    EXPECT_GT(scale, 0.0);
    EXPECT_LT(most, 0.005 * scale) << outline; // 8-bit images against float renders (~4e-4)
    std::printf("outline %d: largest latent difference %.2g of %.2g\n", outline, most, scale);
    EXPECT_GT(r.totalSeconds, 0.0);
  }
}

TEST(BuildBudget, AFullDiskDuringTheBuildLeavesTheFolderAsItWas)
{
  // the free-space check passes (the disk is not full yet), then files cannot grow past 20 KB:
  // the first exemplar shard fails to be written
  const Volume v = blobs();
  const fs::path dir = fs::path(ddg::testing::tempDir()) / "full_disk";
  fs::create_directories(dir);
  std::ofstream(dir / "notes.txt") << "mine";
  const auto before = snapshot(dir);
  std::string what;
  {
    FileSizeLimit full(20 * 1024);
    what = message([&] { buildDesignSpace(v, "", dir.string(), tiny()); });
  }
  EXPECT_NE(what, "(no error)");
  EXPECT_EQ(snapshot(dir), before) << what;
}
