// TestPieces.cxx: the differentiable renderer and the reconstruction over the pieces of a volume
// (ParaView's pieces under MPI, here in threads exchanging through a ThreadBoard).
//
// Compared:
//  1. compositePixelsAdjoint against central differences of compositePixels (exact: the
//     composite is linear in one piece's values), tolerance 1e-4;
//  2. forward over 2, 3 and 4 pieces (bisection and an uneven split with a piece that owns no
//     cell) against the whole's, 1D, Shade with specular, 2D; early termination off: images
//     within 1e-5, table gradients within 1e-4 of their largest entry;
//  3. reconstructTransferFunction over pieces against the whole's, 1D and 2D (the pieces agree
//     on the gradient range with VolumeBrick::gradientMagnitudeMax): the same steps, tables
//     within 1e-3;
//  4. a piece that fails stops every piece: it throws its own error, the others PieceFailed.
#include "VolumePieces.h"

#include "Reconstruct/Reconstruction.h"
#include "Render/DifferentiableRenderer.h"
#include "Render/SortLast.h"

#include <gtest/gtest.h>

#include <random>

using namespace ddg;
using ddg::testing::bisect;
using ddg::testing::blobVolume;
using ddg::testing::Box;
using ddg::testing::orbitView;
using ddg::testing::pieceOf;
using ddg::testing::runPieces;
using ddg::testing::ThreadBoard;
using ddg::testing::ThreadExchange;
using ddg::testing::unevenSplit;

namespace
{

TransferFunction1D pieceTF()
{
  TransferFunction1D tf;
  tf.color = { { 0, 0.1, 0.2, 0.9 }, { 100, 0.9, 0.4, 0.2 }, { 255, 1, 1, 0.8 } };
  tf.opacity = { { 0, 0 }, { 50, 0.05 }, { 140, 0.4 }, { 255, 0.7 } };
  return tf;
}

// One forward + backward over a set of pieces in threads, or over the whole (boxes empty).
struct Pass
{
  std::vector<float> rgba, dTable;
};

Pass runPass(const Volume& whole, const std::vector<Box>& boxes, bool twoD, const View& view,
  const std::vector<int>& pixels, const std::vector<float>& table, int width, int height,
  std::array<double, 2> gradientRange)
{
  RenderOptions opt;
  opt.terminationOpacity = 1.0; // exact: no early termination
  const auto range = whole.range();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1, 1);
  const size_t n = pixels.size();
  std::vector<float> g(4 * n);
  for (auto& v : g)
    v = u(rng);
  auto pass = [&](const DifferentiableRenderer& r, Pass& out)
  {
    std::vector<RayRecord> records;
    out.dTable.assign(table.size(), 0.0f);
    if (twoD)
    {
      r.forward2D(
        table.data(), width, height, range, gradientRange, view, opt, pixels, out.rgba, records);
      r.backward2D(table.data(), width, height, range, gradientRange, view, opt, pixels, records, g,
        out.dTable);
    }
    else
    {
      r.forward(table.data(), width, range[0], range[1], view, opt, pixels, out.rgba, records);
      r.backward(
        table.data(), width, range[0], range[1], view, opt, pixels, records, g, out.dTable);
    }
  };
  if (boxes.empty())
  {
    Pass out;
    pass(DifferentiableRenderer(whole), out);
    return out;
  }
  ThreadBoard board(static_cast<int>(boxes.size()));
  std::vector<Pass> each(boxes.size());
  const auto errors = runPieces(static_cast<int>(boxes.size()),
    [&](int p)
    {
      auto [piece, brick] = pieceOf(whole, boxes[static_cast<size_t>(p)], 1);
      const DifferentiableRenderer r(piece, brick, std::make_shared<ThreadExchange>(board, p));
      pass(r, each[static_cast<size_t>(p)]);
    });
  for (const auto& e : errors)
    if (e)
      std::rethrow_exception(e);
  for (size_t p = 1; p < each.size(); ++p) // every piece holds the same results
  {
    EXPECT_EQ(each[p].rgba, each[0].rgba);
    EXPECT_EQ(each[p].dTable, each[0].dTable);
  }
  return each[0];
}

double largestDifference(const std::vector<float>& a, const std::vector<float>& b)
{
  EXPECT_EQ(a.size(), b.size());
  double worst = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    worst = std::max(worst, static_cast<double>(std::abs(a[i] - b[i])));
  return worst;
}

double largestMagnitude(const std::vector<float>& a)
{
  double m = 0;
  for (float v : a)
    m = std::max(m, static_cast<double>(std::abs(v)));
  return m;
}

std::vector<std::vector<Box>> splitsOf(const Volume& vol)
{
  const auto& d = vol.dims();
  const Box whole{ 0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1 };
  std::vector<std::vector<Box>> splits;
  for (int n : { 2, 3 })
  {
    splits.emplace_back();
    bisect(whole, n, splits.back());
  }
  splits.push_back(unevenSplit(vol)); // with a piece one plane thick (owns no cell)
  return splits;
}

} // namespace

