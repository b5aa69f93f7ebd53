// TestParaViewTransferFunction2D.cxx: ParaView's 2D boxes against hand-computed values of
// vtkPVTransferFunction2D::Build's formulas (1e-12), the fit loss's gradient against central
// finite differences in double precision (relative 1e-5), the fit on targets it can represent
// (boxes) and on our Gaussian primitives (RMSE stated per test), the volume mapping's figures
// and the errors of bad input.
#include "Common/Error.h"
#include "TransferFunction/ParaViewTransferFunction2D.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <random>

using namespace ddg;

namespace
{

// Our TF as an explicit table sampled from a function of (x, y) in ParaView units
// (gradientScale 1): straight rgb and alpha before the opacity correction of exponent e.
TransferFunction2D tableOf(
  const ParaViewTransferFunction2D& pv, double e, int width = 256, int height = 128)
{
  TransferFunction2D tf;
  auto& t = tf.table;
  t.width = width;
  t.height = height;
  t.valueRange = { pv.range[0], pv.range[1] };
  t.gradientRange = { pv.range[2], pv.range[3] };
  t.rgba.resize(4 * static_cast<size_t>(width) * height);
  for (int j = 0; j < height; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      // the table's texel convention: entry i at range[0] + (i + 0.5) * step
      const double x = pv.range[0] + (i + 0.5) * (pv.range[1] - pv.range[0]) / width;
      const double y = pv.range[2] + (j + 0.5) * (pv.range[3] - pv.range[2]) / height;
      const auto c = pv.evaluate(x, y);
      float* out = &t.rgba[4 * (static_cast<size_t>(j) * width + i)];
      for (int q = 0; q < 3; ++q)
      {
        out[q] = static_cast<float>(std::min(1.0, c[q]));
      }
      // per-sample alpha A = 1 - (1 - a)^e  <=>  a = 1 - (1 - A)^(1 / e)
      out[3] = static_cast<float>(1 - std::pow(1 - std::min(c[3], 1.0), 1 / e));
    }
  }
  return tf;
}

ParaViewTransfer2DMapping unitMapping(const std::array<double, 4>& range, double e)
{
  ParaViewTransfer2DMapping m;
  m.valueRange = { range[0], range[1] };
  m.gradientScale = 1;
  m.gradientMax = range[3];
  m.opacityExponent = e;
  return m;
}

} // namespace

TEST(ParaViewBoxes, EvaluateFollowsBuild)
{
  ParaViewTransferFunction2D pv;
  pv.range = { 0, 10, 0, 4 };
  pv.boxes.push_back({ 2, 1, 4, 2, { 1, 0, 0, 0.8 } }); // centre (4, 2)
  auto c = pv.evaluate(4, 2);
  EXPECT_NEAR(c[0], 1, 1e-12);
  EXPECT_NEAR(c[3], 0.8, 1e-12);
  // (x - cx) / w = 0.45: alpha = a exp(-0.45^2 / (2 0.3^2))
  c = pv.evaluate(5.8, 2);
  EXPECT_NEAR(c[3], 0.8 * std::exp(-0.45 * 0.45 / 0.18), 1e-12);
  EXPECT_NEAR(c[0], 1, 1e-12); // colour constant inside the box
  c = pv.evaluate(6.01, 2);    // outside: nothing at all
  EXPECT_EQ(c[0], 0);
  EXPECT_EQ(c[3], 0);
  // a second box over the first: straight colour, c.rgb = f.rgb + c.rgb (1 - f.a)
  pv.boxes.push_back({ 3, 1, 2, 2, { 0, 0.5, 0, 0.5 } }); // centre (4, 2)
  c = pv.evaluate(4, 2);
  EXPECT_NEAR(c[0], 1 * (1 - 0.5), 1e-12);
  EXPECT_NEAR(c[1], 0.5, 1e-12);
  EXPECT_NEAR(c[3], 0.5 + 0.8 * (1 - 0.5), 1e-12);
  // the proxy's property layout
  const auto j = nlohmann::json::parse(pv.toJson());
  ASSERT_EQ(j["Boxes"].size(), 16u);
  EXPECT_EQ(j["Boxes"][8].get<double>(), 3);
  EXPECT_EQ(j["Boxes"][15].get<double>(), 0.5);
  EXPECT_EQ(j["Range"][1].get<double>(), 10);
  EXPECT_EQ(j["OutputDimensions"][0].get<int>(), 1024);
}

