// TestQueryKey.cxx: the query keys (LDA on view pairs, and the contrastive network) find a design
// from another view where the latents cannot, through DesignOutline's nearest; the network's
// gradient matches finite differences; the file round-trips (version 1 still read) and bad input
// is refused.
#include "Common/Error.h"
#include "Gallery/Outline.h"
#include "Gallery/QueryKey.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/QR>

#include <filesystem>
#include <fstream>
#include <random>

namespace
{

// n designs in 8 latent values, mixed by a random rotation: 4 that tell designs apart (spread 1,
// a view moves them by 0.05) and 4 that a change of view redraws (spread 3). own: each design's
// latent from one view, other: from another.
struct Pairs
{
  int dim = 8;
  std::vector<float> own, other;
};

Pairs makePairs(int n, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd random(8, 8);
  std::mt19937_64 mixRng(99); // the same mixing for every set
  for (int i = 0; i < 64; ++i)
    random(i / 8, i % 8) = std::normal_distribution<double>(0.0, 1.0)(mixRng);
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(random).householderQ();
  Pairs p;
  for (int i = 0; i < n; ++i)
  {
    Eigen::VectorXd a(8), b(8);
    for (int c = 0; c < 4; ++c)
    {
      const double s = g(rng);
      a(c) = s + 0.05 * g(rng);
      b(c) = s + 0.05 * g(rng);
    }
    for (int c = 4; c < 8; ++c)
    {
      a(c) = 3 * g(rng);
      b(c) = 3 * g(rng);
    }
    const Eigen::VectorXd ma = q * a, mb = q * b;
    for (int c = 0; c < 8; ++c)
    {
      p.own.push_back(static_cast<float>(ma(c)));
      p.other.push_back(static_cast<float>(mb(c)));
    }
  }
  return p;
}

// The fraction of designs whose other view finds their own row among the outline's k nearest.
double recall(const ddg::DesignOutline& outline, const Pairs& p, int k)
{
  int hits = 0;
  const int n = static_cast<int>(p.own.size()) / p.dim;
  for (int i = 0; i < n; ++i)
  {
    const auto nn = outline.nearest(p.other.data() + static_cast<size_t>(i) * p.dim, k);
    for (const auto& nb : nn)
      hits += nb.row == i;
  }
  return static_cast<double>(hits) / n;
}

ddg::LatentSet setOf(const Pairs& p)
{
  ddg::LatentSet s;
  s.dim = p.dim;
  s.values = p.own;
  for (size_t i = 0; i < p.own.size() / p.dim; ++i)
    s.indices.push_back(i);
  return s;
}

// The planted set's other views: under 20 % found among the 5 nearest by the latents, over 90 %
// by the key. Returns the recall by the latents.
double expectKeyFindsOtherViews(
  ddg::DesignOutline& outline, const ddg::QueryKey& key, const Pairs& test)
{
  const double byLatents = recall(outline, test, 5);
  outline.setQueryKey(key);
  const double byKey = recall(outline, test, 5);
  EXPECT_LT(byLatents, 0.2);
  EXPECT_GT(byKey, 0.9);
  return byLatents;
}

} // namespace

TEST(QueryKey, FindsDesignsFromAnotherViewWhereLatentsCannot)
{
  const Pairs fit = makePairs(2000, 1), test = makePairs(500, 2);
  const ddg::QueryKey key = ddg::fitQueryKey(fit.own, fit.other, 8, 4);
  EXPECT_EQ(key.dim, 8);
  EXPECT_EQ(key.components, 4);
  EXPECT_EQ(key.pairs, 2000);
  ASSERT_EQ(key.layers.size(), 1u);
  ASSERT_EQ(key.layers[0].weights.size(), 32u);
  EXPECT_TRUE(key.layers[0].bias.empty());
  EXPECT_EQ(key.method, "lda");
  ddg::DesignOutline outline(setOf(test));
  const double byLatents = expectKeyFindsOtherViews(outline, key, test);
  // the own latent is its own nearest either way
  const auto self = outline.nearest(test.own.data() + 7 * 8, 1);
  ASSERT_EQ(self.size(), 1u);
  EXPECT_EQ(self[0].row, 7);
  EXPECT_NEAR(self[0].distance, 0.0, 1e-4);
  // an empty key: the latents again
  outline.setQueryKey({});
  EXPECT_DOUBLE_EQ(recall(outline, test, 5), byLatents);
}