// The adjoint of sort-last compositing, for each piece, against central differences.
TEST(SortLast, CompositePixelsAdjointMatchesFiniteDifferences)
{
  const int pieces = 3;
  const std::int64_t n = 5;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<std::vector<float>> rgba(pieces, std::vector<float>(4 * n)),
    keys(pieces, std::vector<float>(n));
  for (int p = 0; p < pieces; ++p)
    for (std::int64_t q = 0; q < n; ++q)
    {
      const float a = u(rng);
      for (int c = 0; c < 3; ++c)
        rgba[p][4 * q + c] = a * u(rng); // premultiplied
      rgba[p][4 * q + 3] = a;
      keys[p][q] = q == 2 && p == 1 ? std::numeric_limits<float>::infinity() : 10 * u(rng);
    }
  std::vector<float> w(4 * n);
  for (auto& v : w)
    v = u(rng) - 0.5f;
  auto loss = [&]
  {
    std::vector<const float*> c, k;
    for (int p = 0; p < pieces; ++p)
    {
      c.push_back(rgba[p].data());
      k.push_back(keys[p].data());
    }
    std::vector<float> out(4 * n), front(n), back(4 * n);
    compositePixels(c, k, n, 0, out.data(), front.data(), back.data());
    double l = 0;
    for (size_t i = 0; i < out.size(); ++i)
      l += static_cast<double>(w[i]) * out[i];
    return l;
  };
  for (int mine = 0; mine < pieces; ++mine)
  {
    std::vector<const float*> c, k;
    for (int p = 0; p < pieces; ++p)
    {
      c.push_back(rgba[p].data());
      k.push_back(keys[p].data());
    }
    std::vector<float> out(4 * n), front(n), back(4 * n), d(4 * n);
    compositePixels(c, k, n, mine, out.data(), front.data(), back.data());
    compositePixelsAdjoint(w.data(), front.data(), back.data(), n, d.data());
    for (std::int64_t i = 0; i < 4 * n; ++i)
    {
      if (mine == 1 && i / 4 == 2)
        continue; // no samples on this ray: its values are never composited
      const float keep = rgba[mine][i], h = 1e-2f;
      rgba[mine][i] = keep + h;
      const double up = loss();
      rgba[mine][i] = keep - h;
      const double down = loss();
      rgba[mine][i] = keep;
      EXPECT_NEAR(d[i], (up - down) / (2 * h), 1e-4) << "piece " << mine << " value " << i;
    }
  }
}

// Forward and backward over pieces give the whole's image and table gradient.
TEST(DifferentiableRenderer, PiecesGiveTheWholeImageAndGradient)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const RayCaster caster(vol);
  const TransferTable1D t1 = caster.paraviewTable(pieceTF());
  std::vector<GaussianPrimitive> prims(2);
  prims[0].mean = { 120, 10 };
  prims[0].stddev = { 25, 8 };
  prims[0].rgb = { 0.9, 0.5, 0.2 };
  prims[0].opacity = 0.6;
  prims[1].mean = { 200, 30 };
  prims[1].stddev = { 20, 15 };
  prims[1].rgb = { 0.2, 0.5, 1.0 };
  prims[1].opacity = 0.8;
  const auto grange = vol.gradientMagnitudeRange();
  const TransferTable2D t2 = rasterize2D(prims, vol.range(), grange, 32, 16);
  std::vector<int> pixels;
  std::mt19937 rng(5);
  for (int p = 0; p < 48 * 40; ++p)
    if (rng() % 3 == 0)
      pixels.push_back(p);
  for (const auto& boxes : splitsOf(vol))
    for (int v = 0; v < 2; ++v)
    {
      View view = orbitView(vol, v == 0 ? 30 : 200, v == 1);
      View lit = view;
      lit.lighting.shade = true;
      lit.lighting.specular = 0.5;
      lit.lighting.specularPower = 30;
      const std::string where = std::to_string(boxes.size()) + " pieces, view " + std::to_string(v);
      struct Case
      {
        const char* name;
        bool twoD;
        const View* view;
      };
      for (const Case& c :
        { Case{ "1D", false, &view }, Case{ "lit", false, &lit }, Case{ "2D lit", true, &lit } })
      {
        const std::vector<float>& table = c.twoD ? t2.rgba : t1.rgba;
        const int w = c.twoD ? t2.width : t1.width, h = c.twoD ? t2.height : 1;
        const Pass whole = runPass(vol, {}, c.twoD, *c.view, pixels, table, w, h, grange);
        const Pass parts = runPass(vol, boxes, c.twoD, *c.view, pixels, table, w, h, grange);
        EXPECT_GT(largestMagnitude(whole.rgba), 0.1) << where << " " << c.name;
        EXPECT_LE(largestDifference(parts.rgba, whole.rgba), 1e-5) << where << " " << c.name;
        EXPECT_LE(
          largestDifference(parts.dTable, whole.dTable), 1e-4 * largestMagnitude(whole.dTable))
          << where << " " << c.name;
      }
    }
}

