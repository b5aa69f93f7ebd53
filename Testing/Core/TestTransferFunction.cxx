// TestTransferFunction.cxx: ParaView TF evaluation against hand-computed values (midpoint,
// sharpness, colour spaces), table baking rules, dense table -> control points, preset and 2D
// JSON reading/writing and their errors. Tolerances: 1e-12 for closed forms, 2e-3 for colour
// values quoted from ParaView with 3-4 digits.
#include "Common/Error.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace ddg;

TEST(PiecewiseFunction, LinearMidpointSharpnessStep)
{
  // linear: halfway
  EXPECT_NEAR(piecewiseSegment(0.5, 0.0, 1.0, 0.5, 0.0), 0.5, 1e-12);
  // midpoint 0.25: at s = 0.25 the value is halfway; at s = 0.625 it is 0.75
  EXPECT_NEAR(piecewiseSegment(0.25, 0.0, 1.0, 0.25, 0.0), 0.5, 1e-12);
  EXPECT_NEAR(piecewiseSegment(0.625, 0.0, 1.0, 0.25, 0.0), 0.75, 1e-12);
  // sharpness 1: step at the (remapped) half
  EXPECT_EQ(piecewiseSegment(0.49, 0.2, 0.8, 0.5, 1.0), 0.2);
  EXPECT_EQ(piecewiseSegment(0.51, 0.2, 0.8, 0.5, 1.0), 0.8);
  // sharpness 0.5 at s = 0.25: s' = 0.5 (0.5)^(1 + 5) = 0.0078125; Hermite with slope term
  // t = 0.5 (y2 - y1): h1 y1 + h2 y2 + (h3 + h4) t
  const double s = 0.5 * std::pow(0.5, 6.0);
  const double ss = s * s, sss = ss * s;
  const double expected = (2 * sss - 3 * ss + 1) * 0.0 + (-2 * sss + 3 * ss) * 1.0 +
    ((sss - 2 * ss + s) + (sss - ss)) * 0.5;
  EXPECT_NEAR(piecewiseSegment(0.25, 0.0, 1.0, 0.5, 0.5), expected, 1e-12);
}

TEST(TransferFunction1D, ClampsOutsideAndHitsNodes)
{
  TransferFunction1D tf;
  tf.color = { { 10, 1, 0, 0 }, { 20, 0, 0, 1 } };
  tf.opacity = { { 10, 0.1 }, { 20, 0.9 } };
  EXPECT_EQ(tf.evaluateOpacity(-5), 0.1);
  EXPECT_EQ(tf.evaluateOpacity(50), 0.9);
  EXPECT_NEAR(tf.evaluateOpacity(15), 0.5, 1e-12);
  EXPECT_NEAR(tf.evaluateOpacity(20), 0.9, 1e-12);
  auto c = tf.evaluateColor(12.5);
  EXPECT_NEAR(c[0], 0.75, 1e-12);
  EXPECT_NEAR(c[2], 0.25, 1e-12);
  c = tf.evaluateColor(100);
  EXPECT_EQ(c[2], 1.0);
}

TEST(ColorSpace, VtkMathConversions)
{
  // sRGB red in CIELAB (D65): L 53.24, a 80.09, b 67.20 (vtkMath constants, 2 decimals)
  const auto lab = rgbToLab({ 1, 0, 0 });
  EXPECT_NEAR(lab[0], 53.24, 0.02);
  EXPECT_NEAR(lab[1], 80.09, 0.05);
  EXPECT_NEAR(lab[2], 67.20, 0.05);
  const auto back = labToRgb(rgbToLab({ 0.2, 0.6, 0.9 }));
  EXPECT_NEAR(back[0], 0.2, 1e-3);
  EXPECT_NEAR(back[1], 0.6, 1e-3);
  EXPECT_NEAR(back[2], 0.9, 1e-3);
  const auto hsv = rgbToHsv({ 0, 1, 1 });
  EXPECT_NEAR(hsv[0], 0.5, 1e-12);
  const auto rgb = hsvToRgb({ 2.0 / 3.0, 1, 1 });
  EXPECT_NEAR(rgb[2], 1.0, 1e-12);
  EXPECT_NEAR(rgb[0], 0.0, 1e-12);
}

