// TestKindNetwork.cxx: the kind network on two tiny synthetic volumes — training refuses what it
// cannot use, the files round-trip exactly and bad ones are refused naming the directory, the
// probabilities are the same for every flip and quarter turn of a picture (the 8-fold average),
// the Bhattacharyya coefficient, the reference leaves no temporary files, and the check's
// verdict follows the threshold. Tolerances: exact for round trips; 1e-5 for the symmetry
// (float sums in another order).
#include "Neural/KindNetwork.h"

#include "Common/Error.h"
#include "Design/ExemplarGenerator.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include "TempDir.h"
#include "TestVolumes.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numeric>

using namespace ddg;
namespace fs = std::filesystem;

namespace
{
// A ball in a shell (kind 0) or three bars (kind 1).
Volume synthetic(int kind)
{
  if (kind == 0)
    return ddg::testing::ballInShell();
  return ddg::testing::gridVolume(24, ScalarType::Float32,
    [](double, int i, int j, int k)
    {
      const bool bar = (std::abs(i - 6) < 2 || std::abs(i - 17) < 2) && std::abs(k - 12) < 8;
      return bar ? 180.0 : (std::abs(j - 12) < 2 ? 90.0 : 10.0);
    });
}

DesignSpaceSpec pictureSpec()
{
  DesignSpaceSpec s;
  s.pictureFraction = 0.5;
  return s;
}

std::string dataset(int kind, int size = 16)
{
  const std::string d =
    ddg::testing::tempDir() + "/kind_data_" + std::to_string(kind) + "_" + std::to_string(size);
  if (!fs::exists(d + "/dataset.json"))
  {
    GenerateOptions opt;
    opt.count = 32;
    opt.size = size;
    opt.seed = 3 + kind;
    opt.viewport = false;
    opt.threads = 1;
    generateExemplars(synthetic(kind), pictureSpec(), d, opt);
  }
  return d;
}

KindTrainOptions quick()
{
  KindTrainOptions o;
  o.epochs = 2;
  o.batch = 16;
  o.threads = 1;
  return o;
}

const KindNetwork& trained()
{
  static const KindNetwork net =
    KindNetwork::train({ "ball", "bars" }, { dataset(0), dataset(1) }, quick());
  return net;
}

Image turned(const Image& im) // a quarter turn
{
  Image out(im.height, im.width, im.channels);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      for (int c = 0; c < im.channels; ++c)
        out.pixels[(static_cast<size_t>(im.width - 1 - x) * out.width + y) * im.channels + c] =
          im.pixels[(static_cast<size_t>(y) * im.width + x) * im.channels + c];
  return out;
}

Image mirrored(const Image& im)
{
  Image out(im.width, im.height, im.channels);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      for (int c = 0; c < im.channels; ++c)
        out.pixels[(static_cast<size_t>(y) * im.width + (im.width - 1 - x)) * im.channels + c] =
          im.pixels[(static_cast<size_t>(y) * im.width + x) * im.channels + c];
  return out;
}
} // namespace

TEST(KindNetwork, TrainingRefusesWhatItCannotUse)
{
  EXPECT_THROW(KindNetwork::train({ "ball" }, { dataset(0) }, quick()), Error);
  EXPECT_THROW(KindNetwork::train({ "ball", "ball" }, { dataset(0), dataset(1) }, quick()), Error);
  try
  {
    KindNetwork::train({ "ball", "bars" }, { dataset(0), dataset(1, 24) }, quick());
    FAIL() << "datasets of two sizes were accepted";
  }
  catch (const Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("another image size or spec"), std::string::npos);
  }
}

TEST(KindNetwork, ProbabilitiesAreTheSameForEveryFlipAndTurn)
{
  const KindNetwork& net = trained();
  EXPECT_EQ(net.kinds(), (std::vector<std::string>{ "ball", "bars" }));
  EXPECT_EQ(net.imageSize(), 16);
  const ExemplarDataset ds(dataset(1));
  const Image im = ds.images(5).rgbExp;
  const auto p = net.meanProbabilities({ im });
  ASSERT_EQ(p.size(), 2u);
  EXPECT_NEAR(p[0] + p[1], 1.0, 1e-5);
  for (const Image& other : { turned(im), turned(turned(im)), mirrored(im), mirrored(turned(im)) })
  {
    const auto q = net.meanProbabilities({ other });
    EXPECT_NEAR(q[0], p[0], 1e-5);
  }
  // a picture is framed as a query frames it; an image of another size is refused as input
  EXPECT_THROW(net.meanProbabilities({ Image(20, 20, 3) }), Error);
  EXPECT_NO_THROW(net.pictureProbabilities(ds.images(6).rgbExp));
}