TEST(QueryKey, AppliesAsItsMatrix)
{
  const Pairs fit = makePairs(200, 3);
  const ddg::QueryKey key = ddg::fitQueryKey(fit.own, fit.other, 8, 3);
  const std::vector<float> k = key.apply(fit.own.data() + 8, 1, 8);
  ASSERT_EQ(k.size(), 3u);
  for (int r = 0; r < 3; ++r)
  {
    double s = 0;
    for (int c = 0; c < 8; ++c)
      s += key.layers[0].weights[static_cast<size_t>(r) * 8 + c] * fit.own[8 + c];
    EXPECT_NEAR(k[r], s, 1e-4);
  }
  EXPECT_THROW(key.apply(fit.own.data(), 1, 7), ddg::Error); // another model's latents
  EXPECT_EQ(ddg::QueryKey{}.apply(fit.own.data(), 2, 8),
    std::vector<float>(fit.own.begin(), fit.own.begin() + 16));
}

TEST(QueryKey, RefusesTooFewOrMismatchedPairs)
{
  const Pairs p = makePairs(15, 4); // under 2 x dim
  EXPECT_THROW(ddg::fitQueryKey(p.own, p.other, 8, 4), ddg::Error);
  const Pairs q = makePairs(100, 5);
  std::vector<float> shorter(q.other.begin(), q.other.end() - 8);
  EXPECT_THROW(ddg::fitQueryKey(q.own, shorter, 8, 4), ddg::Error);
  EXPECT_THROW(ddg::fitQueryKey(q.own, q.other, 8, 0), ddg::Error);
  EXPECT_THROW(ddg::fitQueryKey(q.own, q.other, 8, 9), ddg::Error);
}

TEST(QueryKey, FileRoundTripAndCorruption)
{
  const Pairs p = makePairs(100, 6);
  const ddg::QueryKey key = ddg::fitQueryKey(p.own, p.other, 8, 2);
  const auto dir = std::filesystem::temp_directory_path() / "ddg-test-query-key";
  std::filesystem::create_directories(dir);
  const std::string path = ddg::queryKeyFile(dir.string());
  EXPECT_EQ(std::filesystem::path(path).filename(), "query_key.json");
  ddg::writeQueryKey(key, path);
  const ddg::QueryKey back = ddg::readQueryKey(path);
  EXPECT_EQ(back.dim, 8);
  EXPECT_EQ(back.components, 2);
  EXPECT_EQ(back.pairs, 100);
  EXPECT_EQ(back.layers[0].weights, key.layers[0].weights);
  EXPECT_EQ(back.method, "lda");
  EXPECT_THROW(ddg::writeQueryKey(ddg::QueryKey{}, path), ddg::Error);
  {
    std::ofstream(path) << R"({"format": "ddg-query-key", "version": 1, "dim": 8,
      "components": 2, "pairs": 100, "matrix": [1, 2, 3]})";
  }
  try
  {
    ddg::readQueryKey(path);
    FAIL() << "a key with too few values should be refused";
  }
  catch (const ddg::Error& e)
  {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  {
    std::ofstream(path) << "not json";
  }
  EXPECT_THROW(ddg::readQueryKey(path), ddg::Error);
  std::filesystem::remove_all(dir);
  EXPECT_THROW(ddg::readQueryKey(path), ddg::Error);
}

namespace
{
ddg::ContrastiveKeyOptions smallNetwork()
{
  ddg::ContrastiveKeyOptions o;
  o.hidden = 32;
  o.components = 8;
  o.epochs = 30;
  o.batch = 128;
  return o;
}
} // namespace