TEST(ParaViewBoxes, LossGradientMatchesFiniteDifferences)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const std::array<double, 4> range{ -1, 3, 0, 2 };
  const int gw = 24, gh = 16;
  std::vector<ParaViewBox> boxes;
  for (int k = 0; k < 3; ++k)
  {
    boxes.push_back({ -1 + 2 * u(rng), 0.8 * u(rng), 1 + 2 * u(rng), 0.6 + 0.8 * u(rng),
      { u(rng), u(rng), u(rng), 0.2 + 0.7 * u(rng) } });
  }
  std::vector<double> target(4 * gw * gh);
  for (auto& t : target)
  {
    t = u(rng);
  }
  std::vector<double> grad;
  paraViewBoxLoss(boxes, range, gw, gh, target, &grad);
  ASSERT_EQ(grad.size(), 24u);
  int checked = 0;
  for (size_t k = 0; k < boxes.size(); ++k)
  {
    for (int q = 0; q < 8; ++q)
    {
      auto plus = boxes, minus = boxes;
      auto param = [&](std::vector<ParaViewBox>& b) -> double&
      {
        switch (q)
        {
          case 0:
            return b[k].x;
          case 1:
            return b[k].y;
          case 2:
            return b[k].width;
          case 3:
            return b[k].height;
          default:
            return b[k].rgba[q - 4];
        }
      };
      const double eps = 1e-7;
      param(plus) += eps;
      param(minus) -= eps;
      const double fd = (paraViewBoxLoss(plus, range, gw, gh, target) -
                          paraViewBoxLoss(minus, range, gw, gh, target)) /
        (2 * eps);
      EXPECT_NEAR(grad[8 * k + q], fd, 1e-5 * std::max(1.0, std::abs(fd)))
        << "box " << k << " parameter " << q;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 24);
}

TEST(ParaViewBoxes, FitRecoversATargetMadeOfBoxes)
{
  // Three boxes make the target; the fit starts from the table (greedy placement), not from
  // them. The boxes' own evaluation at the fit grid is the oracle.
  ParaViewTransferFunction2D truth;
  truth.range = { 0, 100, 0, 25 };
  truth.boxes = { { 10, 2, 20, 8, { 0.9, 0.6, 0.3, 0.5 } },
    { 55, 10, 30, 10, { 0.2, 0.4, 1, 0.3 } }, { 70, 1, 12, 5, { 1, 1, 1, 0.9 } } };
  const double e = 0.35;
  ParaViewBoxFitOptions options;
  options.maxBoxes = 6;
  ParaViewBoxFitReport report;
  const auto fit =
    fitParaViewBoxes(tableOf(truth, e), unitMapping(truth.range, e), options, &report);
  EXPECT_LE(fit.boxes.size(), 6u);
  EXPECT_GE(fit.boxes.size(), 3u);
  EXPECT_EQ(fit.range, truth.range);
  EXPECT_NEAR(report.maxAlpha, 0.9, 0.02);
  EXPECT_LT(report.rmse, 0.5 * report.initialRmse);
  EXPECT_LT(report.rmse, 0.01);       // measured 0.0045 (from 0.024 placed greedily)
  EXPECT_LT(report.alphaRmse, 0.015); // measured 0.0071
  // the fitted function agrees with the truth at the three box centres (within 0.1 alpha)
  for (const auto& b : truth.boxes)
  {
    const double x = b.x + b.width / 2, y = b.y + b.height / 2;
    EXPECT_NEAR(fit.evaluate(x, y)[3], std::min(1.0, truth.evaluate(x, y)[3]), 0.1) << x;
  }
}

