// TestMatch.cxx: the picture match's parts on synthetic pictures and a small synthetic volume —
// background estimation (uniform, ParaView's gradient, none), the camera moves (vtkCamera's
// roll, pan in view heights, dolly), and the refusals (tiny, uniform, cancelled, another
// object), and the part of a picture that shows the render (a window's screenshot). The match on a
// shipped volume is in Testing/Reconstruction/TestMatch.cxx.
#include "Reconstruct/Match.h"

#include "Common/Error.h"
#include "Gallery/QueryImage.h"
#include "Image/Image.h"
#include "Image/ImageMetrics.h"
#include "Reconstruct/CarryLook.h"
#include "Reconstruct/MatchParts.h"
#include "Render/RayCaster.h"
#include "VolumePieces.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace ddg;

namespace
{
constexpr double kLevel = 1.0 / 255.0;

// A picture over a uniform colour with a filled disc (the object) in the middle.
Image discPicture(int w, int h, std::array<double, 3> bg, std::array<double, 3> fg)
{
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      const bool in = std::hypot(x - 0.5 * w, y - 0.5 * h) < 0.25 * h;
      for (int c = 0; c < 3; ++c)
        img.pixels[3 * (static_cast<size_t>(y) * w + x) + c] =
          static_cast<float>(in ? fg[c] : bg[c]);
    }
  return img;
}

// An asymmetric object: an ellipsoid (value 120) holding an off-centre sphere (value 220), with a
// knob (value 220) on its side.
Volume blobVolume()
{
  const int nx = 40, ny = 32, nz = 28;
  std::vector<float> v;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
      {
        const double e = std::sqrt(std::pow((i - 19.5) / 16.0, 2) + std::pow((j - 15.5) / 10.0, 2) +
          std::pow((k - 13.5) / 8.0, 2));
        const double s =
          std::sqrt(std::pow(i - 27.0, 2) + std::pow(j - 19.0, 2) + std::pow(k - 13.5, 2));
        double value = std::clamp(1.0 - (e - 1.0) * 6.0, 0.0, 1.0) * 120.0;
        value = std::max(value, std::clamp(1.0 - (s - 4.0) / 1.5, 0.0, 1.0) * 220.0);
        const double knob =
          std::sqrt(std::pow(i - 10.0, 2) + std::pow(j - 26.0, 2) + std::pow(k - 8.0, 2));
        value = std::max(value, std::clamp(1.0 - (knob - 3.5) / 1.5, 0.0, 1.0) * 220.0);
        v.push_back(static_cast<float>(std::floor(value))); // uint8: whole numbers
      }
  return Volume({ nx, ny, nz }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::UInt8);
}
} // namespace

// A reconstruction target's background: the view's when the border agrees (exactly the view's
// numbers), the border's with a warning when it disagrees, the view's without a warning when the
// border has no one colour, and a given colour with a warning when the border disagrees.
TEST(MatchBackground, TargetBackground)
{
  View view;
  view.width = 80;
  view.height = 60;
  view.background = { 0.329, 0.349, 0.427 };
  const std::array<double, 3> white{ 1, 1, 1 };
  const auto agree = targetBackground(
    discPicture(80, 60, { 84 / 255.0, 89 / 255.0, 109 / 255.0 }, { 0.9, 0.8, 0.7 }), view);
  EXPECT_EQ(agree.source, "view");
  EXPECT_TRUE(agree.warning.empty()) << agree.warning;
  EXPECT_EQ(agree.background.bottom, view.background);
  const Image overWhite = discPicture(80, 60, white, { 0.9, 0.8, 0.7 });
  const auto disagree = targetBackground(overWhite, view);
  EXPECT_EQ(disagree.source, "picture");
  EXPECT_NE(disagree.warning.find("border"), std::string::npos);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(disagree.background.bottom[c], 1.0, 0.5 * kLevel);
  View v2 = view;
  disagree.background.applyTo(v2);
  EXPECT_EQ(v2.background, disagree.background.bottom);
  EXPECT_FALSE(v2.background2.has_value());
  Image scene(80, 60, 3); // no one colour on the border: nothing to check against
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 80; ++x)
      for (int c = 0; c < 3; ++c)
        scene.pixels[3 * (static_cast<size_t>(y) * 80 + x) + c] = x < 40 ? 0.1f : 0.9f;
  const auto none = targetBackground(scene, view);
  EXPECT_EQ(none.source, "view");
  EXPECT_TRUE(none.warning.empty());
  const auto givenRight = targetBackground(overWhite, view, white);
  EXPECT_EQ(givenRight.source, "given");
  EXPECT_TRUE(givenRight.warning.empty()) << givenRight.warning;
  const auto givenWrong = targetBackground(overWhite, view, view.background);
  EXPECT_EQ(givenWrong.background.bottom, view.background);
  EXPECT_NE(givenWrong.warning.find("not the given background"), std::string::npos);
}

TEST(MatchBackground, UniformColour)
{
  const std::array<double, 3> bg{ 82 / 255.0, 87 / 255.0, 110 / 255.0 };
  const auto b = estimateBackground(discPicture(80, 60, bg, { 0.9, 0.8, 0.7 }));
  EXPECT_FALSE(b.gradient);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(b.bottom[c], bg[c], 0.5 * kLevel);
  EXPECT_LT(b.noise, kLevel);
}