TEST(ColorSpace, DivergingCoolToWarmMidpointIsMorelandGrey)
{
  // ParaView's "Cool to Warm": endpoints (0.231, 0.298, 0.753) and (0.706, 0.016, 0.149);
  // Moreland's white point (M = 88) at s = 0.5 is (0.865, 0.865, 0.865).
  const RGB cool{ 0.231373, 0.298039, 0.752941 }, warm{ 0.705882, 0.0156863, 0.14902 };
  const auto mid = interpolateColor(ColorSpace::Diverging, false, 0.5, cool, warm);
  for (double c : mid)
  {
    EXPECT_NEAR(c, 0.865, 2e-3);
  }
  const auto start = interpolateColor(ColorSpace::Diverging, false, 0.0, cool, warm);
  EXPECT_NEAR(start[0], cool[0], 2e-3);
  EXPECT_NEAR(start[2], cool[2], 2e-3);
}

TEST(ColorSpace, HsvInterpolatesHueAndStepTakesRightNode)
{
  // red (h 0) to blue (h 2/3) through green in HSV without wrap: halfway is h 1/3 = green
  const auto g = interpolateColor(ColorSpace::HSV, false, 0.5, { 1, 0, 0 }, { 0, 0, 1 });
  EXPECT_NEAR(g[1], 1.0, 1e-12);
  EXPECT_NEAR(g[0], 0.0, 1e-12);
  // with wrap the short way round goes through magenta
  const auto m = interpolateColor(ColorSpace::HSV, true, 0.5, { 1, 0, 0 }, { 0, 0, 1 });
  EXPECT_NEAR(m[1], 0.0, 1e-12);
  EXPECT_GT(m[0], 0.9);
  const auto s = interpolateColor(ColorSpace::Step, false, 0.2, { 1, 0, 0 }, { 0, 0, 1 });
  EXPECT_EQ(s[2], 1.0);
}

TEST(TransferTable, ParaViewWidthAndLookupConvention)
{
  TransferFunction1D tf;
  tf.color = { { 0, 0, 0, 0 }, { 255, 1, 1, 1 } };
  tf.opacity = { { 0, 0 }, { 255, 1 } };
  EXPECT_EQ(paraviewTableWidth(tf, 0, 255), 1024);
  tf.opacity = { { 0, 0 }, { 0.1, 1 }, { 255, 1 } }; // gap 0.1 -> 2550 -> 4096
  EXPECT_EQ(paraviewTableWidth(tf, 0, 255), 4096);
  const auto t = bakeTable(TransferFunction1D{ "", ColorSpace::RGB, false,
                             { { 0, 0, 0, 0 }, { 1, 1, 1, 1 } }, { { 0, 0 }, { 1, 1 } } },
    0, 1, 5);
  // entries at 0, .25, .5, .75, 1; value 0.5 -> t = 0.5 * 5 - 0.5 = 2 -> entry 2 exactly
  EXPECT_NEAR(t.lookup(0.5)[3], 0.5, 1e-6);
  // value 0.1 -> t = 0 -> entry 0 (texel-centre clamp)
  EXPECT_NEAR(t.lookup(0.1)[3], 0.0, 1e-6);
  // value 0.3 -> t = 1 -> entry 1 = 0.25
  EXPECT_NEAR(t.lookup(0.3)[3], 0.25, 1e-6);
}

TEST(TransferTable, ControlPointsStayWithinTolerance)
{
  TransferTable1D t;
  t.min = -10;
  t.max = 30;
  t.width = 256;
  for (int i = 0; i < t.width; ++i)
  {
    const double x = i / 255.0;
    t.rgba.insert(t.rgba.end(),
      { static_cast<float>(0.5 + 0.5 * std::sin(6 * x)), static_cast<float>(x), 0.3f,
        static_cast<float>(std::exp(-40 * (x - 0.6) * (x - 0.6))) });
  }
  const double tol = 1.0 / 512.0;
  const TransferFunction1D tf = tableToTransferFunction(t, tol);
  EXPECT_LT(tf.color.size(), 64u);
  EXPECT_LT(tf.opacity.size(), 64u);
  tf.validate();
  for (int i = 0; i < t.width; ++i)
  {
    const double x = t.min + i * (t.max - t.min) / (t.width - 1);
    const auto c = tf.evaluateColor(x);
    EXPECT_NEAR(c[0], t.rgba[4 * i], tol + 1e-6);
    EXPECT_NEAR(c[1], t.rgba[4 * i + 1], tol + 1e-6);
    EXPECT_NEAR(tf.evaluateOpacity(x), t.rgba[4 * i + 3], tol + 1e-6);
  }
}

