// TestMatchEmission.cxx: the colours' screening of the picture match (MatchCamera.h) on a
// synthetic volume whose silhouette is a ball from every direction — the emission model's
// residual is least at the picture's camera, and its image-plane alignments agree with renders
// at the moved cameras. The match that needs it (a translucent CT head from the front) is in
// Testing/Reconstruction/TestMatch.cxx.
#include "Reconstruct/MatchCamera.h"

#include "Reconstruct/MatchParts.h"
#include "Render/RayCaster.h"
#include "VolumePieces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace ddg;
using namespace ddg::matchparts;

namespace
{

// A ball (value 90, a shell a little denser: 110) holding two blobs off its centre (values 200
// and 160) and a rod (value 140): round from every direction, its inside tells directions apart.
Volume ballVolume()
{
  const int n = 36;
  std::vector<float> v;
  auto bump = [](double d, double r) { return std::clamp(1.0 - (d - r) / 1.5, 0.0, 1.0); };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const double x = i - 17.5, y = j - 17.5, z = k - 17.5;
        const double r = std::sqrt(x * x + y * y + z * z);
        double value = bump(r, 15.0) * (r > 13.0 ? 110.0 : 90.0);
        value = std::max(value, 200.0 * bump(std::hypot(x - 6, y - 4, z + 3), 3.5));
        value = std::max(value, 160.0 * bump(std::hypot(x + 5, y + 7, z - 5), 3.0));
        const double rod = std::hypot(y - 6, z - 6); // along x, on one side
        value = std::max(value, 140.0 * bump(rod, 1.8) * (x > -10 && x < 4));
        v.push_back(static_cast<float>(std::floor(value))); // uint8: whole numbers
      }
  return Volume({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::UInt8);
}

TransferFunction1D translucent()
{
  TransferFunction1D tf;
  tf.color = { { 0, 0.2, 0.8, 0.7 }, { 110, 0.3, 0.9, 0.8 }, { 150, 0.9, 0.9, 0.2 },
    { 255, 1.0, 0.3, 0.2 } };
  tf.opacity = { { 0, 0 }, { 70, 0 }, { 100, 0.03 }, { 130, 0.05 }, { 150, 0.5 }, { 255, 0.8 } };
  return tf;
}

// The picture minus its background at w x h (the screen's input).
Image difference(const Image& picture, const std::array<double, 3>& bg, int w, int h)
{
  Image small = resizeImage(picture, w, h);
  for (size_t i = 0; i < small.pixels.size(); ++i)
    small.pixels[i] -= static_cast<float>(bg[i % 3]);
  return small;
}

Mask all(int w, int h)
{
  Mask m(w, h);
  std::fill(m.m.begin(), m.m.end(), 1);
  return m;
}

} // namespace

// The ball at azimuth 40, elevation 15, roll 10 over the palette's background (96 x 72) and the
// screen of that picture.
struct BallPicture
{
  const Volume vol = ballVolume();
  const DifferentiableRenderer renderer{ vol };
  const View base = defaultView(vol, 96, 72);
  const View truth = cameraMove(base, 40, 15, 10, 1.1, { 0.02, -0.01 });
  const std::array<double, 3> bg{ 0.32, 0.34, 0.43 };
  const EmissionScreen screen{ renderer, RenderOptions{},
    difference(
      compositeOverBackground(
        renderer.caster().render(renderer.caster().paraviewTable(translucent()), truth), bg),
      bg, 96, 72),
    all(96, 72) };
};

TEST(MatchEmission, ResidualIsLeastAtThePicturesCamera)
{
  const BallPicture ball;
  const double atTruth = ball.screen.residual(ball.truth);
  for (const auto& other : { cameraMove(ball.base, 70, 15, 10, 1.1, { 0.02, -0.01 }),
         cameraMove(ball.base, 40, 15, 100, 1.1, { 0.02, -0.01 }),
         cameraMove(ball.base, -140, -15, 190, 1.1, { 0.02, -0.01 }) })
    EXPECT_LT(atTruth, 0.6 * ball.screen.residual(other));
}