TEST(MatchBackground, ParaViewGradient)
{
  View v;
  v.width = 90;
  v.height = 70;
  v.background = { 0.8, 0.8, 0.9 };                       // bottom row
  v.background2 = std::array<double, 3>{ 0.1, 0.2, 0.6 }; // top row
  Image img(v.width, v.height, 3);
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x)
    {
      const auto c = v.backgroundAt(y);
      for (int k = 0; k < 3; ++k)
        img.pixels[3 * (static_cast<size_t>(y) * v.width + x) + k] = static_cast<float>(c[k]);
    }
  const auto b = estimateBackground(img);
  ASSERT_TRUE(b.gradient);
  for (int c = 0; c < 3; ++c)
  {
    EXPECT_NEAR(b.bottom[c], v.background[c], kLevel);
    EXPECT_NEAR(b.top[c], (*v.background2)[c], kLevel);
  }
  View w;
  b.applyTo(w);
  ASSERT_TRUE(w.background2.has_value());
  EXPECT_NEAR((*w.background2)[2], 0.6, kLevel);
}

TEST(MatchBackground, NoDominantColourIsRefused)
{
  // a scene, not a background: the border is half dark, half light
  Image scene(64, 64, 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c)
        scene.pixels[3 * (static_cast<size_t>(y) * 64 + x) + c] = x < 32 ? 0.1f : 0.9f;
  EXPECT_THROW(estimateBackground(scene), Error);
  // a noisy screenshot keeps its background: the noise widens the tolerance
  Image noisy = discPicture(64, 48, { 0.32, 0.34, 0.43 }, { 0.9, 0.8, 0.7 });
  std::mt19937 rng(3);
  std::normal_distribution<float> n(0.0f, 15.0f / 255.0f);
  for (auto& p : noisy.pixels)
    p = std::clamp(p + n(rng), 0.0f, 1.0f);
  const auto b = estimateBackground(noisy);
  EXPECT_NEAR(b.bottom[2], 0.43, 4 * kLevel);
  // nothing but noise: nothing to match
  Image noise(64, 64, 3);
  std::uniform_real_distribution<float> u(0, 1);
  for (auto& p : noise.pixels)
    p = u(rng);
  const Volume vol = blobVolume();
  const DifferentiableRenderer renderer(vol);
  EXPECT_THROW(matchPicture(renderer, noise), Error);
}

TEST(MatchCamera, MovesAsParaViewsCamera)
{
  View base;
  base.camera.position = { 0, 0, 10 };
  base.camera.focalPoint = { 0, 0, 0 };
  base.camera.viewUp = { 0, 1, 0 };
  // vtkCamera::Roll(90): view up rotated about the direction of projection (0, 0, -1)
  const View rolled = cameraMove(base, 0, 0, 90, 1, { 0, 0 });
  EXPECT_NEAR(rolled.camera.viewUp.x(), 1.0, 1e-9);
  EXPECT_NEAR(rolled.camera.viewUp.y(), 0.0, 1e-9);
  // dolly: distance / zoom; pan: focal point and position move by view heights at the focal point
  const View moved = cameraMove(base, 0, 0, 0, 2, { 0.1, -0.2 });
  const double height = 2 * 5.0 * std::tan(15 * M_PI / 180);
  EXPECT_NEAR((moved.camera.position - moved.camera.focalPoint).norm(), 5.0, 1e-9);
  EXPECT_NEAR(moved.camera.focalPoint.x(), 0.1 * height, 1e-9);
  EXPECT_NEAR(moved.camera.focalPoint.y(), -0.2 * height, 1e-9);
  // azimuth 90 about view up: looks from +x
  const View side = cameraMove(base, 90, 0, 0, 1, { 0, 0 });
  EXPECT_NEAR(side.camera.position.x(), 10.0, 1e-9);
}

