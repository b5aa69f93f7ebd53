// MatchEmission.cxx: the emission model's screening of cameras by a picture's colours, and the
// choice of the cameras a short reconstruction scores (MatchCamera.h).
#include "Reconstruct/MatchCamera.h"

#include "Common/Error.h"
#include "Common/Parallel.h"
#include "Render/PieceExchange.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <iterator>
#include <limits>

namespace ddg
{
namespace matchparts
{

EmissionScreen::EmissionScreen(const DifferentiableRenderer& renderer, const RenderOptions& how,
  const Image& difference, const Mask& care, int stride, int bins)
  : Renderer(renderer)
  , How(how)
  , Difference(difference)
  , Care(care)
  , Bins(bins)
{
  if (difference.width != care.w || difference.height != care.h || difference.channels != 3)
    throw Error("EmissionScreen: the picture's difference (RGB) and its mask differ in size");
  if (stride < 1 || bins < 1 || care.w <= stride / 2 || care.h <= stride / 2)
    throw Error("EmissionScreen: no pixel to cast (stride, bins or raster too small)");
  for (int y = stride / 2; y < care.h; y += stride)
    for (int x = stride / 2; x < care.w; x += stride)
    {
      const int i = y * care.w + x;
      Pixels.push_back(i);
      if (care.m[static_cast<size_t>(i)])
        for (int c = 0; c < 3; ++c)
          Energy += static_cast<double>(difference.pixels[3 * static_cast<size_t>(i) + c]) *
            difference.pixels[3 * static_cast<size_t>(i) + c];
    }
}

namespace
{
// The ridge: a thousandth of the mean diagonal of n'n (bins no ray reaches get k = 0).
double ridgeOf(const Eigen::MatrixXd& ntn, int bins)
{
  return 1e-3 * std::max(ntn.trace() / bins, 1e-12);
}
} // namespace

// Per cast pixel, its ray's samples counted per value bin (rows: pixels, columns: bins). A ray
// whose samples were not kept (beyond the renderer's record budget) counts none. Cast unlit
// whatever the view's lighting: the counts do not depend on it, and a lit pass's records would
// also hold each sample's light sums after its value.
Eigen::MatrixXd EmissionScreen::histograms(const View& view) const
{
  View v = view;
  v.width = Difference.width;
  v.height = Difference.height;
  v.lighting = Lighting{};
  const auto range = Renderer.dataRange();
  // a transparent table: every ray is marched to its end, all its samples kept
  const int tableWidth = 2;
  const std::vector<float> table(4 * tableWidth, 0.0f);
  std::vector<float> rgba;
  std::vector<RayRecord> records;
  Renderer.forward(table.data(), tableWidth, range[0], range[1], v, How, Pixels, rgba, records);
  Eigen::MatrixXd n = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(Pixels.size()), Bins);
  const double scale = Bins / std::max(range[1] - range[0], 1e-30);
  for (size_t q = 0; q < records.size(); ++q)
    for (float x : records[q].samples)
    {
      const int b = std::clamp(static_cast<int>((x - range[0]) * scale), 0, Bins - 1);
      n(static_cast<Eigen::Index>(q), b) += 1;
    }
  if (const PieceExchange* exchange = Renderer.exchange())
  {
    // a piece counts the samples it owns: the whole's counts are the pieces' sum (whole numbers,
    // exact in float; summed in piece order, the same on every piece)
    const Eigen::MatrixXf mine = n.cast<float>();
    std::vector<float> all(static_cast<size_t>(mine.size()) * exchange->pieces());
    exchange->allGather(mine.data(), mine.size(), all.data());
    n.setZero();
    for (int p = 0; p < exchange->pieces(); ++p)
      n += Eigen::Map<const Eigen::MatrixXf>(
        all.data() + static_cast<size_t>(p) * mine.size(), n.rows(), n.cols())
             .cast<double>();
  }
  return n;
}

// The RMS residual of d ~ n k by ridge least squares (ridgeOf).
double EmissionScreen::solve(const Eigen::MatrixXd& n, const Eigen::MatrixXd& d) const
{
  Eigen::MatrixXd ntn = n.transpose() * n;
  const double ridge = ridgeOf(ntn, Bins);
  ntn.diagonal().array() += ridge;
  const Eigen::MatrixXd ntd = n.transpose() * d;
  const Eigen::MatrixXd k = ntn.ldlt().solve(ntd);
  const double r = (n * k - d).squaredNorm();
  return std::sqrt(r / static_cast<double>(3 * std::max<Eigen::Index>(1, d.rows())));
}

double EmissionScreen::residual(const View& view) const
{
  const Eigen::MatrixXd n = histograms(view);
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n.rows(), 3);
  for (size_t q = 0; q < Pixels.size(); ++q)
  {
    const int i = Pixels[q];
    if (!Care.m[static_cast<size_t>(i)])
      continue;
    for (int c = 0; c < 3; ++c)
      d(static_cast<Eigen::Index>(q), c) = Difference.pixels[3 * static_cast<size_t>(i) + c];
  }
  return solve(n, d);
}