// The screen counts the volume's values along the rays: its residual at a camera is the same
// whatever the view's lighting (a lit match screens cameras as an unlit one does, and the
// lighting estimate runs the lighting-free stages of the search once: CameraSearchStages).
TEST(MatchEmission, ResidualDoesNotDependOnTheLighting)
{
  const BallPicture ball;
  for (const View& at : { ball.truth, cameraMove(ball.base, -140, -15, 190, 1.1, { 0.02, -0.01 }) })
  {
    View lit = at, specular = at;
    lit.lighting.shade = specular.lighting.shade = true;
    specular.lighting.specular = 0.5;
    specular.lighting.specularPower = 30;
    const double unlit = ball.screen.residual(at);
    EXPECT_EQ(ball.screen.residual(lit), unlit);
    EXPECT_EQ(ball.screen.residual(specular), unlit);
  }
}

// Over pieces of the volume (ParaView's ranks; here threads exchanging through a ThreadBoard),
// the camera search's two views of the volume are the whole's: the block silhouettes (the
// pieces' block maxima combined) pixel for pixel, the colours' residual (the pieces' sample
// counts summed) to rounding; on 2, 3 and 4 pieces and an uneven split with a piece that owns no
// cell.
TEST(MatchEmission, PiecesSeeTheWholeVolume)
{
  const Volume vol = ballVolume();
  const DifferentiableRenderer renderer(vol);
  const std::array<double, 3> bg{ 0.32, 0.34, 0.43 };
  const View base = defaultView(vol, 64, 48);
  const View truth = cameraMove(base, 40, 15, 10, 1.1, { 0.02, -0.01 });
  const View other = cameraMove(base, -70, 30, 0, 0.9, { 0, 0 });
  const Image picture = compositeOverBackground(
    renderer.caster().render(renderer.caster().paraviewTable(translucent()), truth), bg);
  const Image diff = difference(picture, bg, 64, 48);
  const SilhouetteModel wholeModel(renderer);
  ASSERT_GT(wholeModel.levels(), 2);
  const EmissionScreen wholeScreen(renderer, RenderOptions{}, diff, all(64, 48));
  const double wholeResidual[2] = { wholeScreen.residual(truth), wholeScreen.residual(other) };
  const auto& d = vol.dims();
  for (const auto& split : { 2, 3, 4, 0 })
  {
    std::vector<ddg::testing::Box> boxes = ddg::testing::unevenSplit(vol); // 0: with an empty piece
    if (split > 0)
    {
      boxes.clear();
      ddg::testing::bisect({ 0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1 }, split, boxes);
    }
    const int n = static_cast<int>(boxes.size());
    std::vector<std::vector<Mask>> masks(static_cast<size_t>(n));
    std::vector<std::array<double, 2>> residuals(static_cast<size_t>(n));
    ddg::testing::onPieces(vol, boxes,
      [&](int p, const DifferentiableRenderer& r)
      {
        EXPECT_EQ(r.bounds(), renderer.bounds());
        EXPECT_EQ(r.defaultSampleDistance(), renderer.defaultSampleDistance());
        const SilhouetteModel model(r);
        EXPECT_EQ(model.levels(), wholeModel.levels()); // (no ASSERT: the piece must go on to
        // the screen's exchanges below, else the others wait for it)
        for (int level = 0; level < std::min(model.levels(), wholeModel.levels()); ++level)
        {
          EXPECT_EQ(model.threshold(level), wholeModel.threshold(level));
          masks[static_cast<size_t>(p)].emplace_back();
          model.render(truth, level, 64, 48, masks[static_cast<size_t>(p)].back());
        }
        const EmissionScreen screen(r, RenderOptions{}, diff, all(64, 48));
        residuals[static_cast<size_t>(p)] = { screen.residual(truth), screen.residual(other) };
      });
    for (int p = 0; p < n; ++p)
    {
      ASSERT_EQ(masks[static_cast<size_t>(p)].size(), static_cast<size_t>(wholeModel.levels()));
      for (int level = 0; level < wholeModel.levels(); ++level)
      {
        Mask want;
        wholeModel.render(truth, level, 64, 48, want);
        EXPECT_EQ(masks[static_cast<size_t>(p)][static_cast<size_t>(level)].m, want.m)
          << n << " pieces, level " << level;
      }
      for (int v = 0; v < 2; ++v)
        EXPECT_NEAR(residuals[static_cast<size_t>(p)][static_cast<size_t>(v)], wholeResidual[v],
          1e-6 * wholeResidual[v])
          << n << " pieces, view " << v;
    }
  }
}

