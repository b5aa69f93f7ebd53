// TestNeuralModel.cxx: the libtorch networks on a tiny synthetic dataset — output shapes and
// ranges, training lowers the imitation error, bundles round-trip exactly, and bad bundles,
// another volume's bundle, a wrong architecture and a cancelled-then-resumed training are
// handled. Tolerances: exact equality for round trips; "lower" for training.
#include "Neural/NeuralDesignModel.h"

#include "TempDir.h"
#include "TestVolumes.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "FileSizeLimit.h"

using namespace ddg;
namespace fs = std::filesystem;

namespace
{
Volume blobs()
{
  return ddg::testing::ballInShell();
}

const ExemplarDataset& dataset()
{
  static const std::string dir = []
  {
    const std::string d = ddg::testing::tempDir() + "/ddg_neural_data";
    fs::remove_all(d);
    GenerateOptions opt;
    opt.count = 24;
    opt.size = 16;
    generateExemplars(blobs(), DesignSpaceSpec{}, d, opt);
    return d;
  }();
  static const ExemplarDataset data(dir);
  return data;
}

NetworkConfig tiny()
{
  NetworkConfig c;
  c.imageSize = 16;
  c.width = 4;
  c.latent = 8;
  return c;
}

TrainOptions quick(int iterations)
{
  TrainOptions t;
  t.batch = 4;
  t.maxIterations = iterations;
  t.minutes = 5;
  t.threads = 1;
  t.learningRate = 1e-3;
  return t;
}
} // namespace

TEST(NeuralModel, ShapesAndRanges)
{
  const NeuralDesignModel m(tiny());
  Image rgb(40, 30, 3, 0.3f); // any size: resized
  const auto z = m.analyze(rgb);
  EXPECT_EQ(z.size(), 8u);
  Image viewport(16, 16, 4, 0.5f);
  const Image out = m.render(z, viewport);
  ASSERT_EQ(out.channels, 4);
  ASSERT_EQ(out.width, 16);
  for (float v : out.pixels)
    ASSERT_TRUE(v >= 0.0f && v <= 1.0f);
  EXPECT_THROW(m.render(std::vector<float>(3), viewport), Error);
  EXPECT_THROW(m.render(z, Image(8, 8, 4)), Error);
  NetworkConfig bad = tiny();
  bad.imageSize = 24;
  EXPECT_THROW(NeuralDesignModel{ bad }, Error);
}

TEST(NeuralModel, TrainingLowersTheError)
{
  NeuralDesignModel m(tiny(), 3);
  const double before = m.evaluate(dataset(), 24).psnr;
  m.train(dataset(), quick(150));
  const double after = m.evaluate(dataset(), 24).psnr;
  EXPECT_GT(after, before + 1.0) << "PSNR before " << before << " after " << after;
}

TEST(NeuralModel, OtherViewDrawIsItsShareAndRepeatable)
{
  for (int image : otherViewDraw(16, 0.0, 7, 3))
    EXPECT_EQ(image, -1);
  int other = 0, white = 0, total = 0;
  for (int it = 0; it < 200; ++it)
  {
    const auto all = otherViewDraw(16, 1.0, 7, it);
    for (int image : all)
    {
      ASSERT_TRUE(image == 0 || image == 1);
      white += image;
    }
    for (int image : otherViewDraw(16, 0.5, 7, it))
    {
      other += image >= 0 ? 1 : 0;
      ++total;
    }
  }
  EXPECT_NEAR(static_cast<double>(other) / total, 0.5, 0.05);
  EXPECT_NEAR(white / 3200.0, 0.5, 0.05); // both backgrounds
  EXPECT_EQ(otherViewDraw(16, 0.5, 7, 11), otherViewDraw(16, 0.5, 7, 11));
  EXPECT_NE(otherViewDraw(64, 0.5, 7, 11), otherViewDraw(64, 0.5, 7, 12));
  EXPECT_NE(otherViewDraw(64, 0.5, 7, 11), otherViewDraw(64, 0.5, 8, 11));
}