std::vector<double> EmissionScreen::residuals(
  const View& view, const std::vector<Alignment>& alignments) const
{
  const Eigen::MatrixXd n = histograms(view);
  // n'n is the same for every alignment: factored once
  Eigen::MatrixXd ntn = n.transpose() * n;
  const double ridge = ridgeOf(ntn, Bins);
  ntn.diagonal().array() += ridge;
  const Eigen::LDLT<Eigen::MatrixXd> factor(ntn);
  const int w = Difference.width, h = Difference.height;
  std::vector<double> out;
  out.reserve(alignments.size());
  Eigen::MatrixXd d(n.rows(), 3);
  for (const auto& a : alignments)
  {
    const double c = std::cos(a.rho), s = std::sin(a.rho);
    for (size_t q = 0; q < Pixels.size(); ++q)
    {
      const int i = Pixels[q];
      const double px = i % w + 0.5 - a.crx, py = i / w + 0.5 - a.cry;
      // the picture's point, then bilinear between pixel centres
      const double u = a.ctx + a.scale * (c * px - s * py) - 0.5,
                   v = a.cty + a.scale * (s * px + c * py) - 0.5;
      const int x0 = static_cast<int>(std::floor(u)), y0 = static_cast<int>(std::floor(v));
      const double fx = u - x0, fy = v - y0;
      double value[3] = { 0, 0, 0 };
      for (int k = 0; k < 4; ++k)
      {
        const int x = x0 + (k & 1), y = y0 + (k >> 1);
        if (x < 0 || y < 0 || x >= w || y >= h || !Care(x, y))
          continue; // off the picture, or an overlay: taken as background (see MatchCamera.h)
        const double wk = ((k & 1) ? fx : 1 - fx) * ((k >> 1) ? fy : 1 - fy);
        for (int cc = 0; cc < 3; ++cc)
          value[cc] += wk * Difference.pixels[3 * (static_cast<size_t>(y) * w + x) + cc];
      }
      for (int cc = 0; cc < 3; ++cc)
        d(static_cast<Eigen::Index>(q), cc) = value[cc];
    }
    const Eigen::MatrixXd ntd = n.transpose() * d;
    const Eigen::MatrixXd k = factor.solve(ntd);
    // |n k - d|^2 = d'd - 2 k'(n'd) + k'(n'n) k, with n'n the unridged product
    const double r = d.squaredNorm() - 2.0 * (k.array() * ntd.array()).sum() +
      (k.array() * ((ntn * k) - ridge * k).array()).sum();
    // in the picture's pixels: a render pixel stands for scale^2 of them, and the picture's
    // difference that no render pixel lands on is unexplained
    const double a2 = a.scale * a.scale;
    const double uncovered = std::max(0.0, Energy - a2 * d.squaredNorm());
    out.push_back(std::sqrt((a2 * std::max(0.0, r) + uncovered) / (3.0 * Pixels.size())));
  }
  return out;
}

Image pictureDifference(const Image& picture, const View& view, int w, int h)
{
  const Image small = resizeImage(picture, w, h);
  Image difference(w, h, 3);
  for (int y = 0; y < h; ++y)
  {
    // the background of the raster's row: the picture's row at its centre
    const auto bg = view.backgroundAt(
      std::min(picture.height - 1, static_cast<int>((y + 0.5) * picture.height / h)));
    for (int x = 0; x < w; ++x)
    {
      const float* p = &small.pixels[(static_cast<size_t>(y) * w + x) * small.channels];
      for (int c = 0; c < 3; ++c)
        difference.pixels[3 * (static_cast<size_t>(y) * w + x) + c] =
          small.channels == 4 ? p[c] * p[3] : static_cast<float>(p[c] - bg[c]);
    }
  }
  return difference;
}