TEST(MatchEmission, AlignmentsAgreeWithRendersAtTheMovedCameras)
{
  const Volume vol = ballVolume();
  const DifferentiableRenderer renderer(vol);
  const std::array<double, 3> bg{ 0.32, 0.34, 0.43 };
  const int w = 96, h = 72;
  const View base = defaultView(vol, w, h);
  const View at = cameraMove(base, 40, 15, 0, 1, { 0, 0 });
  // the picture: the same direction, rolled by 30 degrees and dollied by 1.2
  const View moved = cameraMove(base, 40, 15, 30, 1.2, { 0, 0 });
  const Image picture = compositeOverBackground(
    renderer.caster().render(renderer.caster().paraviewTable(translucent()), moved), bg);
  const EmissionScreen screen(renderer, RenderOptions{}, difference(picture, bg, w, h), all(w, h));
  const double c = 0.5 * w, m = 0.5 * h;
  // the identity alignment is the render at `at` itself
  const auto same = screen.residuals(at, { { c, m, c, m, 0, 1 } });
  EXPECT_NEAR(same[0], screen.residual(at), 1e-6);
  // a camera roll of +30 degrees turns the image by -30 degrees (y down), the dolly scales it:
  // that alignment of the render at `at` explains the picture nearly as well as the render at
  // `moved`, and far better than the opposite turn, the inverse scale or no move at all
  const double rho = -30 * M_PI / 180;
  const auto r = screen.residuals(
    at, { { c, m, c, m, rho, 1.2 }, { c, m, c, m, -rho, 1.2 }, { c, m, c, m, rho, 1 / 1.2 } });
  const double exact = screen.residual(moved);
  std::printf("aligned %.4f, rendered there %.4f; opposite turn %.4f, inverse scale %.4f, no move "
              "%.4f\n",
    r[0], exact, r[1], r[2], same[0]);
  EXPECT_LT(r[0], 2 * exact); // a dolly is not quite a zoom, nor a resampled image a render
  for (double wrong : { r[1], r[2], same[0] })
    EXPECT_LT(r[0], 0.5 * wrong);
}

TEST(MatchEmission, OverlaysAreTakenAsBackground)
{
  // a grey square painted over the picture and left out of `care`: what it covers is never read
  // (taken as background), so the residuals are those of the clean picture with the same care,
  // rendered or aligned
  const Volume vol = ballVolume();
  const DifferentiableRenderer renderer(vol);
  const std::array<double, 3> bg{ 0.32, 0.34, 0.43 };
  const int w = 96, h = 72;
  const View truth = cameraMove(defaultView(vol, w, h), 40, 15, 10, 1.1, { 0, 0 });
  const Image clean = difference(
    compositeOverBackground(
      renderer.caster().render(renderer.caster().paraviewTable(translucent()), truth), bg),
    bg, w, h);
  Image marked = clean;
  Mask care = all(w, h);
  for (int y = 20; y < 40; ++y)
    for (int x = 30; x < 50; ++x)
    {
      care(x, y) = 0;
      for (int c = 0; c < 3; ++c)
        marked.pixels[3 * (static_cast<size_t>(y) * w + x) + c] = 0.6f;
    }
  const EmissionScreen a(renderer, RenderOptions{}, clean, care),
    b(renderer, RenderOptions{}, marked, care);
  const View other = cameraMove(defaultView(vol, w, h), 70, -10, 0, 1, { 0, 0 });
  for (const View& v : { truth, other })
    EXPECT_DOUBLE_EQ(a.residual(v), b.residual(v));
  const double c = 0.5 * w, m = 0.5 * h;
  const std::vector<EmissionScreen::Alignment> moves{ { c, m, c, m, 0.3, 1.1 },
    { c, m, c + 5, m - 3, -0.5, 0.9 } };
  const auto ra = a.residuals(other, moves), rb = b.residuals(other, moves);
  for (size_t k = 0; k < moves.size(); ++k)
    EXPECT_DOUBLE_EQ(ra[k], rb[k]);
}

