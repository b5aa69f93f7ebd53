// TestPictureLook.cxx: users' pictures of exemplars (PictureLook.h) — the camera moves, the
// background and overlays, JPEG, the spec's picture_fraction and the dataset's record of a look.
#include "Design/ExemplarGenerator.h"
#include "Gallery/QueryImage.h"
#include "Image/ImageMetrics.h"

#include "TempDir.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace ddg;

namespace
{
// A ball of value 200 in air (0).
Volume ball()
{
  const int n = 24;
  std::vector<float> v;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        v.push_back(std::hypot(i - 11.5, j - 11.5, k - 11.5) < 7 ? 200.0f : 0.0f);
  return Volume({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::Float32);
}

PictureLook plain(int w, int h)
{
  PictureLook k;
  k.width = w;
  k.height = h;
  return k;
}
} // namespace

TEST(PictureLook, CameraMoves)
{
  const Volume vol = ball();
  const View orbit = orbitView(vol, 64, 30, 20, 1.1);
  // no move: the orbit's camera in the look's frame
  const View same = pictureView(orbit, plain(96, 64));
  EXPECT_EQ(same.width, 96);
  EXPECT_EQ(same.height, 64);
  EXPECT_NEAR((same.camera.position - orbit.camera.position).norm(), 0, 1e-9);
  // the same camera (the view-up made orthogonal to the view direction, as ParaView does)
  EXPECT_NEAR((RayGenerator(same).up() - RayGenerator(orbit).up()).norm(), 0, 1e-9);
  // roll 90 degrees: the view-up turns onto the old right (or left) vector, the position stays
  PictureLook rolled = plain(64, 64);
  rolled.roll = 90;
  const View r = pictureView(orbit, rolled);
  const RayGenerator before(orbit);
  EXPECT_NEAR(std::abs(r.camera.viewUp.dot(before.right())), 1, 1e-9);
  EXPECT_NEAR((r.camera.position - orbit.camera.position).norm(), 0, 1e-9);
  // zoom 2: half the distance; pan 0.1 right: the focal point moves 0.2 of the half height
  PictureLook moved = plain(64, 64);
  moved.zoom = 2;
  moved.panRight = 0.1;
  const View m = pictureView(orbit, moved);
  const double d0 = (orbit.camera.position - orbit.camera.focalPoint).norm();
  EXPECT_NEAR((m.camera.position - m.camera.focalPoint).norm(), d0 / 2, 1e-9);
  const double half = d0 / 2 * std::tan(15 * M_PI / 180);
  EXPECT_NEAR(
    (m.camera.focalPoint - orbit.camera.focalPoint).dot(before.right()), 0.2 * half, 1e-9);
}

TEST(PictureLook, BackgroundOverlaysAndJpeg)
{
  const Volume vol = ball();
  const RayCaster caster(vol);
  GaussianPrimitive g;
  g.mean = { 200, 0 };
  g.stddev = { 20, 1 };
  g.rgb = { 1, 0.5, 0.2 };
  g.opacity = 0.8;
  PictureLook look = plain(120, 90);
  look.background = { 0.32, 0.34, 0.43 };
  const View view = pictureView(orbitView(vol, 45, 0, 0, 1), look);
  const Image render = renderDesign(caster, { g }, 1, { 0, 1 }, view);
  // nothing but the background: the render over it
  const Image bare = drawPicture(render, view, look);
  EXPECT_EQ(bare.pixels, compositeOverBackground(render, look.background).pixels);
  // the orientation axes in the lower left: red, yellow or green pixels where the air was
  look.axes = true;
  const Image axes = drawPicture(render, view, look);
  int coloured = 0;
  for (int y = 60; y < 90; ++y)
    for (int x = 0; x < 30; ++x)
      coloured += std::abs(axes.at(x, y, 0) - bare.at(x, y, 0)) > 0.2f;
  EXPECT_GT(coloured, 5);
  // a gradient: the bottom row the first colour, the top row the second
  look.axes = false;
  look.background2 = std::array<double, 3>{ 1, 1, 1 };
  const Image gradient = drawPicture(render, view, look);
  EXPECT_NEAR(gradient.at(0, 89, 0), 0.32f, 0.01f);
  EXPECT_NEAR(gradient.at(0, 0, 0), 1.0f, 0.01f);
  // JPEG: close to the lossless picture, not equal
  look.jpegQuality = 60;
  const Image jpeg = drawPicture(render, view, look);
  const double p = psnr(jpeg, gradient);
  EXPECT_GT(p, 28.0);
  EXPECT_LT(p, 100.0);
  // a render of another size than the view's is refused
  EXPECT_THROW(drawPicture(bare, pictureView(view, plain(64, 64)), plain(64, 64)), Error);
}

TEST(PictureLook, SpecAndDataset)
{
  const auto s = parseDesignSpaceSpec(R"({"picture_fraction": 0.5})");
  EXPECT_EQ(s.pictureFraction, 0.5);
  EXPECT_EQ(parseDesignSpaceSpec(designSpaceSpecToJson(s)).pictureFraction, 0.5);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"picture_fraction": 1.5})"), Error);
  EXPECT_THROW(parseDesignSpaceSpec(R"({"picture_fraction": -0.1})"), Error);

  const Volume vol = ball();
  const auto regions = findFeatureRegions(vol);
  int pictures = 0;
  for (std::uint64_t i = 0; i < 200; ++i)
  {
    const Exemplar e = sampleExemplar(vol, s, regions, 3, i, 32);
    // the look is drawn after everything else: the design and its views are the plain spec's
    const Exemplar u = sampleExemplar(vol, DesignSpaceSpec{}, regions, 3, i, 32);
    EXPECT_FALSE(u.picture);
    EXPECT_EQ(u.viewExp.camera.position, e.viewExp.camera.position);
    EXPECT_EQ(u.primitives.front().rgb, e.primitives.front().rgb);
    if (e.picture)
    {
      ++pictures;
      EXPECT_EQ(e.picture->height, 64);
      EXPECT_GE(e.picture->width, 64);
      EXPECT_LE(std::abs(e.picture->roll), 30.0);
    }
  }
  EXPECT_GT(pictures, 70);
  EXPECT_LT(pictures, 130);

  // a dataset of pictures: the looks read back, the images framed as queries
  DesignSpaceSpec all;
  all.pictureFraction = 1;
  GenerateOptions opt;
  opt.count = 6;
  opt.size = 32;
  const std::string dir = ddg::testing::tempDir() + "/ddg_gen_pictures";
  generateExemplars(vol, all, dir, opt);
  const ExemplarDataset data(dir);
  int shown = 0;
  for (int i = 0; i < opt.count; ++i)
  {
    const Exemplar& x = data.exemplars()[static_cast<size_t>(i)];
    const Exemplar drawn = sampleExemplar(vol, all, data.regions(), opt.seed, i, opt.size);
    ASSERT_TRUE(drawn.picture);
    // a picture that shows nothing (a query would be refused) keeps the clean image, no look
    if (x.picture)
      EXPECT_EQ(pictureLookToJson(*x.picture), pictureLookToJson(*drawn.picture));
    shown += x.picture.has_value();
  }
  EXPECT_GE(shown, 3); // most of the six show the ball
  Image uniform(16, 16, 3);
  std::fill(uniform.pixels.begin(), uniform.pixels.end(), 0.3f);
  EXPECT_FALSE(hasQueryContent(uniform));
  uniform.at(8, 8, 1) = 0.9f;
  EXPECT_TRUE(hasQueryContent(uniform));
  // the first picture again, drawn and framed as the generator does
  const auto first = std::find_if(data.exemplars().begin(), data.exemplars().end(),
    [](const Exemplar& e) { return e.picture.has_value(); });
  ASSERT_NE(first, data.exemplars().end());
  const Exemplar& x = *first;
  const auto index = static_cast<int>(first - data.exemplars().begin());
  const View pv = pictureView(x.viewExp, *x.picture);
  const RayCaster caster(vol);
  RenderOptions ropt;
  ropt.threads = 1;
  const Image picture = drawPicture(renderDesign(caster, x.primitives, 1, { 0, 1 }, pv, ropt), pv,
    *x.picture, { x.primitives.front().rgb });
  const Image framed = prepareQueryImage(picture, opt.size);
  const auto images = data.images(index);
  // the legend differs (one colour here) when the picture has a scalar bar
  EXPECT_GT(psnr(images.rgbExp, framed), x.picture->scalarBar ? 20.0 : 99.0);
  EXPECT_THROW(parsePictureLook(R"({"width": 8})", "test"), Error);
}
