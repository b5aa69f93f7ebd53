// MatchCamera.h: the picture match's camera search, for Match.cxx and its parts only: a camera
// in the search's parameters, a Nelder-Mead search over them, and the emission model's
// screening of cameras by the picture's colours (MatchEmission.cxx).
#pragma once

#include "Image/Image.h"
#include "Reconstruct/Match.h"
#include "Reconstruct/MatchParts.h"
#include "Render/DifferentiableRenderer.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <numeric>
#include <vector>

namespace ddg
{
namespace matchparts
{

// A camera in the search's parameters (relative to the reset camera).
struct CameraParams
{
  double az = 0, el = 0, roll = 0, logZoom = 0, panX = 0, panY = 0;
  int level = 0;
  double score = 0;
  double colour = -1;       ///< the emission model's residual, once computed
  bool fromColours = false; ///< found by the colours' screening (not by silhouettes)
  /// Parallel projection, at the base's parallel scale (the reset camera's: the bounding
  /// sphere's radius); false: the base's projection.
  bool parallel = false;

  View view(const View& base) const
  {
    View b = base;
    b.camera.parallelProjection = b.camera.parallelProjection || parallel;
    return cameraMove(b, az, std::clamp(el, -89.0, 89.0), roll, std::exp(logZoom), { panX, panY });
  }
};

// The larger of the angles (degrees) between two cameras' directions and between their view-ups.
inline double orientationDistance(const View& a, const View& b)
{
  auto angle = [](const Eigen::Vector3d& u, const Eigen::Vector3d& v)
  { return std::acos(std::clamp(u.normalized().dot(v.normalized()), -1.0, 1.0)) * 180.0 / M_PI; };
  const Eigen::Vector3d fa = a.camera.focalPoint - a.camera.position,
                        fb = b.camera.focalPoint - b.camera.position;
  return std::max(angle(fa, fb), angle(a.camera.viewUp, b.camera.viewUp));
}

// Nelder-Mead maximisation of f over the six camera parameters.
template <typename F>
CameraParams nelderMead(const CameraParams& start, F&& f, int evaluations, double stepScale = 1)
{
  constexpr int n = 6;
  double steps[n] = { 6, 6, 6, 0.06, 0.03, 0.03 };
  for (double& st : steps)
    st *= stepScale;
  auto toVec = [](const CameraParams& p) {
    return std::array<double, n>{ p.az, p.el, p.roll, p.logZoom, p.panX, p.panY };
  };
  auto fromVec = [&](const std::array<double, n>& v)
  {
    CameraParams p = start;
    p.az = v[0];
    p.el = std::clamp(v[1], -89.0, 89.0);
    p.roll = v[2];
    p.logZoom = std::clamp(v[3], -2.0, 2.0);
    p.panX = v[4];
    p.panY = v[5];
    return p;
  };
  std::vector<std::array<double, n>> x(n + 1, toVec(start));
  std::vector<double> fx(n + 1);
  for (int i = 0; i < n; ++i)
    x[i + 1][i] += steps[i];
  int used = 0;
  for (int i = 0; i <= n; ++i, ++used)
    fx[i] = -f(fromVec(x[i]));
  while (used < evaluations)
  {
    std::vector<int> order(n + 1);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return fx[a] < fx[b]; });
    const int best = order[0], worst = order[n], second = order[n - 1];
    std::array<double, n> centroid{};
    for (int i = 0; i <= n; ++i)
      if (i != worst)
        for (int k = 0; k < n; ++k)
          centroid[k] += x[i][k] / n;
    auto along = [&](double t)
    {
      std::array<double, n> p;
      for (int k = 0; k < n; ++k)
        p[k] = centroid[k] + t * (x[worst][k] - centroid[k]);
      return p;
    };
    const auto xr = along(-1.0);
    const double fr = -f(fromVec(xr));
    ++used;
    if (fr < fx[best])
    {
      const auto xe = along(-2.0);
      const double fe = -f(fromVec(xe));
      ++used;
      if (fe < fr)
        x[worst] = xe, fx[worst] = fe;
      else
        x[worst] = xr, fx[worst] = fr;
    }
    else if (fr < fx[second])
    {
      x[worst] = xr;
      fx[worst] = fr;
    }
    else
    {
      const auto xc = along(fr < fx[worst] ? -0.5 : 0.5);
      const double fc = -f(fromVec(xc));
      ++used;
      if (fc < std::min(fr, fx[worst]))
      {
        x[worst] = xc;
        fx[worst] = fc;
      }
      else
      {
        for (int i = 0; i <= n; ++i)
        {
          if (i == best)
            continue;
          for (int k = 0; k < n; ++k)
            x[i][k] = x[best][k] + 0.5 * (x[i][k] - x[best][k]);
          fx[i] = -f(fromVec(x[i]));
          ++used;
        }
      }
    }
  }
  const int bestIndex = static_cast<int>(std::min_element(fx.begin(), fx.end()) - fx.begin());
  CameraParams r = fromVec(x[bestIndex]);
  r.score = -fx[bestIndex];
  return r;
}

// The camera among `start` and the 24 cameras 10 and 20 degrees around it in azimuth and
// elevation with the lowest loss(camera): a hop out of a basin the refinement would not leave
// (a silhouette's twin across a near-symmetric object, e.g. the elevation's sign on a body seen
// from the side).
template <typename L>
CameraParams hopAround(const CameraParams& start, L&& loss)
{
  CameraParams best = start;
  double lowest = loss(start);
  for (double da : { -20.0, -10.0, 0.0, 10.0, 20.0 })
    for (double de : { -20.0, -10.0, 0.0, 10.0, 20.0 })
    {
      if (da == 0 && de == 0)
        continue;
      CameraParams c = start;
      c.az += da;
      c.el = std::clamp(c.el + de, -89.0, 89.0);
      if (const double l = loss(c); l < lowest)
        best = c, lowest = l;
    }
  return best;
}

