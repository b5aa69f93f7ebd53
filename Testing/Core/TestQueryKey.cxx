// TestQueryKey.cxx: the query key (LDA on view pairs) finds a design from another view where the
// latents cannot, through DesignOutline's nearest; its file round-trips and bad input is refused.
#include "Common/Error.h"
#include "Gallery/Outline.h"
#include "Gallery/QueryKey.h"

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

} // namespace

TEST(QueryKey, FindsDesignsFromAnotherViewWhereLatentsCannot)
{
  const Pairs fit = makePairs(2000, 1), test = makePairs(500, 2);
  const ddg::QueryKey key = ddg::fitQueryKey(fit.own, fit.other, 8, 4);
  EXPECT_EQ(key.dim, 8);
  EXPECT_EQ(key.components, 4);
  EXPECT_EQ(key.pairs, 2000);
  ASSERT_EQ(key.matrix.size(), 32u);
  ddg::DesignOutline outline(setOf(test));
  const double byLatents = recall(outline, test, 5);
  outline.setQueryKey(key);
  const double byKey = recall(outline, test, 5);
  EXPECT_LT(byLatents, 0.2);
  EXPECT_GT(byKey, 0.9);
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
      s += key.matrix[static_cast<size_t>(r) * 8 + c] * fit.own[8 + c];
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
  EXPECT_EQ(back.matrix, key.matrix);
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