TEST(Match, FindsTheCameraAndKeepsEmptySpaceClear)
{
  const Volume vol = blobVolume();
  const DifferentiableRenderer renderer(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 0.2, 0.4, 0.9 }, { 120, 0.9, 0.5, 0.2 }, { 255, 1, 1, 0.8 } };
  tf.opacity = { { 0, 0 }, { 60, 0 }, { 120, 0.3 }, { 200, 0.9 }, { 255, 0.9 } };
  const auto table = renderer.caster().paraviewTable(tf);
  View truth = cameraMove(defaultView(vol, 160, 120), 35, 20, 12, 1.2, { 0.03, -0.02 });
  truth.background = { 82 / 255.0, 87 / 255.0, 110 / 255.0 };
  Image picture = compositeOverBackground(renderer.caster().render(table, truth), truth.background);
  // an overlay in a corner: a small white square (as orientation axes or text)
  for (int y = 100; y < 112; ++y)
    for (int x = 6; x < 18; ++x)
      for (int c = 0; c < 3; ++c)
        picture.pixels[3 * (static_cast<size_t>(y) * 160 + x) + c] = 1.0f;

  MatchOptions opt;
  opt.reconstruction.iterations = 300;
  opt.lighting = Lighting{}; // said unlit: the camera search alone (lighting estimated: below)
  const auto m = matchPicture(renderer, picture, opt);
  EXPECT_TRUE(m.cameraEstimated);
  EXPECT_FALSE(m.lightingEstimated);
  const Eigen::Vector3d fFound = m.view.camera.focalPoint - m.view.camera.position;
  const Eigen::Vector3d fTrue = truth.camera.focalPoint - truth.camera.position;
  const double dirError =
    std::acos(std::clamp(fFound.normalized().dot(fTrue.normalized()), -1.0, 1.0));
  EXPECT_LT(dirError * 180 / M_PI, 8.0);
  EXPECT_GT(m.overlap, 0.8);
  EXPECT_GT(m.fitPSNR, 30.0);
  // the overlay square is masked, the object is not
  EXPECT_GT(m.masks.overlay.at(11, 105, 0), 0.5f);
  EXPECT_LT(m.masks.overlay.at(80, 60, 0), 0.5f);
  EXPECT_NEAR(m.background.bottom[0], 82 / 255.0, kLevel);
  // no haze: the air (value 0) is transparent in the found TF
  EXPECT_LT(m.tf.table1D.rgba[3], 1e-3);
}

// The match over pieces of the volume (ParaView's ranks; here threads exchanging through a
// ThreadBoard) takes the whole's steps: every piece finds the whole's camera and TF (rays run to
// their end, so that the pieces' composite equals the whole's up to float rounding), and all
// pieces the same numbers.
TEST(Match, PiecesMatchAsTheWholeVolume)
{
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "three matches are too slow under the sanitizers (the pieces' parts of the "
                  "match: MatchEmission.PiecesSeeTheWholeVolume)";
#endif
  const Volume vol = blobVolume();
  const DifferentiableRenderer renderer(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 0.2, 0.4, 0.9 }, { 120, 0.9, 0.5, 0.2 }, { 255, 1, 1, 0.8 } };
  tf.opacity = { { 0, 0 }, { 60, 0 }, { 120, 0.3 }, { 200, 0.9 }, { 255, 0.9 } };
  View truth = cameraMove(defaultView(vol, 120, 96), -50, 25, -8, 1.1, { -0.02, 0.03 });
  truth.background = { 0.1, 0.1, 0.15 };
  const Image picture = compositeOverBackground(
    renderer.caster().render(renderer.caster().paraviewTable(tf), truth), truth.background);
  MatchOptions opt;
  opt.reconstruction.iterations = 120;
  opt.reconstruction.render.terminationOpacity = 1.0;
  opt.reconstruction.render.threads = 1;
  opt.reconstruction.snapshotEvery = 40; // previews rendered over the pieces too
  opt.lighting = Lighting{};
  int previews = 0;
  const auto whole = matchPicture(renderer, picture, opt,
    [&](const std::string&, double, const Image* preview)
    {
      previews += preview != nullptr;
      return true;
    });
  EXPECT_GT(previews, 0);
  EXPECT_FALSE(whole.view.camera.parallelProjection); // drawn in perspective: not matched parallel
  for (int n : { 2, 3 })
  {
    std::vector<MatchResult> each(static_cast<size_t>(n));
    std::vector<Image> lastPreview(static_cast<size_t>(n));
    ddg::testing::onPieces(vol, n,
      [&](int p, const DifferentiableRenderer& r)
      {
        each[static_cast<size_t>(p)] = matchPicture(r, picture, opt,
          [&](const std::string&, double, const Image* preview)
          {
            if (preview)
              lastPreview[static_cast<size_t>(p)] = *preview;
            return true;
          });
      });
    for (int p = 0; p < n; ++p)
    {
      const MatchResult& m = each[static_cast<size_t>(p)];
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(m.orbit[a], whole.orbit[a], 0.5) << n << " pieces, piece " << p;
      EXPECT_NEAR(m.zoom, whole.zoom, 0.01 * whole.zoom);
      // the pieces' fit agrees with the whole's at 48-52 dB (below); judged at the picture's
      // resolution (the whole's fit 37.6 dB) that shows as 0.5 dB (0.3 when aliasing bound it)
      EXPECT_NEAR(m.fitPSNR, whole.fitPSNR, 0.6);
      EXPECT_NEAR(m.overlap, whole.overlap, 0.02);
      // the found TF looks as the whole's: rendered at the whole's camera and from the side
      for (double azimuth : { 0.0, 120.0 })
      {
        View v = cameraMove(whole.view, azimuth, 0, 0, 1, { 0, 0 });
        const double agree = psnr(
          renderResult(renderer.caster(), m.tf, v), renderResult(renderer.caster(), whole.tf, v));
        std::printf("%d pieces, azimuth %.0f: %.2f dB\n", n, azimuth, agree);
        EXPECT_GT(agree, 30.0) << n << " pieces, azimuth " << azimuth;
      }
      // the same numbers on every piece (the whole's composite and gradients on each)
      EXPECT_EQ(m.tf.table1D.rgba, each[0].tf.table1D.rgba);
      EXPECT_EQ(m.orbit, each[0].orbit);
      EXPECT_FALSE(lastPreview[static_cast<size_t>(p)].empty());
    }
  }
}