TEST(PresetJson, RoundTripAndErrors)
{
  const std::string text = R"([{"Name": "t", "ColorSpace": "Diverging",
      "RGBPoints": [0, 0, 0, 1, 100, 1, 0, 0], "Points": [0, 0, 0.5, 0, 100, 1, 0.3, 0.2]}])";
  const TransferFunction1D tf = parsePreset(text);
  EXPECT_EQ(tf.colorSpace, ColorSpace::Diverging);
  ASSERT_EQ(tf.opacity.size(), 2u);
  EXPECT_EQ(tf.opacity[1].midpoint, 0.3);
  const TransferFunction1D again = parsePreset(presetToJson(tf));
  EXPECT_EQ(again.color.size(), 2u);
  EXPECT_EQ(again.opacity[1].sharpness, 0.2);

  EXPECT_THROW(parsePreset("[{\"Name\": "), Error);                  // malformed
  EXPECT_THROW(parsePreset("[]"), Error);                            // empty list
  EXPECT_THROW(parsePreset(R"([{"RGBPoints": [0,0,0,0]}])"), Error); // no Points
  EXPECT_THROW(parsePreset(R"([{"RGBPoints": [0,0,0], "Points": [0,0,.5,0]}])"), Error); // not x4
  EXPECT_THROW(
    parsePreset(R"([{"RGBPoints": [5,0,0,0, 1,1,1,1], "Points": [0,0,.5,0]}])"), Error); // unsorted
  EXPECT_THROW(
    parsePreset(R"([{"RGBPoints": [0,0,0,2], "Points": [0,0,.5,0]}])"), Error); // colour > 1
  EXPECT_THROW(
    parsePreset(R"([{"RGBPoints": [0,0,0,0], "Points": [0,-1,.5,0]}])"), Error); // alpha < 0
  EXPECT_THROW(
    parsePreset(
      R"([{"RGBPoints": [0,0,0,0], "Points": [0,0,.5,0], "ColorSpace": "Lab/CIEDE2000"}])"),
    Error);
  EXPECT_THROW(parsePreset(R"([{"RGBPoints": ["a",0,0,0], "Points": [0,0,.5,0]}])"), Error);
}

TEST(TwoDJson, PrimitivesAndTableRoundTrip)
{
  const std::string text = R"({"Format": "ddg-transfer-function-2d", "Version": 1, "Name": "x",
      "ValueRange": [0, 255], "GradientRange": [0, 50], "Size": [32, 16],
      "Primitives": [{"mean": [100, 10], "stddev": [20, 5], "rgb": [1, 0.5, 0], "opacity": 0.7}]})";
  const auto f = parseTransferFunctionFile(text, "test");
  ASSERT_TRUE(f.is2D);
  const TransferTable2D t = f.tf2D.bake();
  EXPECT_EQ(t.width, 32);
  EXPECT_EQ(t.height, 16);
  // peak opacity near the primitive's mean
  EXPECT_NEAR(t.lookup(100, 10)[3], 0.7, 0.05);
  TransferFunction2D withTable = f.tf2D;
  withTable.table = t;
  const auto again = parseTransferFunction2D(transferFunction2DToJson(withTable));
  EXPECT_EQ(again.table.rgba.size(), t.rgba.size());
  EXPECT_THROW(
    parseTransferFunction2D(
      R"({"Format": "ddg-transfer-function-2d", "ValueRange": [0, 1], "GradientRange": [0, 1]})"),
    Error);
  EXPECT_THROW(
    parseTransferFunction2D(
      R"({"Format": "ddg-transfer-function-2d", "ValueRange": [1, 0], "GradientRange": [0, 1], "Primitives": []})"),
    Error);
  EXPECT_THROW(
    parseTransferFunction2D(
      R"({"Format": "ddg-transfer-function-2d", "ValueRange": [0, 1], "GradientRange": [0, 1],
      "Primitives": [{"mean": [0, 0], "stddev": [0, 1], "rgb": [1, 1, 1], "opacity": 1}]})"),
    Error);
}

// ParaView's 2D boxes (what `ddg export --format paraview-2d` writes) are a TF file too; they
// become a table only with a volume (RayCaster::resolve).
TEST(TwoDJson, ParaViewBoxesAreATransferFunctionFile)
{
  const auto f = parseTransferFunctionFile(
    R"({"Boxes": [10, 0, 50, 20, 1, 0.5, 0.2, 0.6], "Range": [0, 255, 0, 63.75],
        "OutputDimensions": [1024, 1024]})",
    "boxes");
  EXPECT_TRUE(f.isParaView2D);
  EXPECT_FALSE(f.is2D);
  ASSERT_EQ(f.paraview2D.boxes.size(), 1u);
  EXPECT_EQ(f.paraview2D.boxes[0].width, 50);
  EXPECT_THROW(parseTransferFunctionFile(R"({"Boxes": [10, 0, 50]})", "boxes"), Error);
}