// The reconstruction over pieces takes the whole's steps: 1D and 2D.
TEST(Reconstruction, PiecesReconstructTheWholeOnesTransferFunction)
{
  const Volume vol = blobVolume(ScalarType::Float32);
  const View view = orbitView(vol, 40, false);
  const Image target = RayCaster(vol).render(RayCaster(vol).paraviewTable(pieceTF()), view);
  const auto& d = vol.dims();
  std::vector<Box> boxes;
  bisect({ 0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1 }, 3, boxes);
  for (bool twoD : { false, true })
  {
    ReconstructionOptions opt;
    opt.twoD = twoD;
    opt.bins = 32;
    opt.gradientBins = 8;
    opt.iterations = 25;
    opt.raysPerIteration = 600;
    opt.render.terminationOpacity = 1.0;
    const ReconstructionResult whole =
      reconstructTransferFunction(DifferentiableRenderer(vol), { { target, view } }, opt);
    ThreadBoard board(static_cast<int>(boxes.size()));
    std::vector<ReconstructionResult> each(boxes.size());
    std::vector<double> gradientMax(boxes.size());
    const auto errors = runPieces(static_cast<int>(boxes.size()),
      [&](int p)
      {
        auto [piece, brick] = pieceOf(vol, boxes[static_cast<size_t>(p)], 1);
        // the pieces agree on the gradient range (MPI: an all-reduce of the maxima)
        for (size_t q = 0; q < boxes.size(); ++q)
        {
          auto [other, otherBrick] = pieceOf(vol, boxes[q], 1);
          brick.wholeGradientRange[1] =
            std::max(brick.wholeGradientRange[1], otherBrick.gradientMagnitudeMax(other));
        }
        gradientMax[static_cast<size_t>(p)] = brick.wholeGradientRange[1];
        const DifferentiableRenderer r(piece, brick, std::make_shared<ThreadExchange>(board, p));
        each[static_cast<size_t>(p)] = reconstructTransferFunction(r, { { target, view } }, opt);
      });
    for (const auto& e : errors)
      if (e)
        std::rethrow_exception(e);
    EXPECT_EQ(gradientMax[0], vol.gradientMagnitudeRange()[1]);
    for (const auto& r : each)
    {
      ASSERT_EQ(r.iterations, whole.iterations);
      ASSERT_EQ(r.loss.size(), whole.loss.size());
      for (size_t i = 0; i < r.loss.size(); ++i)
        EXPECT_NEAR(r.loss[i], whole.loss[i], 1e-4 * whole.loss[0]) << "step " << i;
      const auto& a = twoD ? r.table2D.rgba : r.table1D.rgba;
      const auto& b = twoD ? whole.table2D.rgba : whole.table1D.rgba;
      EXPECT_LE(largestDifference(a, b), 1e-3) << (twoD ? "2D" : "1D");
      EXPECT_EQ(a, (twoD ? each[0].table2D.rgba : each[0].table1D.rgba)); // identical on all
    }
  }
}

// A piece whose local pass fails (here: Shade without the ghost points its gradient needs)
// throws its error; the others throw PieceFailed after the exchange instead of waiting.
TEST(DifferentiableRenderer, AFailingPieceStopsEveryPiece)
{
  const Volume vol = blobVolume(ScalarType::UInt8);
  const auto& d = vol.dims();
  std::vector<Box> boxes;
  bisect({ 0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1 }, 2, boxes);
  View lit = orbitView(vol, 30, false);
  lit.lighting.shade = true;
  const TransferTable1D t = RayCaster(vol).paraviewTable(pieceTF());
  ThreadBoard board(2);
  const auto errors = runPieces(2,
    [&](int p)
    {
      auto [piece, brick] = pieceOf(vol, boxes[static_cast<size_t>(p)], p == 1 ? 0 : 1);
      const DifferentiableRenderer r(piece, brick, std::make_shared<ThreadExchange>(board, p));
      std::vector<float> rgba;
      std::vector<RayRecord> records;
      r.forward(t.rgba.data(), t.width, t.min, t.max, lit, {}, {}, rgba, records);
    });
  ASSERT_TRUE(errors[0] && errors[1]);
  try
  {
    std::rethrow_exception(errors[0]);
  }
  catch (const PieceFailed&)
  {
  }
  catch (const std::exception& e)
  {
    ADD_FAILURE() << "piece 0 threw " << e.what();
  }
  try
  {
    std::rethrow_exception(errors[1]);
  }
  catch (const PieceFailed&)
  {
    ADD_FAILURE() << "piece 1 did not report its own error";
  }
  catch (const Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("ghost"), std::string::npos) << e.what();
  }
}