TEST(Match, EstimatesWhetherThePictureIsLit)
{
#if defined(__SANITIZE_ADDRESS__)
  // six whole matches: about 20 s optimised, over 10 minutes in the sanitizer build, whose
  // purpose (memory and undefined behaviour) the match's other tests serve on the same code
  GTEST_SKIP() << "six matches are too slow under the sanitizers; run in the optimised build";
#endif
  // the same object and camera, once with Shade on (Specular 0.5 / 30) and once unlit: with no
  // lighting said, the match tells them apart
  const Volume vol = blobVolume();
  const DifferentiableRenderer renderer(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 0.9, 0.8, 0.7 }, { 120, 0.9, 0.6, 0.4 }, { 255, 0.7, 0.8, 1 } };
  tf.opacity = { { 0, 0 }, { 60, 0 }, { 120, 0.4 }, { 200, 0.9 }, { 255, 0.9 } };
  const auto table = renderer.caster().paraviewTable(tf);
  View truth = cameraMove(defaultView(vol, 160, 120), -30, 15, 0, 1.1, { 0, 0 });
  truth.background = { 0, 0, 0 };
  for (const bool lit : { true, false })
  {
    truth.lighting = Lighting{};
    truth.lighting.shade = lit;
    truth.lighting.specular = lit ? 0.5 : 0.0;
    truth.lighting.specularPower = 30;
    const Image picture =
      compositeOverBackground(renderer.caster().render(table, truth), truth.background);
    MatchOptions opt;
    opt.reconstruction.iterations = 300;
    const auto m = matchPicture(renderer, picture, opt);
    EXPECT_TRUE(m.lightingEstimated);
    EXPECT_EQ(m.view.lighting.shade, lit)
      << "fit " << m.fitPSNR << " dB, the other lighting's " << m.otherLightingFitPSNR << " dB";
    EXPECT_GT(m.fitPSNR, m.otherLightingFitPSNR);
    std::printf("%s picture: fit %.1f dB, the other lighting's %.1f dB\n", lit ? "lit" : "unlit",
      m.fitPSNR, m.otherLightingFitPSNR);
  }
}

TEST(Match, RefusesWhatItCannotUse)
{
  const Volume vol = blobVolume();
  const DifferentiableRenderer renderer(vol);
  const std::array<double, 3> bg{ 0.32, 0.34, 0.43 };
  // tiny
  EXPECT_THROW(matchPicture(renderer, discPicture(8, 8, bg, { 1, 1, 1 })), Error);
  // uniform
  EXPECT_THROW(matchPicture(renderer, discPicture(64, 48, bg, bg)), Error);
  // another object: a thin diagonal bar no view of the blob makes
  Image bar(120, 90, 3);
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 120; ++x)
    {
      const bool on = std::abs(y - 0.75 * x) < 1.5;
      for (int c = 0; c < 3; ++c)
        bar.pixels[3 * (static_cast<size_t>(y) * 120 + x) + c] =
          static_cast<float>(on ? 0.9 : bg[c]);
    }
  try
  {
    matchPicture(renderer, bar);
    ADD_FAILURE() << "a bar matched";
  }
  catch (const Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("no camera explains the picture"), std::string::npos)
      << e.what();
  }
  // cancelled
  EXPECT_THROW(matchPicture(renderer, discPicture(64, 48, bg, { 0.9, 0.6, 0.3 }), {},
                 [](const std::string& stage, double, const Image*) { return stage != "camera"; }),
    Cancelled);
}

TEST(Match, LetterboxedPictureIsMatchedInside)
{
  const Volume vol = blobVolume();
  const DifferentiableRenderer renderer(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 0.2, 0.4, 0.9 }, { 120, 0.9, 0.5, 0.2 }, { 255, 1, 1, 0.8 } };
  tf.opacity = { { 0, 0 }, { 60, 0 }, { 120, 0.3 }, { 200, 0.9 }, { 255, 0.9 } };
  View truth = cameraMove(defaultView(vol, 120, 90), 20, 10, 0, 1.1, { 0, 0 });
  truth.background = { 82 / 255.0, 87 / 255.0, 110 / 255.0 };
  const Image inner = compositeOverBackground(
    renderer.caster().render(renderer.caster().paraviewTable(tf), truth), truth.background);
  // black bars: 20 pixels left and right, 6 at the top and bottom
  Image boxed(160, 102, 3);
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 120; ++x)
      for (int c = 0; c < 3; ++c)
        boxed.pixels[3 * (static_cast<size_t>(y + 6) * 160 + x + 20) + c] =
          inner.pixels[3 * (static_cast<size_t>(y) * 120 + x) + c];
  MatchOptions opt;
  opt.view = truth; // the camera given: this is about the bands
  const auto m = matchPicture(renderer, boxed, opt);
  EXPECT_GT(m.fitPSNR, 30.0);
  EXPECT_EQ(m.crop, (std::array<int, 4>{ 20, 6, 120, 90 }));
  EXPECT_EQ(m.view.width, 120);
  EXPECT_EQ(m.view.height, 90);
  EXPECT_NEAR(m.background.bottom[2], 110 / 255.0, kLevel);
}