// The hop before the photometric refinement (MatchCamera.h's hopAround): from a camera in a
// shallow basin at elevation +9 whose twin at -9 (azimuth 12 further) is deeper, it moves to the
// grid camera nearest the twin, from where a local search reaches it; in the deeper basin it
// stays; and elevation never leaves [-89, 89].
TEST(MatchCamera, HopsOutOfATwinBasin)
{
  auto basin = [](const CameraParams& c, double az, double el, double depth) {
    return depth * std::exp(-(std::pow(c.az - az, 2) + std::pow(c.el - el, 2)) / (2 * 8.0 * 8.0));
  };
  int evaluations = 0;
  auto loss = [&](const CameraParams& c)
  {
    ++evaluations;
    return 1.0 - basin(c, -76, 9, 0.5) - basin(c, -88, -9, 0.8);
  };
  CameraParams shallow;
  shallow.az = -76;
  shallow.el = 9;
  shallow.roll = 3;
  const CameraParams hop = hopAround(shallow, loss);
  EXPECT_EQ(evaluations, 25);
  EXPECT_DOUBLE_EQ(hop.az, -86);
  EXPECT_DOUBLE_EQ(hop.el, -11);
  EXPECT_DOUBLE_EQ(hop.roll, 3); // only azimuth and elevation move
  EXPECT_LT(loss(hop), loss(shallow));
  CameraParams deep;
  deep.az = -88;
  deep.el = -9;
  const CameraParams stay = hopAround(deep, loss);
  EXPECT_DOUBLE_EQ(stay.az, -88);
  EXPECT_DOUBLE_EQ(stay.el, -9);
  CameraParams top;
  top.el = 85;
  const CameraParams clamped = hopAround(top, [](const CameraParams& c) { return -c.el; });
  EXPECT_DOUBLE_EQ(clamped.el, 89);
}

// Stage 3's choice of the cameras scored: the colours' best-explained camera is scored when it
// looks from a direction no silhouettes' camera does, though its residual misses the margin that
// lets a colours' camera replace a near silhouettes' one (a translucent chest's figure: its
// silhouettes' cameras all 117 degrees or more off, the colours' best 8 degrees off).
TEST(MatchCamera, ScoresTheColoursBestCameraFromAnotherDirection)
{
  View start;
  start.camera.position = { 0, 0, 10 };
  start.camera.focalPoint = { 0, 0, 0 };
  start.camera.viewUp = { 0, 1, 0 };
  auto camera = [](double az, double score, double colour = -1)
  {
    CameraParams c;
    c.az = az;
    c.score = score;
    c.colour = colour;
    c.fromColours = colour >= 0;
    return c;
  };
  // the silhouettes' cameras at azimuth 0 and 40 explain the colours by 0.07 and 0.075
  const auto residual = [](const View& v) { return v.camera.position.x() < 1 ? 0.07 : 0.075; };
  const auto azimuths = [&](const std::vector<CameraParams>& finalists)
  {
    std::vector<double> az;
    for (const auto& c : camerasToScore(finalists, start, 6, residual))
      az.push_back(c.az);
    return az;
  };
  const CameraParams s0 = camera(0, 0.91), s40 = camera(40, 0.90);
  // above the margin (0.8 x 0.07), from a direction none scores, the best explained: scored too
  EXPECT_EQ(azimuths({ s0, s40, camera(120, 0.75, 0.059) }), (std::vector<double>{ 0, 40, 120 }));
  // only the best explained of the colours' cameras
  EXPECT_EQ(azimuths({ s0, s40, camera(120, 0.75, 0.059), camera(-120, 0.8, 0.065) }),
    (std::vector<double>{ 0, 40, 120 }));
  // not better explained than every scored camera: not scored
  EXPECT_EQ(azimuths({ s0, s40, camera(120, 0.75, 0.072) }), (std::vector<double>{ 0, 40 }));
  // the best explained near a silhouettes' camera, above the margin: neither replaced nor added
  EXPECT_EQ(azimuths({ s0, s40, camera(5, 0.85, 0.058), camera(120, 0.75, 0.059) }),
    (std::vector<double>{ 0, 40 }));
  // under the margin it replaces the near one, as before
  EXPECT_EQ(azimuths({ s0, s40, camera(5, 0.85, 0.05) }), (std::vector<double>{ 40, 5 }));
  // the silhouettes' cameras get their residual; without a screening they alone are scored
  const auto chosen = camerasToScore({ s0, s40 }, start, 6, residual);
  EXPECT_DOUBLE_EQ(chosen[0].colour, 0.07);
  EXPECT_DOUBLE_EQ(chosen[1].colour, 0.075);
  EXPECT_EQ(camerasToScore({ s0, s40, camera(120, 0.75, 0.01) }, start, 6, nullptr).size(), 2u);
  EXPECT_TRUE(camerasToScore({}, start, 6, residual).empty());
}