std::vector<CameraParams> screenByColours(const EmissionScreen& screen, const View& start,
  const std::vector<std::pair<double, double>>& directions, std::vector<Aligned>& aligned,
  int count, int threads)
{
  // one ray cast per direction for all its alignments; the directions side by side
  parallelFor(static_cast<std::int64_t>(directions.size()), threads,
    [&](std::int64_t d, int)
    {
      auto& of = aligned[static_cast<size_t>(d)];
      if (of.empty())
        return;
      CameraParams at;
      at.az = directions[static_cast<size_t>(d)].first;
      at.el = directions[static_cast<size_t>(d)].second;
      std::vector<EmissionScreen::Alignment> a;
      for (const auto& e : of)
        a.push_back(e.first);
      const auto r = screen.residuals(at.view(start), a);
      for (size_t k = 0; k < r.size(); ++k)
        of[k].second.colour = r[k];
    });
  std::vector<CameraParams> ranked;
  for (const auto& of : aligned)
    for (const auto& e : of)
      ranked.push_back(e.second);
  std::sort(ranked.begin(), ranked.end(),
    [](const CameraParams& a, const CameraParams& b) { return a.colour < b.colour; });
  std::vector<CameraParams> picked;
  for (const auto& c : ranked)
  {
    if (static_cast<int>(picked.size()) >= count)
      break;
    bool distinct = true;
    for (const auto& p : picked)
      distinct = distinct && orientationDistance(c.view(start), p.view(start)) > 20;
    if (distinct)
      picked.push_back(c);
  }
  // each refined by Nelder-Mead on the residual, side by side
  std::vector<CameraParams> refined(picked.size());
  parallelFor(static_cast<std::int64_t>(picked.size()), threads,
    [&](std::int64_t i, int)
    {
      CameraParams& r = refined[static_cast<size_t>(i)];
      r = nelderMead(
        picked[static_cast<size_t>(i)],
        [&](const CameraParams& p) { return -screen.residual(p.view(start)); }, 100);
      r.colour = -r.score;
      r.fromColours = true;
    });
  return refined;
}

std::vector<CameraParams> camerasToScore(const std::vector<CameraParams>& finalists,
  const View& start, int cameraCandidates, const std::function<double(const View&)>& residual)
{
  const auto apart = [&](const CameraParams& a, const CameraParams& b)
  { return orientationDistance(a.view(start), b.view(start)) > 15; };
  std::vector<CameraParams> scored;
  if (finalists.empty())
    return scored;
  for (const auto& f : finalists)
  {
    bool distinct = true;
    for (const auto& s : scored)
      distinct = distinct && apart(f, s);
    if (distinct && !f.fromColours && f.score >= finalists.front().score - 0.1 &&
      static_cast<int>(scored.size()) < std::max(1, cameraCandidates))
      scored.push_back(f);
  }
  if (scored.empty()) // a colours' camera overlaps best by far: the best silhouettes' one
  {
    const auto first = std::find_if(
      finalists.begin(), finalists.end(), [](const CameraParams& f) { return !f.fromColours; });
    scored.push_back(first != finalists.end() ? *first : finalists.front());
  }
  if (!residual)
    return scored;
  double silhouettesColour = std::numeric_limits<double>::infinity();
  for (auto& f : scored)
    silhouettesColour = std::min(silhouettesColour, f.colour = residual(f.view(start)));
  std::vector<CameraParams> byColour;
  std::copy_if(finalists.begin(), finalists.end(), std::back_inserter(byColour),
    [](const CameraParams& f) { return f.fromColours; });
  std::sort(byColour.begin(), byColour.end(),
    [](const CameraParams& a, const CameraParams& b) { return a.colour < b.colour; });
  // (one near a silhouettes' camera replaces it: the same direction, better explained)
  for (const auto& f : byColour)
  {
    if (f.colour >= 0.8 * silhouettesColour)
      break;
    std::vector<CameraParams> kept;
    bool nearColours = false;
    for (const auto& s : scored)
    {
      const bool near = !apart(f, s);
      nearColours = nearColours || (near && s.fromColours);
      if (!near || s.fromColours)
        kept.push_back(s);
    }
    if (nearColours)
      continue;
    kept.push_back(f);
    scored = std::move(kept);
  }
  if (!byColour.empty())
  {
    const CameraParams& best = byColour.front();
    bool distinct = true, explainsBest = true;
    for (const auto& s : scored)
      distinct = distinct && apart(best, s), explainsBest = explainsBest && best.colour < s.colour;
    if (distinct && explainsBest)
      scored.push_back(best);
  }
  return scored;
}

} // namespace matchparts
} // namespace ddg