TEST(NeuralModel, TrainingOnTheOtherViewLowersTheError)
{
  // every analyzer image from the other view: what the analyzer learns must still carry over to
  // the images at V_exp that it is evaluated on
  NeuralDesignModel m(tiny(), 3);
  const double before = m.evaluate(dataset(), 24).psnr;
  TrainOptions t = quick(150);
  t.otherViewFraction = 1;
  m.train(dataset(), t);
  const double after = m.evaluate(dataset(), 24).psnr;
  EXPECT_GT(after, before + 1.0) << "PSNR before " << before << " after " << after;
  t.otherViewFraction = 1.5;
  EXPECT_THROW(m.train(dataset(), t), Error);
  t.otherViewFraction = 0;
  t.imageSampleScale = 0; // the image loss's step: refused before any step
  EXPECT_THROW(m.train(dataset(), t), Error);
}

TEST(NeuralModel, TheUNetRefusesDataWithoutViewports)
{
  const std::string d = ddg::testing::tempDir() + "/ddg_neural_no_viewport";
  fs::remove_all(d);
  GenerateOptions opt;
  opt.count = 4;
  opt.size = 16;
  opt.viewport = false;
  generateExemplars(blobs(), DesignSpaceSpec{}, d, opt);
  const ExemplarDataset data(d);
  NeuralDesignModel m(tiny(), 3);
  EXPECT_THROW(m.train(data, quick(2)), Error);
  EXPECT_THROW(m.evaluate(data, 4), Error);
}

TEST(NeuralModel, BundlesRoundTripAndRefuseBadOnes)
{
  NeuralDesignModel m(tiny(), 5);
  m.train(dataset(), quick(5));
  const std::string dir = ddg::testing::tempDir() + "/ddg_bundle";
  fs::remove_all(dir);
  m.saveBundle(dir, dataset(), "{\"psnr\": 1}");
  const auto loaded = NeuralDesignModel::loadBundle(dir, dataset().fingerprint());
  Image rgb(16, 16, 3, 0.25f);
  EXPECT_EQ(m.analyze(rgb), loaded.analyze(rgb));
  // half floats: header (32 bytes), 24 indices, 24 x 8 values
  EXPECT_EQ(fs::file_size(dir + "/latents.bin"), 32u + 24u * 8u + 24u * 8u * 2u);
  // the training designs come back with the bundle, latents equal to the analyzer's
  const auto& designs = loaded.trainingDesigns();
  ASSERT_EQ(designs.count(), 24);
  const auto first = dataset().images(0).rgbExp;
  const auto z0 = m.analyze(first);
  for (int c = 0; c < 8; ++c) // half precision: 11 significant bits
    EXPECT_NEAR(designs.latentOf(0)[c], z0[c], 1e-3 * std::max(1.0f, std::abs(z0[c])));
  EXPECT_EQ(designs.tfs[0].size(), dataset().exemplars()[0].primitives.size());
  {
    // truncated latents or designs
    const std::string cut = ddg::testing::tempDir() + "/ddg_bundle_cut";
    fs::remove_all(cut);
    fs::copy(dir, cut);
    fs::resize_file(cut + "/latents.bin", 100);
    EXPECT_THROW(NeuralDesignModel::loadBundle(cut), Error);
    fs::remove_all(cut);
    fs::copy(dir, cut);
    fs::resize_file(cut + "/exemplars.json", 50);
    EXPECT_THROW(NeuralDesignModel::loadBundle(cut), Error);
  }

  // another volume: said in words, without hashes
  try
  {
    NeuralDesignModel::loadBundle(dir, "64x64x64 spacing 1,1,1 range 0..1 fnv1a 0");
    ADD_FAILURE() << "another volume's bundle was loaded";
  }
  catch (const Error& e)
  {
    const std::string what = e.what();
    EXPECT_NE(what.find("trained on another volume"), std::string::npos) << what;
    EXPECT_NE(what.find("not this one (64 x 64 x 64 voxels, values 0 to 1)"), std::string::npos)
      << what;
    EXPECT_EQ(what.find("fnv1a"), std::string::npos) << what;
  }
  // wrong architecture in bundle.json
  const std::string wrong = ddg::testing::tempDir() + "/ddg_bundle_wrong";
  fs::remove_all(wrong);
  fs::copy(dir, wrong);
  {
    std::ifstream in(wrong + "/bundle.json");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    text.replace(text.find("\"width\": 4"), 10, "\"width\": 6");
    std::ofstream(wrong + "/bundle.json") << text;
  }
  EXPECT_THROW(NeuralDesignModel::loadBundle(wrong), Error);
  // truncated weights
  fs::resize_file(wrong + "/model.pt", 100);
  EXPECT_THROW(NeuralDesignModel::loadBundle(wrong), Error);
  // corrupt index, missing bundle
  std::ofstream(wrong + "/bundle.json") << "{\"format\": ";
  EXPECT_THROW(NeuralDesignModel::loadBundle(wrong), Error);
  EXPECT_THROW(NeuralDesignModel::loadBundle(ddg::testing::tempDir() + "/ddg_no_bundle"), Error);
}