TEST(MatchBackground, SteepGradientIsNoLetterbox)
{
  // a gradient of 3 levels a row, with an object: matched whole, the gradient found
  const Volume vol = blobVolume();
  const DifferentiableRenderer renderer(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 1, 1, 1 }, { 255, 1, 1, 1 } };
  tf.opacity = { { 0, 0 }, { 60, 0 }, { 120, 0.6 }, { 255, 0.9 } };
  View v = defaultView(vol, 120, 80);
  v.background = { 0.95, 0.95, 0.95 };
  v.background2 = std::array<double, 3>{ 0.95 - 3.0 * 80 / 255.0, 0.95 - 3.0 * 80 / 255.0, 0.95 };
  const Image render = renderer.caster().render(renderer.caster().paraviewTable(tf), v);
  const Image picture = compositeOverBackground(render, v.background, *v.background2);
  MatchOptions opt;
  opt.view = v;
  const auto m = matchPicture(renderer, picture, opt);
  EXPECT_EQ(m.crop, (std::array<int, 4>{ 0, 0, 120, 80 }));
  EXPECT_TRUE(m.background.gradient);
  EXPECT_NEAR(m.background.top[0], (*v.background2)[0], 2 * kLevel);
}

namespace
{
// A screenshot of a whole window, as ParaView's GUI looks: a toolbar of icons, a panel of text
// and widgets, and the render view (`inner`, over its own background) in a blue frame of 2
// pixels at (frameX, frameY). Everything is then scaled by `scale` (nearest) and moved right and
// down by `shift` pixels of the window's grey.
struct Window
{
  Image picture;
  std::array<int, 4> view; // the render view's inside
};
Window windowAround(const Image& inner, int frameX, int frameY, int scale, int shift)
{
  const int w = frameX + inner.width + 4 + 12, h = frameY + inner.height + 4 + 20;
  Image win(w, h, 3);
  auto paint = [&](int x0, int y0, int x1, int y1, std::array<float, 3> c)
  {
    for (int y = std::max(0, y0); y < std::min(h, y1); ++y)
      for (int x = std::max(0, x0); x < std::min(w, x1); ++x)
        for (int k = 0; k < 3; ++k)
          win.pixels[3 * (static_cast<size_t>(y) * w + x) + k] = c[static_cast<size_t>(k)];
  };
  paint(0, 0, w, h, { 0.94f, 0.94f, 0.94f });
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  for (int x = 6; x + 16 < w; x += 26) // the toolbar's icons
    paint(x, 8, x + 16, 24, { u(rng), u(rng), u(rng) });
  paint(0, 34, frameX - 8, h - 24, { 1, 1, 1 }); // the panel, its lines of text and widgets
  for (int y = 44; y + 10 < h - 24; y += 18)
    for (int x = 10; x + 8 < frameX - 14; x += 9)
      if (u(rng) < 0.8f)
      {
        paint(x, y, x + 1, y + 9, { 0.1f, 0.1f, 0.1f });
        paint(x, y + 4, x + 6, y + 5, { 0.1f, 0.1f, 0.1f });
        paint(x + 5, y + 2, x + 6, y + 9, { 0.1f, 0.1f, 0.1f });
      }
  paint(frameX, frameY, frameX + inner.width + 4, frameY + inner.height + 4, { 0.2f, 0.4f, 0.9f });
  for (int y = 0; y < inner.height; ++y)
    for (int x = 0; x < inner.width; ++x)
      for (int k = 0; k < 3; ++k)
        win.pixels[3 * (static_cast<size_t>(y + frameY + 2) * w + x + frameX + 2) + k] =
          inner.pixels[3 * (static_cast<size_t>(y) * inner.width + x) + k];
  paint(0, h - 16, w, h, { 0.85f, 0.85f, 0.85f }); // the status bar
  Window r;
  r.picture = Image(w * scale + shift, h * scale + shift, 3);
  for (size_t i = 0; i < r.picture.pixels.size(); ++i)
    r.picture.pixels[i] = 0.94f;
  for (int y = 0; y < h * scale; ++y)
    for (int x = 0; x < w * scale; ++x)
      for (int k = 0; k < 3; ++k)
        r.picture.pixels[3 * (static_cast<size_t>(y + shift) * r.picture.width + x + shift) + k] =
          win.pixels[3 * (static_cast<size_t>(y / scale) * w + x / scale) + k];
  r.view = { (frameX + 2) * scale + shift, (frameY + 2) * scale + shift, inner.width * scale,
    inner.height * scale };
  return r;
}

struct BlobScene
{
  Volume vol = blobVolume();
  DifferentiableRenderer renderer{ vol };
  View view;
  TransferFunction1D tf;
  Image picture;
  explicit BlobScene(int w, int h)
  {
    tf.color = { { 0, 0.2, 0.4, 0.9 }, { 120, 0.9, 0.5, 0.2 }, { 255, 1, 1, 0.8 } };
    tf.opacity = { { 0, 0 }, { 60, 0 }, { 120, 0.3 }, { 200, 0.9 }, { 255, 0.9 } };
    view = cameraMove(defaultView(vol, w, h), 20, 10, 0, 1.1, { 0, 0 });
    view.background = { 82 / 255.0, 87 / 255.0, 110 / 255.0 };
    picture = compositeOverBackground(
      renderer.caster().render(renderer.caster().paraviewTable(tf), view), view.background);
  }
};
} // namespace

