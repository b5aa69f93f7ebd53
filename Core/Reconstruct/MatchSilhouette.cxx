// MatchSilhouette.cxx: the volume's block silhouettes (MatchParts.h's SilhouetteModel).
#include "Reconstruct/MatchParts.h"

#include "Render/PieceExchange.h"
#include "Volume/Volume.h"
#include "Volume/VolumeBrick.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace ddg
{
namespace matchparts
{

namespace
{
// The blocks of a volume of `d` points: about 64 a side, bs points each (a block covers the
// points b bs .. (b + 1) bs inclusive).
struct Blocks
{
  int bs = 1;
  int nb[3] = { 1, 1, 1 };
  explicit Blocks(const std::array<int, 3>& d)
  {
    const int longest = std::max({ d[0], d[1], d[2] });
    bs = std::max(1, (longest + 63) / 64); // at most ~64 blocks a side
    for (int k = 0; k < 3; ++k)
      nb[k] = std::max(1, (d[k] - 1 + bs - 1) / bs);
  }
  size_t count() const { return static_cast<size_t>(nb[0]) * nb[1] * nb[2]; }
  // the blocks point i belongs to along an axis of n blocks: a point on a block's lower face
  // belongs to the block below as well
  std::pair<int, int> of(int i, int n) const
  {
    const int hi = std::min(n - 1, i / bs);
    const int lo = (i % bs == 0 && i > 0) ? std::min(hi, i / bs - 1) : hi;
    return { lo, hi };
  }
  // the largest value per block over the points lo .. hi (whole indices) of `vol`, whose point 0
  // is the whole's point `offset`
  void maxima(const Volume& vol, const std::array<int, 3>& lo, const std::array<int, 3>& hi,
    const std::array<int, 3>& offset, std::vector<float>& blockMax) const
  {
    for (int k = lo[2]; k <= hi[2]; ++k)
    {
      const auto [bk0, bk1] = of(k, nb[2]);
      for (int j = lo[1]; j <= hi[1]; ++j)
      {
        const auto [bj0, bj1] = of(j, nb[1]);
        for (int i = lo[0]; i <= hi[0]; ++i)
        {
          const float v = vol.at(i - offset[0], j - offset[1], k - offset[2]);
          const auto [bi0, bi1] = of(i, nb[0]);
          for (int bk = bk0; bk <= bk1; ++bk)
            for (int bj = bj0; bj <= bj1; ++bj)
              for (int bi = bi0; bi <= bi1; ++bi)
              {
                float& m = blockMax[(static_cast<size_t>(bk) * nb[1] + bj) * nb[0] + bi];
                m = std::max(m, v);
              }
        }
      }
    }
  }
};
} // namespace

SilhouetteModel::SilhouetteModel(const Volume& vol)
{
  const Blocks blocks(vol.dims());
  std::vector<float> blockMax(blocks.count(), -1e30f);
  const auto& d = vol.dims();
  blocks.maxima(vol, { 0, 0, 0 }, { d[0] - 1, d[1] - 1, d[2] - 1 }, { 0, 0, 0 }, blockMax);
  build(d, vol.origin(), vol.spacing(), blockMax);
}

SilhouetteModel::SilhouetteModel(const DifferentiableRenderer& renderer)
{
  const VolumeBrick* brick = renderer.brick();
  if (!brick)
  {
    *this = SilhouetteModel(renderer.caster().volume());
    return;
  }
  // each piece the blocks over the points it owns; the largest over the pieces
  const Blocks blocks(brick->wholeDims);
  std::vector<float> blockMax(blocks.count(), -1e30f);
  if (!brick->ownsNothing())
    blocks.maxima(
      renderer.caster().volume(), brick->ownedMin, brick->ownedMax, brick->offset, blockMax);
  const PieceExchange& exchange = *renderer.exchange();
  std::vector<float> all(blockMax.size() * static_cast<size_t>(exchange.pieces()));
  exchange.allGather(blockMax.data(), static_cast<std::int64_t>(blockMax.size()), all.data());
  for (int p = 0; p < exchange.pieces(); ++p)
    for (size_t b = 0; b < blockMax.size(); ++b)
      blockMax[b] = std::max(blockMax[b], all[static_cast<size_t>(p) * blockMax.size() + b]);
  build(brick->wholeDims, brick->wholeOrigin, brick->spacing, blockMax);
}

void SilhouetteModel::build(const std::array<int, 3>& d, const std::array<double, 3>& o,
  const std::array<double, 3>& s, const std::vector<float>& blockMax)
{
  const Blocks blocks(d);
  const int bs = blocks.bs;
  const int* nb = blocks.nb;
  // levels: thresholds at which these fractions of the blocks are occupied
  std::vector<float> sorted = blockMax;
  std::sort(sorted.begin(), sorted.end());
  std::vector<float> thresholds;
  for (double f : { 0.9, 0.7, 0.5, 0.35, 0.22, 0.12, 0.06, 0.03, 0.015 })
  {
    const size_t idx = std::min(
      sorted.size() - 1, static_cast<size_t>((1.0 - f) * static_cast<double>(sorted.size())));
    const float t = sorted[idx];
    if (t > sorted.front() && (thresholds.empty() || t > thresholds.back()))
      thresholds.push_back(t);
  }
  Eigen::Vector3d half;
  for (int k = 0; k < 3; ++k)
    half[k] = 0.5 * bs * std::abs(s[k]);
  Radius = half.minCoeff(); // the inscribed sphere: occupied blocks already reach past the surface
  for (float t : thresholds)
  {
    std::vector<Eigen::Vector3f> pts;
    auto occupied = [&](int bi, int bj, int bk)
    {
      if (bi < 0 || bj < 0 || bk < 0 || bi >= nb[0] || bj >= nb[1] || bk >= nb[2])
        return false;
      return blockMax[(static_cast<size_t>(bk) * nb[1] + bj) * nb[0] + bi] >= t;
    };
    for (int bk = 0; bk < nb[2]; ++bk)
      for (int bj = 0; bj < nb[1]; ++bj)
        for (int bi = 0; bi < nb[0]; ++bi)
        {
          if (!occupied(bi, bj, bk))
            continue;
          if (occupied(bi - 1, bj, bk) && occupied(bi + 1, bj, bk) && occupied(bi, bj - 1, bk) &&
            occupied(bi, bj + 1, bk) && occupied(bi, bj, bk - 1) && occupied(bi, bj, bk + 1))
            continue; // inside: hidden in any projection by its neighbours
          const int idx[3] = { bi, bj, bk };
          Eigen::Vector3f c;
          for (int k = 0; k < 3; ++k)
          {
            const double lo = idx[k] * bs, hi = std::min<double>((idx[k] + 1) * bs, d[k] - 1);
            c[k] = static_cast<float>(o[k] + s[k] * 0.5 * (lo + hi));
          }
          pts.push_back(c);
        }
    if (!pts.empty())
    {
      Points.push_back(std::move(pts));
      Thresholds.push_back(t);
    }
  }
}

// The silhouette of level `level` at `view` in a w x h raster (the view's framing).
void SilhouetteModel::render(const View& view, int level, int w, int h, Mask& out) const
{
  out = Mask(w, h);
  const auto& cam = view.camera;
  const Eigen::Vector3d fwd = (cam.focalPoint - cam.position).normalized();
  const Eigen::Vector3d right = fwd.cross(cam.viewUp).normalized();
  const Eigen::Vector3d up = right.cross(fwd);
  const double f = cam.parallelProjection ? 0.5 * h / cam.parallelScale
                                          : 0.5 * h / std::tan(cam.viewAngle * M_PI / 360.0);
  const Eigen::Vector3f p0 = cam.position.cast<float>();
  const Eigen::Vector3f fw = fwd.cast<float>(), rt = right.cast<float>(), u = up.cast<float>();
  for (const auto& p : Points[static_cast<size_t>(level)])
  {
    const Eigen::Vector3f q = p - p0;
    const float z = q.dot(fw);
    double scale = f;
    if (!cam.parallelProjection)
    {
      if (z <= 1e-6f)
        continue;
      scale = f / z;
    }
    const double cx = 0.5 * w + q.dot(rt) * scale, cy = 0.5 * h - q.dot(u) * scale;
    const double r = Radius * scale;
    const int x0 = std::max(0, static_cast<int>(std::ceil(cx - r - 0.5)));
    const int x1 = std::min(w - 1, static_cast<int>(std::floor(cx + r - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::ceil(cy - r - 0.5)));
    const int y1 = std::min(h - 1, static_cast<int>(std::floor(cy + r - 0.5)));
    const double r2 = r * r;
    for (int y = y0; y <= y1; ++y)
    {
      const double dy = y + 0.5 - cy;
      for (int x = x0; x <= x1; ++x)
      {
        const double dx = x + 0.5 - cx;
        if (dx * dx + dy * dy <= r2)
          out(x, y) = 1;
      }
    }
    if (x0 > x1 || y0 > y1) // smaller than a pixel: mark the pixel it falls in
    {
      const int x = static_cast<int>(std::floor(cx)), y = static_cast<int>(std::floor(cy));
      if (x >= 0 && y >= 0 && x < w && y < h)
        out(x, y) = 1;
    }
  }
}

} // namespace matchparts
} // namespace ddg