TEST(QueryKey, ContrastiveKeyFindsDesignsFromAnotherView)
{
  const Pairs fit = makePairs(2000, 7), test = makePairs(500, 8);
  const ddg::QueryKey key = ddg::fitContrastiveQueryKey(fit.own, fit.other, 8, smallNetwork());
  EXPECT_EQ(key.method, "contrastive");
  EXPECT_EQ(key.components, 8);
  EXPECT_EQ(key.pairs, 2000);
  ASSERT_EQ(key.layers.size(), 3u);
  ddg::DesignOutline outline(setOf(test));
  expectKeyFindsOtherViews(outline, key, test);
  // unit-length keys
  const auto k = key.apply(test.own.data(), 3, 8);
  for (int r = 0; r < 3; ++r)
  {
    double s = 0;
    for (int c = 0; c < 8; ++c)
      s += k[static_cast<size_t>(r) * 8 + c] * k[static_cast<size_t>(r) * 8 + c];
    EXPECT_NEAR(s, 1.0, 1e-5);
  }
  // the same seed, the same key; cancelled through progress
  const ddg::QueryKey again = ddg::fitContrastiveQueryKey(fit.own, fit.other, 8, smallNetwork());
  EXPECT_EQ(again.layers[2].weights, key.layers[2].weights);
  EXPECT_THROW(ddg::fitContrastiveQueryKey(
                 fit.own, fit.other, 8, smallNetwork(), [](double f) { return f < 0.5; }),
    ddg::Cancelled);
  const Pairs few = makePairs(15, 9);
  EXPECT_THROW(ddg::fitContrastiveQueryKey(few.own, few.other, 8), ddg::Error);
  auto bad = smallNetwork();
  bad.temperature = 0;
  EXPECT_THROW(ddg::fitContrastiveQueryKey(fit.own, fit.other, 8, bad), ddg::Error);
}

TEST(QueryKey, ContrastiveGradientMatchesFiniteDifferences)
{
  const Pairs p = makePairs(64, 10);
  auto o = smallNetwork();
  o.epochs = 2; // a trained (not initial) network, its GELUs off zero
  o.batch = 16;
  ddg::QueryKey key = ddg::fitContrastiveQueryKey(p.own, p.other, 8, o);
  const int batch = 12;
  std::vector<std::vector<float>> grad;
  ddg::contrastiveKeyLoss(key, p.own.data(), p.other.data(), batch, 0.1, &grad);
  ASSERT_EQ(grad.size(), 3u);
  std::mt19937_64 rng(11);
  int checked = 0;
  for (size_t l = 0; l < key.layers.size(); ++l)
    for (int trial = 0; trial < 12; ++trial)
    {
      auto& layer = key.layers[l];
      const size_t nw = layer.weights.size();
      const size_t i = rng() % (nw + layer.bias.size());
      float& w = i < nw ? layer.weights[i] : layer.bias[i - nw];
      const float saved = w, h = 1e-2f;
      w = saved + h;
      const double up = ddg::contrastiveKeyLoss(key, p.own.data(), p.other.data(), batch, 0.1, {});
      w = saved - h;
      const double down =
        ddg::contrastiveKeyLoss(key, p.own.data(), p.other.data(), batch, 0.1, {});
      w = saved;
      const double fd = (up - down) / (2 * h);
      EXPECT_NEAR(grad[l][i], fd, 2e-3 + 0.03 * std::abs(fd)) << "layer " << l << " entry " << i;
      ++checked;
    }
  EXPECT_EQ(checked, 36);
}

TEST(QueryKey, ContrastiveFileRoundTripAndVersionOne)
{
  const Pairs p = makePairs(200, 12);
  auto o = smallNetwork();
  o.epochs = 2;
  const ddg::QueryKey key = ddg::fitContrastiveQueryKey(p.own, p.other, 8, o);
  const auto dir = std::filesystem::temp_directory_path() / "ddg-test-query-key-net";
  std::filesystem::create_directories(dir);
  const std::string path = ddg::queryKeyFile(dir.string());
  ddg::writeQueryKey(key, path);
  const ddg::QueryKey back = ddg::readQueryKey(path);
  EXPECT_EQ(back.method, "contrastive");
  EXPECT_TRUE(back.normalized);
  EXPECT_EQ(back.mean, key.mean);
  EXPECT_EQ(back.apply(p.other.data(), 5, 8), key.apply(p.other.data(), 5, 8));
  {
    std::ofstream(path) << R"({"format": "ddg-query-key", "version": 1, "dim": 2,
      "components": 1, "pairs": 100, "matrix": [2, 3]})";
  }
  const ddg::QueryKey linear = ddg::readQueryKey(path);
  const float z[2] = { 1, 10 };
  EXPECT_EQ(linear.method, "lda");
  EXPECT_EQ(linear.apply(z, 1, 2), std::vector<float>{ 32 });
  {
    std::ofstream(path) << R"({"format": "ddg-query-key", "version": 2, "method": "contrastive",
      "dim": 2, "components": 1, "pairs": 100, "mean": [0, 0], "scale": [1, 0],
      "layers": [{"rows": 1, "cols": 2, "weights": [2, 3], "bias": [1]}], "normalized": true})";
  }
  EXPECT_THROW(ddg::readQueryKey(path), ddg::Error); // a zero scale
  std::filesystem::remove_all(dir);
}