// `part` lies inside `view` and loses at most `slack` pixels on each side.
void expectInside(const std::array<int, 4>& part, const std::array<int, 4>& view, int slack)
{
  EXPECT_GE(part[0], view[0]);
  EXPECT_GE(part[1], view[1]);
  EXPECT_LE(part[0], view[0] + slack);
  EXPECT_LE(part[1], view[1] + slack);
  EXPECT_LE(part[0] + part[2], view[0] + view[2]);
  EXPECT_LE(part[1] + part[3], view[1] + view[3]);
  EXPECT_GE(part[0] + part[2], view[0] + view[2] - slack);
  EXPECT_GE(part[1] + part[3], view[1] + view[3] - slack);
}

TEST(MatchParts, RenderViewOfAWindowsScreenshot)
{
  const BlobScene scene(208, 150);
  // the window as drawn: its render view exactly
  const Window plain = windowAround(scene.picture, 150, 40, 1, 0);
  EXPECT_EQ(matchparts::renderView(plain.picture), plain.view);
  EXPECT_EQ(matchparts::renderedPart(plain.picture), plain.view);
  // scaled four times (1496 x 856, read halved twice to at most 512 a side): the halved pixels
  // line up with the view's edges, so the same view
  const Window large = windowAround(scene.picture, 150, 40, 4, 0);
  EXPECT_EQ(matchparts::renderView(large.picture), large.view);
  // moved by 3 pixels they do not: inside the view, within one halved pixel (4) of each edge
  const Window moved = windowAround(scene.picture, 150, 40, 4, 3);
  expectInside(matchparts::renderView(moved.picture), moved.view, 4);
  // JPEG at quality 85 rings beside the frame: inside the view, within a JPEG block (8 pixels)
  // of each edge
  expectInside(matchparts::renderView(jpegRoundTrip(plain.picture, 85)), plain.view, 8);
}

TEST(MatchParts, RenderViewOfParaViewsWindow)
{
  // ParaView 5.11's window (Testing/Data/README.md): the inside of its render view, read from
  // the pixels (the blue frame's inner edge), is the 844 x 527 pixels from (303, 200); the
  // window's border has no one colour (60-70 % of it)
  const Image window = readImage(std::string(DDG_DATA_DIR) + "/../Testing/Data/window_tooth.jpg");
  EXPECT_THROW(estimateBackground(window), Error);
  expectInside(matchparts::renderedPart(window), { 303, 200, 844, 527 }, 8);
}

namespace
{
// `render` pasted on a white page at (30, 20), a colour bar beside it and a caption's letters
// under it (a paper's figure)
Image figureWith(const Image& render)
{
  const int w = render.width + 92, h = render.height + 70;
  Image page(w, h, 3);
  for (size_t i = 0; i < page.pixels.size(); ++i)
    page.pixels[i] = 1.0f;
  for (int y = 0; y < render.height; ++y)
    for (int x = 0; x < render.width; ++x)
      for (int c = 0; c < 3; ++c)
        page.pixels[3 * (static_cast<size_t>(y + 20) * w + x + 30) + c] =
          render.pixels[3 * (static_cast<size_t>(y) * render.width + x) + c];
  for (int y = 30; y < 160; ++y) // the colour bar
    for (int x = w - 45; x < w - 35; ++x)
      for (int c = 0; c < 3; ++c)
        page.pixels[3 * (static_cast<size_t>(y) * w + x) + c] = static_cast<float>(y - 30) / 130.0f;
  for (int x = 30; x < 200; x += 7) // the caption's letters
    for (int y = h - 30; y < h - 22; ++y)
      for (int c = 0; c < 3; ++c)
        page.pixels[3 * (static_cast<size_t>(y) * w + x) + c] = 0.1f;
  return page;
}
} // namespace

TEST(MatchParts, RenderPastedOnAPage)
{
  // a figure: the render over ParaView's palette, over black, and over ParaView's gradient,
  // pasted on a white page: read inside the render's rectangle, less 2 pixels at its edges
  BlobScene scene(208, 150);
  const std::array<int, 4> inside{ 32, 22, 204, 146 };
  EXPECT_EQ(matchparts::renderView(figureWith(scene.picture)), inside);
  const Image raw =
    scene.renderer.caster().render(scene.renderer.caster().paraviewTable(scene.tf), scene.view);
  EXPECT_EQ(matchparts::renderView(figureWith(compositeOverBackground(raw, { 0, 0, 0 }))), inside);
  EXPECT_EQ(matchparts::renderView(
              figureWith(compositeOverBackground(raw, { 0.32, 0.34, 0.43 }, { 0, 0, 0.16 }))),
    inside);
  // as a JPEG (quality 85): inside the rectangle, within a JPEG block of each edge
  expectInside(matchparts::renderedPart(jpegRoundTrip(figureWith(scene.picture), 85)),
    { 30, 20, 208, 150 }, 8);
  // the render over the page's white: no rectangle, read whole
  const Image onWhite = figureWith(compositeOverBackground(raw, { 1, 1, 1 }));
  EXPECT_EQ(matchparts::renderView(onWhite), (std::array<int, 4>{ 0, 0, 300, 220 }));
}

