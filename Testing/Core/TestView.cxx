// TestView.cxx: view JSON contract (defaults, errors) and ray generation conventions
// (pixel centres, rows from the top, vertical view angle, parallel scale = half height).
// Rays against VTK's own camera matrices are in Testing/Plugin/TestCameraRays.cxx.
#include "Common/Error.h"
#include "Render/View.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <initializer_list>
#include <string>
#include <utility>

using namespace ddg;

TEST(View, ParsesDefaultsAndRoundTrips)
{
  const View v = parseView(
    R"({"camera": {"position": [0, 0, 10], "focal_point": [0, 0, 0], "view_up": [0, 1, 0]}})");
  EXPECT_EQ(v.width, 512);
  EXPECT_EQ(v.camera.viewAngle, 30.0);
  EXPECT_FALSE(v.opacityUnitDistance.has_value());
  View w = v;
  w.opacityUnitDistance = 2.5;
  w.width = 100;
  const View again = parseView(viewToJson(w));
  EXPECT_EQ(again.width, 100);
  EXPECT_EQ(*again.opacityUnitDistance, 2.5);
}

TEST(View, RejectsDegenerateCamerasAndSizes)
{
  const std::string cam =
    R"("camera": {"position": [0, 0, 10], "focal_point": [0, 0, 0], "view_up": [0, 1, 0]})";
  EXPECT_THROW(parseView("{"), Error);
  EXPECT_THROW(
    parseView(
      R"({"camera": {"position": [0, 0, 0], "focal_point": [0, 0, 0], "view_up": [0, 1, 0]}})"),
    Error);
  EXPECT_THROW(
    parseView(
      R"({"camera": {"position": [0, 0, 5], "focal_point": [0, 0, 0], "view_up": [0, 0, 1]}})"),
    Error);
  EXPECT_THROW(
    parseView(
      R"({"camera": {"position": [0, 0, 5], "focal_point": [0, 0, 0], "view_up": [0, 1, 0], "view_angle": 0}})"),
    Error);
  EXPECT_THROW(parseView("{" + cam + R"(, "size": [0, 10]})"), Error);
  EXPECT_THROW(parseView("{" + cam + R"(, "size": [100000, 100000]})"), Error);
  EXPECT_THROW(parseView("{" + cam + R"(, "size": [10.5, 10]})"), Error);
  EXPECT_THROW(parseView("{" + cam + R"(, "background": [2, 0, 0]})"), Error);
  EXPECT_THROW(parseView("{" + cam + R"(, "opacity_unit_distance": -1})"), Error);
  // a value of the wrong type names its key (not the JSON library's "type must be number")
  const std::string camStart =
    R"({"camera": {"position": [0, 0, 10], "focal_point": [0, 0, 0], "view_up": [0, 1, 0], )";
  for (const auto& [bad, says] : std::initializer_list<std::pair<const char*, const char*>>{
         { R"("view_angle": "wide"}})", R"(camera "view_angle" must be a number)" },
         { R"("parallel_scale": [1]}})", R"(camera "parallel_scale" must be a number)" },
         { R"("parallel_projection": "yes"}})",
           R"(camera "parallel_projection" must be true or false)" } })
  {
    try
    {
      parseView(camStart + bad);
      ADD_FAILURE() << bad << " was read";
    }
    catch (const Error& e)
    {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
  try
  {
    parseView("{" + cam + R"(, "opacity_unit_distance": "2"})");
    ADD_FAILURE() << "a string opacity unit distance was read";
  }
  catch (const Error& e)
  {
    EXPECT_NE(
      std::string(e.what()).find(R"("opacity_unit_distance" must be a number)"), std::string::npos)
      << e.what();
  }
  // ParaView's integer flag is read as its truth (the camera properties take 0 or 1)
  EXPECT_TRUE(parseView(camStart + R"("parallel_projection": 1}})").camera.parallelProjection);
}

TEST(View, LightingDefaultsRoundTripAndErrors)
{
  const std::string cam =
    R"("camera": {"position": [0, 0, 10], "focal_point": [0, 0, 0], "view_up": [0, 1, 0]})";
  // ParaView's defaults, and no "lighting" written for them (existing view files stay as they are)
  const View plain = parseView("{" + cam + "}");
  EXPECT_FALSE(plain.lighting.shade);
  EXPECT_EQ(plain.lighting.ambient, 0.0);
  EXPECT_EQ(plain.lighting.diffuse, 1.0);
  EXPECT_EQ(plain.lighting.specular, 0.0);
  EXPECT_EQ(plain.lighting.specularPower, 100.0);
  EXPECT_EQ(viewToJson(plain).find("lighting"), std::string::npos);
  // each key optional; a round trip keeps them
  const View lit = parseView(
    "{" + cam + R"(, "lighting": {"shade": true, "specular": 0.5, "specular_power": 30}})");
  EXPECT_TRUE(lit.lighting.shade);
  EXPECT_EQ(lit.lighting.diffuse, 1.0);
  EXPECT_EQ(lit.lighting.specular, 0.5);
  EXPECT_EQ(lit.lighting.specularPower, 30.0);
  EXPECT_TRUE(parseView(viewToJson(lit)).lighting == lit.lighting);
  EXPECT_TRUE(parseView("{" + cam + R"(, "lighting": {"shade": 1}})").lighting.shade);
  // unknown keys, wrong types and ParaView's ranges
  for (const char* bad :
    { R"({"shade": true, "specularpower": 30})", R"({"shade": "yes"})", R"({"diffuse": 1.5})",
      R"({"ambient": -0.1})", R"({"specular_power": 128})", R"({"specular": "0.5"})", "[1, 2]" })
  {
    EXPECT_THROW(parseView("{" + cam + R"(, "lighting": )" + bad + "}"), Error) << bad;
  }
  try
  {
    parseView("{" + cam + R"(, "lighting": {"shade": true, "speculr": 0.5}})");
    FAIL();
  }
  catch (const Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("unknown lighting key \"speculr\""), std::string::npos);
  }
}

TEST(View, LightingAloneNeedsNoCamera)
{
  // the carried look's view: only "lighting" is read, so no camera is needed
  EXPECT_FALSE(viewLighting("{}").shade);
  const Lighting lit = viewLighting(R"({"lighting": {"shade": true, "specular": 0.3}})");
  EXPECT_TRUE(lit.shade);
  EXPECT_EQ(lit.specular, 0.3);
  EXPECT_EQ(lit.diffuse, 1.0);
  const std::string full = R"({"camera": {"position": [0, 0, 10], "focal_point": [0, 0, 0],
    "view_up": [0, 1, 0]}, "lighting": {"shade": true, "ambient": 0.2}})";
  EXPECT_TRUE(viewLighting(full) == parseView(full).lighting);
  for (const char* bad : { "[1]", "not json", R"({"lighting": {"diffuse": 2}})",
         R"({"lighting": {"shade": true, "speculr": 0.5}})", R"({"lighting": true})" })
    EXPECT_THROW(viewLighting(bad, "ViewJSON"), Error) << bad;
}