TEST(ParaViewBoxes, FitOfGaussianPrimitivesStartsOneBoxEach)
{
  // Two of our primitives on a 64^3 volume of spacing 0.5, value range 0..255: ParaView's Y is
  // G * 0.5 (G our per-sample gradient axis); alpha per sample with exponent d / unit.
  const auto m =
    ParaViewTransfer2DMapping::forVolume({ 64, 64, 64 }, { 0.5, 0.5, 0.5 }, { 0, 255 }, 0.2, 0.866);
  EXPECT_NEAR(m.gradientScale, 0.5, 1e-12); // the mean spacing
  EXPECT_NEAR(m.gradientMax, 63.75, 1e-12);
  EXPECT_NEAR(m.opacityExponent, 0.2 / 0.866, 1e-12);
  TransferFunction2D tf;
  tf.table.valueRange = { 0, 255 };
  tf.table.gradientRange = { 0, 120 };
  GaussianPrimitive a, b;
  a.mean = { 80, 20 };
  a.stddev = { 10, 8 };
  a.rgb = { 1, 0.5, 0.2 };
  a.opacity = 0.6;
  b.mean = { 180, 60 };
  b.stddev = { 15, 20 };
  b.rgb = { 0.3, 0.6, 1 };
  b.opacity = 0.9;
  tf.primitives = { a, b };
  ParaViewBoxFitReport report;
  const auto fit = fitParaViewBoxes(tf, m, {}, &report);
  ASSERT_EQ(fit.boxes.size(), 2u);
  // the stronger primitive is composited last; its centre is near its mean in ParaView units
  EXPECT_NEAR(fit.boxes[1].x + fit.boxes[1].width / 2, 180, 5);
  EXPECT_NEAR(fit.boxes[1].y + fit.boxes[1].height / 2, 60 * m.gradientScale, 5);
  EXPECT_NEAR(fit.boxes[1].rgba[2], 1, 0.1);
  EXPECT_LE(report.rmse, report.initialRmse);
  EXPECT_LT(report.alphaRmse, 0.1 * report.maxAlpha);
}

TEST(ParaViewBoxes, BadInputIsRefused)
{
  TransferFunction2D empty;
  const auto m = unitMapping({ 0, 1, 0, 1 }, 0.5);
  EXPECT_THROW(fitParaViewBoxes(empty, m), Error); // neither table nor primitives
  TransferFunction2D tf;
  tf.primitives.push_back({});
  ParaViewBoxFitOptions bad;
  bad.maxBoxes = 0;
  EXPECT_THROW(fitParaViewBoxes(tf, m, bad), Error);
  auto flat = m;
  flat.opacityExponent = std::nan("");
  EXPECT_THROW(fitParaViewBoxes(tf, flat), Error);
  EXPECT_THROW(
    ParaViewTransfer2DMapping::forVolume({ 8, 8, 8 }, { 1, 1, 1 }, { 3, 3 }, 0.5, 1), Error);
  EXPECT_THROW(
    ParaViewTransfer2DMapping::forVolume({ 8, 8, 8 }, { 1, 1, 1 }, { 0, 3 }, 0, 1), Error);
  EXPECT_THROW(paraViewBoxLoss({}, { 0, 1, 1, 0 }, 2, 2, std::vector<double>(16)), Error);
  EXPECT_THROW(paraViewBoxLoss({}, { 0, 1, 0, 1 }, 2, 2, std::vector<double>(15)), Error);
}

// The function image as vtkPVTransferFunction2D::Build makes it, from its formulas by hand:
// pixel (i, j) at x = R0 + i (R1 - R0) / W, each box's 128 x 128 8-bit texture (colour and the
// Gaussian alpha truncated to 1/255), the texel below the pixel, composited in box order.
// (Checked once against ParaView 5.11's own image of these boxes: equal in every value.)
TEST(ParaViewBoxes, FunctionImageFollowsBuild)
{
  ParaViewTransferFunction2D tf;
  tf.boxes = { { 10, 5, 40, 20, { 0.8, 0.3, 0.2, 0.7 } },
    { 30, 10, 20, 30, { 0.1, 0.5, 0.9, 0.5 } } };
  tf.range = { 0, 100, 0, 50 };
  tf.outputDimensions = { 1024, 1024 };
  const auto image = tf.functionImage();
  ASSERT_EQ(image.size(), 4u * 1024 * 1024);
  auto texel = [](const ParaViewBox& b, double x, double y, float out[4])
  {
    const int tx = static_cast<int>((x - b.x) / (b.width / 128));
    const int ty = static_cast<int>((y - b.y) / (b.height / 128));
    const double r2 = (tx - 64.0) * (tx - 64.0) + (ty - 64.0) * (ty - 64.0);
    const double sigma = 0.3 * 128;
    for (int c = 0; c < 3; ++c)
      out[c] = static_cast<float>(static_cast<int>(b.rgba[c] * 255) / 255.0);
    out[3] = static_cast<float>(
      static_cast<int>(b.rgba[3] * 255 * std::exp(-r2 / (2 * sigma * sigma))) / 255.0);
  };
  const double sx = 100.0 / 1024, sy = 50.0 / 1024;
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{
         { 200, 200 }, { 300, 300 }, { 350, 400 }, { 10, 10 }, { 500, 900 }, { 103, 103 } })
  {
    const double x = i * sx, y = j * sy;
    float expected[4] = { 0, 0, 0, 0 };
    for (const auto& b : tf.boxes)
    {
      if (i < static_cast<int>(b.x / sx) || i >= static_cast<int>((b.x + b.width) / sx) ||
        j < static_cast<int>(b.y / sy) || j >= static_cast<int>((b.y + b.height) / sy))
        continue;
      float t[4];
      texel(b, x, y, t);
      for (int c = 0; c < 3; ++c)
        expected[c] = t[c] + expected[c] * (1 - t[3]);
      expected[3] = t[3] + expected[3] * (1 - t[3]);
    }
    const float* got = &image[4 * (static_cast<size_t>(j) * 1024 + i)];
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(got[c], expected[c], 1e-6) << "pixel " << i << ", " << j << " channel " << c;
  }
  // (350, 400) lies in both boxes: the second composited over the first
  EXPECT_GT(image[4 * (400 * 1024 + 350) + 3], 0.5f);
}