TEST(MatchParts, JpegCutAtItsRenderIsReadInsideItsRinging)
{
  // a figure saved as a JPEG (quality 90), then cut by eye at the render's rectangle: the blocks
  // beside the cut ring with the page's white, so the cut picture's border has no one colour (the
  // match refused it: "the picture has no background colour"); read inside a border inset by up
  // to a JPEG block, whose colour is the render's background. Cut 2 pixels further in, the border
  // has one colour: read whole, as before.
  const BlobScene scene(640, 480);
  const Image jpeg = jpegRoundTrip(figureWith(scene.picture), 90);
  const Image exact = matchparts::cropTo(jpeg, { 30, 20, 640, 480 });
  EXPECT_THROW(estimateBackground(exact), Error); // the cut rings
  const std::array<int, 4> part = matchparts::renderedPart(exact);
  expectInside(part, { 0, 0, 640, 480 }, 8);
  EXPECT_LT(part[2], 640);
  const PictureBackground bg = estimateBackground(matchparts::cropTo(exact, part));
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(bg.bottom[c], scene.view.background[c], 3 * kLevel);
  const Image inside = matchparts::cropTo(jpeg, { 32, 22, 636, 476 });
  EXPECT_NO_THROW(estimateBackground(inside));
  EXPECT_EQ(matchparts::renderedPart(inside), (std::array<int, 4>{ 0, 0, 636, 476 }));
}

TEST(MatchParts, LetterboxedRenderIsLeftToLetterbox)
{
  // a render (over the palette) letterboxed in black bands above and below, the picture an odd
  // size read halved (1023 x 701, the last column left out of the halving): the letterbox's exact
  // inside, not the page reading's (a few pixels further in)
  const BlobScene scene(1023, 400);
  const int w = 1023, h = 701, y0 = 150;
  Image boxed(w, h, 3);
  std::copy(scene.picture.pixels.begin(), scene.picture.pixels.end(),
    boxed.pixels.begin() + 3 * static_cast<std::ptrdiff_t>(y0) * w);
  const std::array<int, 4> inside = matchparts::letterbox(boxed);
  expectInside(inside, { 0, y0, w, 400 }, 1);
  EXPECT_EQ(matchparts::renderedPart(boxed), inside);
}

TEST(MatchParts, HazyBoxIsNoPastedRender)
{
  // a TF that paints the air (as ParaView's default opacity ramp does) shows the volume's box as a
  // filled rectangle holding the object; in parallel projection, face on, over white, black or the
  // palette, it is a veil over the background, not a pasted render: read whole
  BlobScene scene(208, 150);
  scene.tf.color = { { 0, 0.23, 0.3, 0.75 }, { 120, 0.87, 0.87, 0.87 }, { 255, 0.7, 0.02, 0.15 } };
  scene.tf.opacity = { { 0, 0.03 }, { 60, 0.03 }, { 255, 1.0 } };
  View face = defaultView(scene.vol, 208, 150);
  face.camera.parallelProjection = true;
  face.camera.parallelScale *= 1.3; // the box inside the picture
  const Image raw =
    scene.renderer.caster().render(scene.renderer.caster().paraviewTable(scene.tf), face);
  for (const std::array<double, 3>& colour :
    { std::array<double, 3>{ 1, 1, 1 }, { 0, 0, 0 }, { 0.32, 0.34, 0.43 } })
  {
    const Image picture = compositeOverBackground(raw, colour);
    // the haze is there: a pixel inside the box's corner, off the object, is not the background
    const float* haze = &picture.pixels[3 * (static_cast<size_t>(100) * 208 + 68)];
    EXPECT_GT(std::abs(haze[2] - colour[2]) + std::abs(haze[0] - colour[0]), 0.05);
    EXPECT_EQ(matchparts::renderedPart(picture), (std::array<int, 4>{ 0, 0, 208, 150 }))
      << colour[0];
  }
  // ParaView 5.11's default TF on Tooth, parallel projection, face on, over white (a real render,
  // Testing/Data/README.md): a filled rectangle whose fill has one colour, light blue, so its
  // colour alone tells it from a pasted render
  const Image tooth = readImage(std::string(DDG_DATA_DIR) + "/../Testing/Data/hazy_tooth.png");
  const std::array<int, 4> box{ 254, 171, 292, 258 }; // inside the box's edges
  const PictureBackground fill = estimateBackground(matchparts::cropTo(tooth, box));
  EXPECT_FALSE(fill.gradient);
  EXPECT_NEAR(fill.bottom[2], 1.0, 0.02);
  EXPECT_NEAR(fill.bottom[0], 0.63, 0.03);
  EXPECT_EQ(
    matchparts::renderedPart(tooth), (std::array<int, 4>{ 0, 0, tooth.width, tooth.height }));
  // the control: the same picture with its haze painted black (a render over black pasted on the
  // white page) is read inside the box
  Image pasted = tooth;
  for (int y = 160; y < 440; ++y)
    for (int x = 240; x < 560; ++x)
    {
      float* p = &pasted.pixels[3 * (static_cast<size_t>(y) * tooth.width + x)];
      if (std::abs(p[0] - fill.bottom[0]) < 0.03 && std::abs(p[1] - fill.bottom[1]) < 0.03 &&
        std::abs(p[2] - fill.bottom[2]) < 0.03)
        p[0] = p[1] = p[2] = 0.0f;
    }
  expectInside(matchparts::renderedPart(pasted), { 250, 167, 300, 266 }, 8);
}