// The emission model of a picture at a camera, for screening cameras by the picture's colours
// where silhouettes cannot tell them apart (a roundish, translucent object): each pixel's
// difference from the background, d_p = picture_p - background_p, is fitted as a linear
// function of its ray's histogram of volume values, d_p ~ sum_b n_pb k_b (n_pb: samples of the
// ray in value bin b; k_b: the bin's opacity times its colour minus the background, one RGB
// vector per bin, by ridge least squares). This is emission-absorption rendering to first order
// in the opacity (no attenuation): exact for faint objects, a ranking for others, and free of
// any TF: the RMS residual says how well a camera's rays can explain the picture's colours.
class EmissionScreen
{
public:
  /// `difference`: the picture minus its background at the search raster (RGB, w x h; a picture
  /// with transparency: its premultiplied colour); `care`: 0 on overlays, whose colour is
  /// taken as the background's (d = 0): overlays mostly sit over the background, as orientation
  /// axes in a corner, and the faint fragments around a translucent object that are taken for
  /// overlay candidates nearly are background (leaving their rays out instead lost the camera of
  /// a translucent CT head: Match.TranslucentHeadOrientedByItsColours).
  /// Rays are cast through every `stride`-th pixel along x and y. Throws ddg::Error when no
  /// pixel would be cast.
  EmissionScreen(const DifferentiableRenderer& renderer, const RenderOptions& how,
    const Image& difference, const Mask& care, int stride = 2, int bins = 24);

  /// The residual of the picture at `view`'s camera (rendered at the raster's size).
  double residual(const View& view) const;

  /// An image-plane alignment of a render to the picture: render pixel p lands on the picture's
  /// point ct + scale R(rho) (p - cr) (pixel coordinates of the raster, y down).
  struct Alignment
  {
    double crx = 0, cry = 0, ctx = 0, cty = 0, rho = 0, scale = 1;
  };
  /// The residuals of the picture at `view` moved in the image plane by each alignment: one
  /// ray cast for all (a roll, a dolly and a pan move the image, to first order). Counted in
  /// the picture's pixels: a render pixel stands for scale^2 of them, and the picture's
  /// difference that no render pixel lands on counts as unexplained.
  std::vector<double> residuals(const View& view, const std::vector<Alignment>& alignments) const;

private:
  Eigen::MatrixXd histograms(const View& view) const;
  double solve(const Eigen::MatrixXd& n, const Eigen::MatrixXd& d) const;

  const DifferentiableRenderer& Renderer;
  RenderOptions How;
  Image Difference;
  Mask Care;
  std::vector<int> Pixels; // raster pixels whose rays are cast
  double Energy = 0;       // sum of the squared difference over them (where care is set)
  int Bins;
};

/// The screen's input: `picture` (RGB over `view`'s background, or RGBA with straight alpha)
/// at a w x h raster minus its background (RGBA: its premultiplied colour).
Image pictureDifference(const Image& picture, const View& view, int w, int h);

/// A direction's alignment to the picture and the camera it makes (stage 1 of the search).
using Aligned = std::vector<std::pair<EmissionScreen::Alignment, CameraParams>>;

/// The colours' screening (stage 2b of the search): every alignment in `aligned` (per direction;
/// the caller keeps those whose silhouette overlaps the picture's by half or more; their
/// camera relative to `start`) gets the emission residual (into its CameraParams::colour); the
/// best `count` distinct ones (20 degrees apart) are refined by Nelder-Mead on the residual (100
/// evaluations) and returned, marked fromColours, colour = their residual. Runs the directions,
/// then the candidates, side by side on `threads` (the screen's renders should use one each).
std::vector<CameraParams> screenByColours(const EmissionScreen& screen, const View& start,
  const std::vector<std::pair<double, double>>& directions, std::vector<Aligned>& aligned,
  int count, int threads);

/// Stage 3 of the search: the finalists (best silhouette overlap first) that get a short
/// reconstruction each. The distinct (15 degrees apart) silhouettes' cameras within 0.1 of the
/// best overlap, at most `cameraCandidates` (at least the best silhouettes' one); then the
/// colours' cameras (fromColours, their residual in `colour`) that explain the picture's colours
/// clearly better than all of those (a residual under 0.8 of theirs: refined on the colours, a
/// colours' camera has the edge near the right direction), the best explained first, each
/// replacing the silhouettes' cameras within 15 degrees of it; and the colours' best-explained
/// camera when it looks from a direction none of the chosen does (more than 15 degrees from
/// each) and explains the colours better than all of them, whatever the margin: a translucent
/// object's silhouettes can all point elsewhere. `residual` gives a silhouettes' camera its
/// emission residual (null: no colours' screening; the silhouettes' cameras alone). The
/// silhouettes' cameras chosen get their residual in `colour`.
std::vector<CameraParams> camerasToScore(const std::vector<CameraParams>& finalists,
  const View& start, int cameraCandidates, const std::function<double(const View&)>& residual);

/// The camera search's stages that do not depend on the lighting (Match.cxx): the volume's block
/// silhouettes, the finalists of the silhouettes and of the colours' screening (their distances
/// corrected) and the screening's emission model. matchPicture, estimating the lighting, keeps
/// them from its first match of a picture for the next, which differs in the lighting alone:
/// the same cameras, searched once.
struct CameraSearchStages
{
  std::shared_ptr<const SilhouetteModel> model;
  std::vector<CameraParams> finalists;
  std::shared_ptr<const EmissionScreen> screen;
};

} // namespace matchparts
} // namespace ddg