// As our 2D table: the image over the data range and the gradient axis up to gradientMax /
// gradientScale, alpha made per unit distance again (1 - (1 - A)^(1 / e)), ParaView's sizes only.
TEST(ParaViewBoxes, TableUndoesTheOpacityCorrection)
{
  ParaViewTransferFunction2D tf;
  tf.boxes = { { 10, 5, 40, 20, { 0.8, 0.3, 0.2, 0.7 } } };
  tf.range = { 0, 100, 0, 50 };
  ParaViewTransfer2DMapping m;
  m.valueRange = { -20, 180 };
  m.gradientScale = 0.5;
  m.gradientMax = 50;
  m.opacityExponent = 0.25;
  const TransferTable2D t = tf.table(m);
  EXPECT_EQ(t.width, 1024);
  EXPECT_EQ(t.height, 1024);
  EXPECT_EQ(t.valueRange[0], -20);
  EXPECT_EQ(t.valueRange[1], 180);
  EXPECT_DOUBLE_EQ(t.gradientRange[1], 100); // 50 / 0.5
  const auto image = tf.functionImage();
  const size_t p = 4 * (200 * 1024 + 300);
  ASSERT_GT(image[p + 3], 0.1f);
  EXPECT_NEAR(1 - std::pow(1 - t.rgba[p + 3], 0.25), image[p + 3], 1e-5);
  EXPECT_EQ(t.rgba[p], image[p]);
  tf.outputDimensions = { 10, 10 }; // ParaView's default: its mapper resamples it
  EXPECT_THROW(tf.table(m), Error);
}

TEST(ParaViewBoxes, FromJsonReadsWhatToJsonWrites)
{
  ParaViewTransferFunction2D tf;
  tf.boxes = { { 1, 2, 3, 4, { 0.1, 0.2, 0.3, 0.4 } }, { 5, 6, 7, 8, { 0.5, 0.6, 0.7, 0.8 } } };
  tf.range = { 0, 10, 0, 20 };
  const auto back = ParaViewTransferFunction2D::fromJson(tf.toJson(), "boxes");
  ASSERT_EQ(back.boxes.size(), 2u);
  EXPECT_EQ(back.boxes[1].x, 5);
  EXPECT_EQ(back.boxes[1].rgba[3], 0.8);
  EXPECT_EQ(back.range[3], 20);
  EXPECT_EQ(back.outputDimensions[0], 1024);
  for (const char* bad : { "[]", "{\"Boxes\": []}", "{\"Boxes\": [1, 2, 3]}",
         "{\"Boxes\": [0, 0, 0, 1, 1, 1, 1, 1]}", "{\"Boxes\": [0, 0, 1, 1, 1, 1, 1, 2]}",
         "{\"Boxes\": [0, 0, 1, 1, 1, 1, 1, 1], \"Range\": [1, 0, 0, 1]}", "{\"Boxes\": " })
  {
    EXPECT_THROW(ParaViewTransferFunction2D::fromJson(bad, "boxes"), Error) << bad;
  }
}