TEST(KindNetwork, FilesRoundTripAndBadOnesAreRefused)
{
  KindNetwork net = KindNetwork::train({ "ball", "bars" }, { dataset(0), dataset(1) }, quick());
  net.setThreshold(0.42);
  EXPECT_THROW(net.setThreshold(1.5), Error);
  const std::string dir = ddg::testing::tempDir() + "/kind_net";
  net.save(dir);
  const KindNetwork back = KindNetwork::load(dir);
  EXPECT_EQ(back.kinds(), net.kinds());
  EXPECT_EQ(back.threshold(), 0.42);
  EXPECT_EQ(back.referenceCount(), net.referenceCount());
  EXPECT_NE(back.trainingRecord().find("validation_accuracy"), std::string::npos);
  const ExemplarDataset ds(dataset(0));
  std::vector<Image> images;
  for (int i = 0; i < 8; ++i)
    images.push_back(ds.images(i).rgbExp);
  EXPECT_EQ(back.meanProbabilities(images), net.meanProbabilities(images));

  auto refused = [](const std::string& d, const std::string& words)
  {
    try
    {
      KindNetwork::load(d);
      ADD_FAILURE() << "loaded " << d;
    }
    catch (const Error& e)
    {
      const std::string m = e.what();
      EXPECT_NE(m.find(d), std::string::npos) << m;
      EXPECT_NE(m.find(words), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  };
  refused(dir + "/nowhere", "has no kind.json");
  const std::string bad = ddg::testing::tempDir() + "/kind_bad";
  fs::create_directories(bad);
  fs::copy_file(dir + "/kind.json", bad + "/kind.json", fs::copy_options::overwrite_existing);
  std::ofstream(bad + "/kind.pt") << "not weights";
  refused(bad, "missing or corrupt");
  std::ofstream(bad + "/kind.json") << R"({"format": "ddg-exemplars", "version": 1})";
  refused(bad, "not a kind network");
}

TEST(KindNetwork, BhattacharyyaCoefficient)
{
  EXPECT_NEAR(bhattacharyya({ 0.2, 0.8 }, { 0.2, 0.8 }), 1.0, 1e-12);
  EXPECT_NEAR(bhattacharyya({ 1, 0 }, { 0, 1 }), 0.0, 1e-12);
  EXPECT_NEAR(bhattacharyya({ 0.5, 0.5 }, { 1, 0 }), std::sqrt(0.5), 1e-12);
  EXPECT_THROW(bhattacharyya({ 1 }, { 0.5, 0.5 }), Error);
}

TEST(KindNetwork, TheReferenceCancelsAndLeavesNoFilesAndTheVerdictFollowsTheThreshold)
{
  KindNetwork net = KindNetwork::train({ "ball", "bars" }, { dataset(0), dataset(1) }, quick());
  // a temporary directory of this test alone: nothing else writes there
  const std::string tmp = ddg::testing::tempDir() + "/kind_tmp";
  fs::create_directories(tmp);
  const char* saved = std::getenv("TMPDIR");
  const std::string before = saved ? saved : "";
  ::setenv("TMPDIR", tmp.c_str(), 1);
  auto leftOver = [&]
  { return std::distance(fs::directory_iterator(tmp), fs::directory_iterator()); };
  int calls = 0;
  EXPECT_THROW(kindReference(net, synthetic(0), 1, [&](double) { return ++calls < 2; }), Cancelled);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(leftOver(), 0) << "a cancelled reference left its exemplars";
  const auto reference = kindReference(net, synthetic(0), 1);
  EXPECT_EQ(leftOver(), 0);
  saved ? (void)::setenv("TMPDIR", before.c_str(), 1) : (void)::unsetenv("TMPDIR");
  ASSERT_EQ(reference.size(), 2u);
  EXPECT_NEAR(reference[0] + reference[1], 1.0, 1e-5);

  // differs exactly when the agreement lies under the threshold; the words and the JSON say it
  const Image picture = ExemplarDataset(dataset(1)).images(3).rgbExp;
  const double agreement = checkKind(net, picture, reference).agreement;
  ASSERT_GT(agreement, 0.0);
  ASSERT_LT(agreement, 1.0);
  const double step = std::min({ 0.005, agreement / 2, (1 - agreement) / 2 });
  net.setThreshold(agreement + step);
  const KindCheck under = checkKind(net, picture, reference);
  net.setThreshold(agreement - step);
  const KindCheck over = checkKind(net, picture, reference);
  EXPECT_EQ(under.agreement, over.agreement);
  EXPECT_TRUE(under.differs);
  EXPECT_FALSE(over.differs);
  EXPECT_NE(describeKindCheck(under).find("may show a volume of another kind"), std::string::npos);
  EXPECT_NE(describeKindCheck(over).find("the same kind"), std::string::npos);
  EXPECT_NE(kindCheckToJson(under).find("\"differs\":true"), std::string::npos);
  EXPECT_TRUE(under.pictureLike == "ball" || under.pictureLike == "bars");
}

TEST(KindNetwork, TheCheckerKeepsAReferenceByTheFingerprintItIsGiven)
{
  // under MPI the reference is drawn from the volume assembled on the first rank and kept under
  // the whole volume's fingerprint (Plugin/Filters/DDGKindCheck.cxx)
  const std::string dir = ddg::testing::tempDir() + "/kind_checker";
  trained().save(dir);
  const Image picture = ExemplarDataset(dataset(1)).images(2).rgbExp;
  // references kept on disk in a directory of this test alone
  const std::string cache = ddg::testing::tempDir() + "/kind_cache";
  fs::remove_all(cache);
  struct Restore // DDG_CACHE_DIR as it was, however the test ends
  {
    const char* saved = std::getenv("DDG_CACHE_DIR");
    std::string before = saved ? saved : "";
    ~Restore()
    {
      saved ? (void)::setenv("DDG_CACHE_DIR", before.c_str(), 1)
            : (void)::unsetenv("DDG_CACHE_DIR");
    }
  } restore;
  ::setenv("DDG_CACHE_DIR", cache.c_str(), 1);
  EXPECT_EQ(kindCacheDirectory(), cache);
  KindChecker checker;
  EXPECT_FALSE(checker.hasReference(dir, "the whole"));
  EXPECT_THROW(checker.check(dir, picture, "the whole"), Error);
  checker.addReference(dir, "the whole", synthetic(0), 1);
  EXPECT_TRUE(checker.hasReference(dir, "the whole"));
  int calls = 0; // kept: not drawn again
  checker.addReference(dir, "the whole", synthetic(1), 1, [&](double) { return ++calls > 0; });
  EXPECT_EQ(calls, 0);
  const KindCheck kept = checker.check(dir, picture, "the whole");
  const KindCheck drawn = checker.check(dir, picture, synthetic(0), 1); // by its own fingerprint
  EXPECT_DOUBLE_EQ(kept.agreement, drawn.agreement);
  EXPECT_EQ(kept.volumeLike, drawn.volumeLike);
  EXPECT_TRUE(checker.hasReference(dir, volumeFingerprint(synthetic(0))));
  EXPECT_NE(checker.check(dir, picture, synthetic(1), 1).agreement, kept.agreement);

  // the next session reads the kept reference back instead of drawing it (the volume given is
  // another: the file is keyed by the network and the fingerprint)
  const fs::path files = fs::path(cache) / "kind-references";
  ASSERT_EQ(std::distance(fs::directory_iterator(files), fs::directory_iterator()), 3);
  int draws = 0;
  auto counting = [&](double)
  {
    ++draws;
    return true;
  };
  KindChecker next;
  next.addReference(dir, "the whole", synthetic(1), 1, counting);
  EXPECT_EQ(draws, 0);
  EXPECT_DOUBLE_EQ(next.check(dir, picture, "the whole").agreement, kept.agreement);
  // an unreadable file is draws again and written over
  for (const auto& f : fs::directory_iterator(files))
    std::ofstream(f.path()) << "{ not json";
  KindChecker third;
  third.addReference(dir, "the whole", synthetic(0), 1, counting);
  EXPECT_GT(draws, 0);
  EXPECT_DOUBLE_EQ(third.check(dir, picture, "the whole").agreement, kept.agreement);
  draws = 0;
  KindChecker fourth;
  fourth.addReference(dir, "the whole", synthetic(1), 1, counting);
  EXPECT_EQ(draws, 0) << "the file draws again was not written over";
  // "none": nothing kept, nothing read
  ::setenv("DDG_CACHE_DIR", "none", 1);
  EXPECT_EQ(kindCacheDirectory(), "");
  KindChecker off;
  off.addReference(dir, "the whole", synthetic(1), 1, counting);
  EXPECT_GT(draws, 0);
  EXPECT_NE(off.check(dir, picture, "the whole").agreement, kept.agreement);
}