TEST(MatchParts, RenderViewLeavesOtherPicturesWhole)
{
  const BlobScene scene(208, 150);
  const std::array<int, 4> whole{ 0, 0, 208, 150 };
  // a render: its border has one colour
  EXPECT_EQ(matchparts::renderView(scene.picture), whole);
  // a window with no render in its view (the view painted as the panel, text and all): the
  // panel's text is not a solid object, so no part of it is taken for a render view
  Image empty(208, 150, 3);
  for (size_t i = 0; i < empty.pixels.size(); ++i)
    empty.pixels[i] = 1.0f;
  const Window blank = windowAround(empty, 150, 40, 1, 0);
  EXPECT_EQ(matchparts::renderView(blank.picture),
    (std::array<int, 4>{ 0, 0, blank.picture.width, blank.picture.height }));
  // the window cut so that its view reaches the picture's top and left edges: a region at the
  // edge is the picture's own (a render cut by the frame), not a view
  const Window window = windowAround(scene.picture, 150, 40, 1, 0);
  const std::array<int, 4> cut{ window.view[0] + 10, window.view[1] + 10, 220, 160 };
  const Image cutPicture = matchparts::cropTo(window.picture, cut);
  EXPECT_EQ(matchparts::renderView(cutPicture), (std::array<int, 4>{ 0, 0, 220, 160 }));
  // a picture saved with transparency is a render
  Image rgba(40, 30, 4);
  for (size_t i = 0; i < rgba.pixels.size(); ++i)
    rgba.pixels[i] = (i % 4 == 3) ? 0.0f : static_cast<float>(i % 7) / 7.0f;
  EXPECT_EQ(matchparts::renderView(rgba), (std::array<int, 4>{ 0, 0, 40, 30 }));
}

TEST(Match, WindowsScreenshotIsMatchedAtItsRenderView)
{
  const BlobScene scene(208, 150);
  const Window window = windowAround(scene.picture, 150, 40, 1, 0);
  // before, the window's border (grey, a status bar, text) refused the picture
  EXPECT_THROW(estimateBackground(window.picture), Error);
  MatchOptions opt;
  opt.view = scene.view; // the camera given: this is about the part matched
  const auto m = matchPicture(scene.renderer, window.picture, opt);
  EXPECT_EQ(m.crop, window.view);
  EXPECT_GT(m.fitPSNR, 30.0);
  EXPECT_EQ(m.view.width, 208);
  EXPECT_NEAR(m.background.bottom[2], 110 / 255.0, kLevel);
  // the carried look's and the query's reading of a picture take the same part
  EXPECT_EQ(readPictureObject(window.picture).picture.width, 208);
  Image held;
  EXPECT_EQ(queryPicture(window.picture, held).width, 208);
  EXPECT_EQ(checkQueryPicture(window.picture), "");
}

// The fit is judged on the picture's pixels: the render it is compared with is made at the
// picture's size and reduced as the picture is. Thin bright plates (a chest's ribs, seen edge on)
// rendered one ray a preview pixel alias against the picture's filtered pixels, and the match
// judged its own render by the aliasing (26.4 dB here so, 41.5 dB now; a chest over black at its
// true camera 24.0 dB, under the 25 dB the match needs, and 43.0 dB now).
TEST(Match, FineStructureIsJudgedAtThePicturesResolution)
{
  const int n = 64;
  std::vector<float> v;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const bool inside = std::hypot(i - 31.5, j - 31.5, k - 31.5) < 28.0;
        v.push_back(inside && i % 3 == 0 ? 220.0f : 0.0f);
      }
  const Volume vol({ n, n, n }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::UInt8);
  const DifferentiableRenderer renderer(vol);
  TransferFunction1D tf;
  tf.color = { { 0, 0.2, 0.4, 0.8 }, { 220, 1, 0.95, 0.85 } };
  tf.opacity = { { 0, 0 }, { 100, 0 }, { 220, 0.95 } };
  View truth = cameraMove(defaultView(vol, 256, 192), 25, 15, 0, 1.2, { 0, 0 });
  truth.background = { 0, 0, 0 };
  const Image picture = compositeOverBackground(
    renderer.caster().render(renderer.caster().paraviewTable(tf), truth), truth.background);
  MatchOptions opt;
  opt.view = truth; // the camera given: this is about how the fit is judged
  const auto m = matchPicture(renderer, picture, opt);
  EXPECT_GT(m.fitPSNR, 35.0);
}