// ParaView 5.11's Reset Camera on Tooth's bounds in a 300 x 500 view (pvpython: Show, Render,
// CameraPosition and CameraParallelScale): a view taller than wide fits the horizontal angle
TEST(View, ResetCameraFollowsParaViewInATallView)
{
  const std::array<double, 6> tooth{ 0, 102, 0, 93, 0, 160 };
  const View tall = resetCameraView(tooth, 300, 500);
  EXPECT_NEAR(tall.camera.position.z() - tall.camera.focalPoint.z(), 665.6299954645581, 1e-6);
  EXPECT_NEAR(tall.camera.parallelScale, 176.09380391648588, 1e-9);
  EXPECT_EQ(tall.camera.focalPoint, Eigen::Vector3d(51, 46.5, 80));
  for (auto [w, h] : { std::pair{ 500, 300 }, std::pair{ 400, 400 } }) // as wide or wider
  {
    const View a = resetCameraView(tooth, w, h), b = defaultView(tooth, w, h);
    EXPECT_EQ(a.camera.position, b.camera.position);
    EXPECT_EQ(a.camera.parallelScale, b.camera.parallelScale);
  }
}

TEST(View, CameraForShapeKeepsThePicturesWidthInANarrowerView)
{
  View picture;
  picture.width = 400;
  picture.height = 200;
  picture.camera.position = { 0, 0, 10 };
  picture.camera.viewAngle = 30;
  picture.camera.parallelScale = 3;
  const auto halfWidth = [](const Camera& c, double aspect, bool parallel)
  { return aspect * (parallel ? c.parallelScale : std::tan(c.viewAngle * M_PI / 360.0)); };
  // a narrower view (300 x 400): the picture's half width at unit distance kept, the rest as is
  const Camera narrow = cameraForShape(picture, 300, 400);
  EXPECT_NEAR(halfWidth(narrow, 0.75, false), halfWidth(picture.camera, 2.0, false), 1e-12);
  EXPECT_NEAR(halfWidth(narrow, 0.75, true), halfWidth(picture.camera, 2.0, true), 1e-12);
  EXPECT_EQ(narrow.position, picture.camera.position);
  EXPECT_EQ(narrow.focalPoint, picture.camera.focalPoint);
  EXPECT_EQ(narrow.viewUp, picture.camera.viewUp);
  // as wide or wider: the camera as it is (more is seen on the sides)
  for (auto [w, h] : { std::pair{ 400, 200 }, std::pair{ 800, 300 } })
  {
    const Camera same = cameraForShape(picture, w, h);
    EXPECT_EQ(same.viewAngle, picture.camera.viewAngle);
    EXPECT_EQ(same.parallelScale, picture.camera.parallelScale);
  }
  // the widest angle VTK takes
  EXPECT_LE(cameraForShape(picture, 1, 1000).viewAngle, 179.0);
}

TEST(RayGenerator, PerspectiveAndParallelConventions)
{
  View v;
  v.width = 200;
  v.height = 100;
  v.camera.position = { 0, 0, 10 };
  v.camera.focalPoint = { 0, 0, 0 };
  v.camera.viewUp = { 0, 1, 0.3 }; // not orthogonal: orthogonalised like vtkCamera
  v.camera.viewAngle = 60;
  RayGenerator g(v);
  Eigen::Vector3d o, d;
  // top-left pixel centre: ndc (-1 + 1/200, 1 - 1/100); tan(30 deg) scales y, times aspect 2 for x
  g.ray(0, 0, o, d);
  const double t = std::tan(M_PI / 6);
  const Eigen::Vector3d expected =
    Eigen::Vector3d((-1 + 1.0 / 200) * t * 2, (1 - 1.0 / 100) * t, -1).normalized();
  EXPECT_NEAR((d - expected).norm(), 0, 1e-12);
  EXPECT_NEAR((o - v.camera.position).norm(), 0, 1e-12);
  v.camera.parallelProjection = true;
  v.camera.parallelScale = 5; // half height
  RayGenerator p(v);
  p.ray(199, 99, o, d);
  EXPECT_NEAR(o[0], (1 - 1.0 / 200) * 5 * 2, 1e-12);
  EXPECT_NEAR(o[1], (-1 + 1.0 / 100) * 5, 1e-12);
  EXPECT_NEAR((d - Eigen::Vector3d(0, 0, -1)).norm(), 0, 1e-12);
}