TEST(NeuralModel, CancelThenResumeContinuesFromTheCheckpoint)
{
  const std::string ckpt = ddg::testing::tempDir() + "/ddg_ckpt.pt";
  fs::remove(ckpt);
  NeuralDesignModel m(tiny(), 7);
  TrainOptions t = quick(40);
  t.checkpoint = ckpt;
  const auto first = m.train(dataset(), t, [](const TrainProgress& p) { return p.iteration < 20; });
  EXPECT_TRUE(first.cancelled);
  EXPECT_EQ(first.iterations, 20);
  ASSERT_TRUE(fs::exists(ckpt));
  NeuralDesignModel resumed(tiny(), 99); // different initialisation: the checkpoint must win
  t.resume = true;
  const auto second = resumed.train(dataset(), t);
  EXPECT_FALSE(second.cancelled);
  EXPECT_EQ(second.iterations, 40);
  // a corrupt checkpoint is refused
  std::ofstream(ckpt) << "garbage";
  NeuralDesignModel other(tiny());
  EXPECT_THROW(other.train(dataset(), t), Error);
}

TEST(NeuralModel, DecoderVariantDecodesRendersAndRoundTrips)
{
  NetworkConfig c = tiny();
  c.kind = "decoder";
  c.regions = static_cast<int>(dataset().regions().size());
  NeuralDesignModel m(c, 11);
  Image rgb(16, 16, 3, 0.3f), viewport(16, 16, 4, 0.0f);
  const auto z = m.analyze(rgb);
  EXPECT_THROW(m.renderAt(z, viewport, dataset().exemplars()[0].viewView), Error); // no volume yet
  EXPECT_THROW(m.decode(z), Error); // no regions before training
  m.attachVolume(blobs());
  m.train(dataset(), quick(1));
  const double before = m.evaluate(dataset(), 24).psnr;
  m.train(dataset(), quick(300));
  const double after = m.evaluate(dataset(), 24).psnr;
  EXPECT_GT(after, before) << "PSNR before " << before << " after " << after;
  for (const auto& g : m.decode(z))
  {
    EXPECT_GE(g.opacity, 0.0);
    EXPECT_LE(g.opacity, 1.0);
  }
  const Image out = m.renderAt(z, viewport, dataset().exemplars()[0].viewView);
  EXPECT_EQ(out.channels, 4);
  EXPECT_THROW(m.render(z, viewport), Error); // the decoder needs a view

  const std::string dir = ddg::testing::tempDir() + "/ddg_bundle_decoder";
  fs::remove_all(dir);
  m.saveBundle(dir, dataset(), "");
  auto loaded = NeuralDesignModel::loadBundle(dir, dataset().fingerprint());
  EXPECT_EQ(loaded.config().kind, "decoder");
  EXPECT_EQ(m.decode(z).size(), loaded.decode(z).size());
  // a volume other than the training one is refused
  std::vector<float> other(8 * 8 * 8, 1.0f);
  other[0] = 0.0f;
  EXPECT_THROW(loaded.attachVolume(Volume({ 8, 8, 8 }, { 0, 0, 0 }, { 1, 1, 1 }, other)), Error);
}

TEST(NeuralModel, FullDiskKeepsThePreviousCheckpointAndNoHalfBundle)
{
  const std::string ckpt = ddg::testing::tempDir() + "/ddg_full_ckpt.pt";
  fs::remove(ckpt);
  NeuralDesignModel m(tiny(), 3);
  TrainOptions t = quick(2);
  t.checkpoint = ckpt;
  m.train(dataset(), t);
  ASSERT_TRUE(fs::exists(ckpt));
  const auto size = fs::file_size(ckpt);
  const std::string dir = ddg::testing::tempDir() + "/ddg_full_bundle";
  fs::remove_all(dir);
  m.saveBundle(dir, dataset(), "");
  const auto weights = fs::file_size(dir + "/model.pt");
  {
    FileSizeLimit full(std::min(size, weights) / 2);
    t.maxIterations = 4;
    t.resume = true;
    try
    {
      m.train(dataset(), t);
      ADD_FAILURE() << "a checkpoint was written to a full disk";
    }
    catch (const Error& e)
    {
      EXPECT_NE(std::string(e.what()).find("disk full"), std::string::npos) << e.what();
    }
    EXPECT_THROW(m.saveBundle(dir, dataset(), ""), Error);
  }
  EXPECT_EQ(fs::file_size(ckpt), size);
  for (const auto& f : fs::directory_iterator(ddg::testing::tempDir()))
    EXPECT_EQ(f.path().filename().string().find("ddg_full_ckpt.pt.tmp"), std::string::npos)
      << "temporary file left: " << f.path();
  EXPECT_FALSE(fs::exists(dir + "/bundle.json"));
  EXPECT_THROW(NeuralDesignModel::loadBundle(dir), Error);
  // with space again, resuming from the kept checkpoint works
  NeuralDesignModel again(tiny(), 4);
  EXPECT_EQ(again.train(dataset(), t).iterations, 4);
}

