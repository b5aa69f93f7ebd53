// ViewEstimation.cxx: coarse grid over orbit views, short reconstructions, local refinement.
#include "Reconstruct/ViewEstimation.h"

#include "Common/Error.h"
#include "Render/RayCaster.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ddg
{

View orbitView(const View& base, double azimuthDeg, double elevationDeg, double zoom)
{
  View v = base;
  const Eigen::Vector3d up = base.camera.viewUp.normalized();
  Eigen::Vector3d offset = base.camera.position - base.camera.focalPoint;
  offset = Eigen::AngleAxisd(azimuthDeg * M_PI / 180.0, up) * offset;
  const Eigen::Vector3d right = (-offset).normalized().cross(up).normalized();
  offset = Eigen::AngleAxisd(-elevationDeg * M_PI / 180.0, right) * offset;
  v.camera.position = base.camera.focalPoint + offset / zoom;
  v.camera.parallelScale = base.camera.parallelScale / zoom;
  const Eigen::Vector3d forward = (-offset).normalized();
  v.camera.viewUp = forward.cross(up).cross(forward).normalized();
  return v;
}

namespace
{

// Foreground of a target: differs from the background (opaque) or has alpha (RGBA).
std::vector<char> foreground(const Image& img, const std::array<double, 3>& bg)
{
  const size_t n = static_cast<size_t>(img.width) * img.height;
  std::vector<char> mask(n, 0);
  for (size_t i = 0; i < n; ++i)
  {
    const float* p = &img.pixels[i * img.channels];
    if (img.channels == 4)
      mask[i] = p[3] > 1.0f / 255.0f;
    else
      for (int c = 0; c < 3; ++c)
        mask[i] = mask[i] || std::abs(p[c] - bg[c]) > 2.5 / 255.0;
  }
  return mask;
}

Image downsample(const Image& img, int w, int h)
{
  return resizeImage(img, w, h);
}

} // namespace

View estimateView(const DifferentiableRenderer& renderer, const ReconstructionTarget& target,
  const ViewEstimationOptions& opt, ViewEstimationReport* report)
{
  const auto start = std::chrono::steady_clock::now();
  const View& base = target.view;
  base.validate();
  if (target.image.width != base.width || target.image.height != base.height)
  {
    throw Error("estimate view: the target's size differs from its view's");
  }
  const RayCaster& caster = renderer.caster();
  // Small scoring images with the target's aspect.
  const double aspect = static_cast<double>(base.width) / base.height;
  const int sw = std::max(8, static_cast<int>(std::lround(opt.scoreSize * std::min(1.0, aspect))));
  const int sh =
    std::max(8, static_cast<int>(std::lround(opt.scoreSize * std::min(1.0, 1.0 / aspect))));
  View small = base;
  small.width = sw;
  small.height = sh;
  const Image smallTarget = downsample(target.image, sw, sh);
  const auto targetMask = foreground(smallTarget, base.background);

  // Occupancy TFs: opaque above one of three thresholds of the data range.
  const auto range = caster.volume().range();
  std::vector<TransferTable1D> occupancy;
  for (double q : { 0.25, 0.45, 0.65 })
  {
    TransferFunction1D tf;
    const double x = range[0] + q * (range[1] - range[0]);
    tf.color = { { range[0], 1, 1, 1 } };
    tf.opacity = { { range[0], 0 }, { x, 0 }, { x + 1e-3 * (range[1] - range[0]), 1 },
      { range[1], 1 } };
    occupancy.push_back(bakeTable(tf, range[0], range[1], 1024));
  }
  auto maskScore = [&](const View& v)
  {
    double best = 0;
    for (const auto& table : occupancy)
    {
      const Image r = caster.render(table, v, opt.render);
      size_t inter = 0, uni = 0;
      for (size_t i = 0; i < targetMask.size(); ++i)
      {
        const bool m = r.pixels[4 * i + 3] > 0.5f;
        inter += m && targetMask[i];
        uni += m || targetMask[i];
      }
      best = std::max(best, uni ? static_cast<double>(inter) / uni : 0.0);
    }
    return best;
  };

  struct Candidate
  {
    double az, el, zoom, score;
  };
  std::vector<Candidate> grid;
  for (double el = -60; el <= 60 + 1e-9; el += opt.elevationStep)
    for (double az = 0; az < 360 - 1e-9; az += opt.azimuthStep)
      for (double z : opt.zooms)
        grid.push_back({ az, el, z, maskScore(orbitView(small, az, el, z)) });
  std::sort(grid.begin(), grid.end(),
    [](const Candidate& a, const Candidate& b) { return a.score > b.score; });

  // Short reconstruction at a view: its final loss is the score (lower is better).
  ReconstructionOptions ropt;
  ropt.iterations = opt.scoreSteps;
  ropt.raysPerIteration = 0;
  ropt.bins = 64;
  ropt.patience = opt.scoreSteps;
  ropt.render = opt.render;
  int evaluations = 0;
  auto fitLoss = [&](double az, double el, double zoom)
  {
    ++evaluations;
    ReconstructionTarget t;
    t.image = smallTarget;
    t.view = orbitView(small, az, el, zoom);
    const auto r = reconstructTransferFunction(renderer, { t }, ropt);
    const size_t tail = std::min<size_t>(10, r.loss.size());
    double mean = 0;
    for (size_t i = r.loss.size() - tail; i < r.loss.size(); ++i)
      mean += r.loss[i] / tail;
    return mean;
  };
  Candidate best{ 0, 0, 1, 1e300 };
  for (int c = 0; c < std::min<int>(opt.candidates, static_cast<int>(grid.size())); ++c)
  {
    const double loss = fitLoss(grid[c].az, grid[c].el, grid[c].zoom);
    if (loss < best.score)
    {
      best = { grid[c].az, grid[c].el, grid[c].zoom, loss };
    }
  }
  // Local refinement: coordinate steps, halving.
  double step = opt.azimuthStep / 2, zoomStep = 0.1;
  for (int round = 0; round < opt.refineRounds; ++round)
  {
    bool improved = true;
    for (int pass = 0; pass < 2 && improved; ++pass) // at most two passes per step size
    {
      improved = false;
      const Candidate moves[6] = { { best.az + step, best.el, best.zoom, 0 },
        { best.az - step, best.el, best.zoom, 0 },
        { best.az, std::min(89.0, best.el + step), best.zoom, 0 },
        { best.az, std::max(-89.0, best.el - step), best.zoom, 0 },
        { best.az, best.el, best.zoom * (1 + zoomStep), 0 },
        { best.az, best.el, best.zoom / (1 + zoomStep), 0 } };
      for (const auto& m : moves)
      {
        const double loss = fitLoss(m.az, m.el, m.zoom);
        if (loss < best.score * 0.999)
        {
          best = { m.az, m.el, m.zoom, loss };
          improved = true;
        }
      }
    }
    step /= 2;
    zoomStep /= 2;
  }
  if (report)
  {
    report->azimuth = std::fmod(best.az + 360.0, 360.0);
    report->elevation = best.el;
    report->zoom = best.zoom;
    report->loss = best.score;
    report->evaluations = evaluations;
    report->seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return orbitView(base, best.az, best.el, best.zoom);
}

} // namespace ddg