TEST(NeuralModel, AdaptiveImageRaysFollowWhatAStepCosts)
{
  // maxRays x min(1, rest / image), to maxRays over a power of two, at least a quarter
  EXPECT_EQ(adaptiveImageRays(512, 1.0, 2.0), 512); // the image loss is the cheaper part
  EXPECT_EQ(adaptiveImageRays(512, 1.0, 1.0), 512);
  EXPECT_EQ(adaptiveImageRays(512, 1.3, 1.0), 512); // 0.77: nearest is 2^0
  EXPECT_EQ(adaptiveImageRays(512, 2.0, 1.0), 256);
  EXPECT_EQ(adaptiveImageRays(512, 62.0, 21.0), 128); // the chest (Documentation/DesignSpaces.md)
  EXPECT_EQ(adaptiveImageRays(512, 100.0, 1.0), 128); // never under a quarter
  EXPECT_EQ(adaptiveImageRays(512, 0.0, 1.0), 512);   // nothing timed: unchanged
  EXPECT_EQ(adaptiveImageRays(2, 100.0, 1.0), 1);
  EXPECT_THROW(adaptiveImageRays(0, 1.0, 1.0), Error);

  NetworkConfig c = tiny();
  c.kind = "decoder";
  c.regions = static_cast<int>(dataset().regions().size());
  auto rays = [&](int iterations, double weight, bool adaptive)
  {
    NeuralDesignModel m(c, 3);
    m.attachVolume(blobs());
    TrainOptions t = quick(iterations);
    t.imageWeight = weight;
    t.imageRays = 64;
    t.adaptiveRays = adaptive;
    return m.train(dataset(), t).imageRays;
  };
  EXPECT_EQ(rays(kAdaptiveRaysTo + 5, 0.0, true), 0); // no image loss
  EXPECT_EQ(rays(kAdaptiveRaysTo + 5, 100.0, false), 64);
  EXPECT_EQ(rays(kAdaptiveRaysTo - 1, 100.0, true), 64); // stopped before the timed steps ended
  const int adapted = rays(kAdaptiveRaysTo + 5, 100.0, true);
  EXPECT_TRUE(adapted == 64 || adapted == 32 || adapted == 16) << adapted;
}

// The image loss's coarser march (TrainOptions::imageSampleScale) changes what a step teaches,
// and with adaptive rays the timed steps march at ParaView's step: up to the last of them the
// weights are those of a training without it, to the byte.
TEST(NeuralModel, TheImageLossMarchesCoarserAfterTheTimedSteps)
{
  NetworkConfig c = tiny();
  c.kind = "decoder";
  c.regions = static_cast<int>(dataset().regions().size());
  Image probe(16, 16, 3);
  for (size_t k = 0; k < probe.pixels.size(); ++k)
    probe.pixels[k] = static_cast<float>(k % 7) / 7.0f;
  auto latent = [&](int iterations, double scale, bool adaptive)
  {
    NeuralDesignModel m(c, 3);
    m.attachVolume(blobs());
    TrainOptions t = quick(iterations);
    t.imageWeight = 100;
    t.imageRays = 64;
    t.adaptiveRays = adaptive;
    t.imageSampleScale = scale;
    m.train(dataset(), t);
    return m.analyze(probe);
  };
  EXPECT_NE(latent(5, 1.0, false), latent(5, 2.0, false));
  EXPECT_EQ(latent(kAdaptiveRaysTo, 1.0, true), latent(kAdaptiveRaysTo, 2.0, true));
}
