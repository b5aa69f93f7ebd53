// ImageMetrics.cxx: PSNR, Gaussian-window SSIM (with its gradient) and the colour-histogram
// EMD (LEMON's network simplex).
#include "Image/ImageMetrics.h"

#include "Common/Error.h"
#include "Common/Parallel.h"
#include "TransferFunction/ColorSpace.h"

#include <lemon/network_simplex.h>
#include <lemon/static_graph.h>

#include <boost/sort/pdqsort/pdqsort.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

namespace ddg
{
namespace
{

void checkPair(const Image& a, const Image& b)
{
  if (a.width != b.width || a.height != b.height)
  {
    throw Error("images differ in size: " + std::to_string(a.width) + "x" +
      std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" + std::to_string(b.height));
  }
  if (a.empty())
  {
    throw Error("cannot compare empty images");
  }
}

} // namespace

double psnr(const Image& a0, const Image& b0)
{
  checkPair(a0, b0);
  const Image a = toChannels(a0, 3), b = toChannels(b0, 3);
  double se = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
  {
    const double d = static_cast<double>(a.pixels[i]) - b.pixels[i];
    se += d * d;
  }
  const double mse = se / a.pixels.size();
  return mse == 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / mse);
}

double psnr(const Image& a0, const Image& b0, const Image& ignore)
{
  if (ignore.empty())
    return psnr(a0, b0);
  checkPair(a0, b0);
  if (ignore.width != a0.width || ignore.height != a0.height)
    throw Error("psnr: the mask's size differs from the images'");
  const Image a = toChannels(a0, 3), b = toChannels(b0, 3);
  double se = 0;
  size_t n = 0;
  for (size_t p = 0, np = static_cast<size_t>(a.width) * a.height; p < np; ++p)
  {
    if (ignore.pixels[p * ignore.channels] > 0.5f)
      continue;
    for (int c = 0; c < 3; ++c)
    {
      const double d = static_cast<double>(a.pixels[3 * p + c]) - b.pixels[3 * p + c];
      se += d * d;
    }
    n += 3;
  }
  return n == 0 || se == 0 ? std::numeric_limits<double>::infinity()
                           : 10.0 * std::log10(static_cast<double>(n) / se);
}

double ssim(const Image& a0, const Image& b0)
{
  checkPair(a0, b0);
  const Image a = toChannels(a0, 3), b = toChannels(b0, 3);
  int win = 11;
  while (win > 1 && (win > a.width || win > a.height))
  {
    win -= 2;
  }
  const int r = win / 2;
  std::vector<double> g(static_cast<size_t>(win));
  double gsum = 0;
  for (int i = 0; i < win; ++i)
  {
    g[i] = std::exp(-0.5 * (i - r) * (i - r) / (1.5 * 1.5));
    gsum += g[i];
  }
  for (double& v : g)
    v /= gsum;
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  const int w = a.width, h = a.height;
  double total = 0;
  long count = 0;
  // Separable filtering of x, y, x^2, y^2, xy per channel.
  std::vector<double> rows(static_cast<size_t>(w) * h * 5), cols(5);
  for (int c = 0; c < 3; ++c)
  {
    for (int y = 0; y < h; ++y)
    {
      for (int x = r; x < w - r; ++x)
      {
        double s[5] = { 0, 0, 0, 0, 0 };
        for (int k = -r; k <= r; ++k)
        {
          const double va = a.at(x + k, y, c), vb = b.at(x + k, y, c), wk = g[k + r];
          s[0] += wk * va;
          s[1] += wk * vb;
          s[2] += wk * va * va;
          s[3] += wk * vb * vb;
          s[4] += wk * va * vb;
        }
        for (int q = 0; q < 5; ++q)
          rows[(static_cast<size_t>(y) * w + x) * 5 + q] = s[q];
      }
    }
    for (int y = r; y < h - r; ++y)
    {
      for (int x = r; x < w - r; ++x)
      {
        double s[5] = { 0, 0, 0, 0, 0 };
        for (int k = -r; k <= r; ++k)
        {
          for (int q = 0; q < 5; ++q)
            s[q] += g[k + r] * rows[(static_cast<size_t>(y + k) * w + x) * 5 + q];
        }
        const double mx = s[0], my = s[1];
        const double vx = s[2] - mx * mx, vy = s[3] - my * my, cxy = s[4] - mx * my;
        total +=
          ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
        ++count;
      }
    }
  }
  return count > 0 ? total / count : 1.0;
}

double ssimWithGradient(const float* x, const float* y, int w, int h, double* dS_dx)
{
  int win = 11;
  while (win > 1 && (win > w || win > h))
  {
    win -= 2;
  }
  const int r = win / 2;
  std::vector<double> g(static_cast<size_t>(win) * win);
  double gsum = 0;
  for (int j = 0; j < win; ++j)
    for (int i = 0; i < win; ++i)
    {
      g[j * win + i] = std::exp(-0.5 * ((i - r) * (i - r) + (j - r) * (j - r)) / (1.5 * 1.5));
      gsum += g[j * win + i];
    }
  for (double& v : g)
    v /= gsum;
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  std::fill(dS_dx, dS_dx + static_cast<size_t>(w) * h * 3, 0.0);
  const long windows = static_cast<long>(w - 2 * r) * (h - 2 * r) * 3;
  double total = 0;
  for (int c = 0; c < 3; ++c)
  {
    for (int cy = r; cy < h - r; ++cy)
    {
      for (int cx = r; cx < w - r; ++cx)
      {
        double mx = 0, my = 0, exx = 0, eyy = 0, exy = 0;
        for (int j = -r; j <= r; ++j)
          for (int i = -r; i <= r; ++i)
          {
            const size_t p = (static_cast<size_t>(cy + j) * w + cx + i) * 3 + c;
            const double gw = g[(j + r) * win + i + r];
            mx += gw * x[p];
            my += gw * y[p];
            exx += gw * x[p] * x[p];
            eyy += gw * y[p] * y[p];
            exy += gw * x[p] * y[p];
          }
        const double a1 = 2 * mx * my + c1, a2 = 2 * (exy - mx * my) + c2;
        const double b1 = mx * mx + my * my + c1, b2 = (exx - mx * mx) + (eyy - my * my) + c2;
        const double sVal = a1 * a2 / (b1 * b2);
        total += sVal;
        // S(mx, exx, exy): d/dmx, d/dexx, d/dexy
        const double dmx =
          (2 * my * a2 - 2 * my * a1) / (b1 * b2) - sVal * (2 * mx / b1 - 2 * mx / b2);
        const double dexy = 2 * a1 / (b1 * b2);
        const double dexx = -sVal / b2;
        for (int j = -r; j <= r; ++j)
          for (int i = -r; i <= r; ++i)
          {
            const size_t p = (static_cast<size_t>(cy + j) * w + cx + i) * 3 + c;
            const double gw = g[(j + r) * win + i + r];
            dS_dx[p] += gw * (dmx + 2 * x[p] * dexx + y[p] * dexy) / windows;
          }
      }
    }
  }
  return windows > 0 ? total / windows : 1.0;
}

// --- colour-histogram EMD ----------------------------------------------------------------

namespace
{
constexpr int kBinsL = 8, kBinsA = 12, kBinsB = 12;
constexpr double kL[2] = { 0.0, 100.0 }, kA[2] = { -86.185, 98.254 }, kB[2] = { -107.863, 94.482 };

int binOf(double v, const double r[2], int n)
{
  return std::clamp(static_cast<int>((v - r[0]) / (r[1] - r[0]) * n), 0, n - 1);
}

// Pixel counts per Lab bin.
std::vector<std::int64_t> labHistogram(const Image& img0)
{
  const Image img = toChannels(img0, 3);
  std::vector<std::int64_t> h(static_cast<size_t>(kBinsL) * kBinsA * kBinsB, 0);
  const size_t n = static_cast<size_t>(img.width) * img.height;
  for (size_t i = 0; i < n; ++i)
  {
    const RGB lab = rgbToLab({ std::clamp<double>(img.pixels[3 * i], 0, 1),
      std::clamp<double>(img.pixels[3 * i + 1], 0, 1),
      std::clamp<double>(img.pixels[3 * i + 2], 0, 1) });
    const int l = binOf(lab[0], kL, kBinsL), a = binOf(lab[1], kA, kBinsA),
              b = binOf(lab[2], kB, kBinsB);
    ++h[(static_cast<size_t>(l) * kBinsA + a) * kBinsB + b];
  }
  return h;
}

std::array<double, 3> binCentre(size_t index)
{
  const int b = static_cast<int>(index % kBinsB), a = static_cast<int>((index / kBinsB) % kBinsA),
            l = static_cast<int>(index / (kBinsB * kBinsA));
  return { kL[0] + (l + 0.5) * (kL[1] - kL[0]) / kBinsL,
    kA[0] + (a + 0.5) * (kA[1] - kA[0]) / kBinsA, kB[0] + (b + 0.5) * (kB[1] - kB[0]) / kBinsB };
}

// LEMON's network simplex needs integer costs (its documented requirement): distances are
// scaled by 2^40 and rounded (at most 290 Lab units: < 2^49, far from overflowing its int64
// potentials). The flow it returns is optimal for the rounded costs, so its true cost is within
// 2^-40 (per unit of mass) of the exact optimum; the EMD is that flow's cost in double.
constexpr double kCostScale = 1099511627776.0; // 2^40

} // namespace

double colorHistogramEMD(const Image& a, const Image& b)
{
  if (a.empty() || b.empty())
  {
    throw Error("cannot compare empty images");
  }
  const auto ha = labHistogram(a), hb = labHistogram(b);
  // Integer masses with equal totals: a's bin carries count * nb / g, b's count * na / g
  // (n = pixel counts, g = gcd), so both sum to F = na nb / g and mass / F is the normalised
  // histogram.
  const std::int64_t na = static_cast<std::int64_t>(a.width) * a.height,
                     nb = static_cast<std::int64_t>(b.width) * b.height, g = std::gcd(na, nb);
  std::vector<size_t> ia, ib;
  for (size_t i = 0; i < ha.size(); ++i)
  {
    if (ha[i] > 0)
      ia.push_back(i);
    if (hb[i] > 0)
      ib.push_back(i);
  }
  // Complete bipartite graph: nodes 0..I-1 are a's occupied bins, I..I+J-1 b's; arc i * J + j
  // goes from a's bin i to b's bin j (arcs sorted by source, as StaticDigraph::build needs).
  const int I = static_cast<int>(ia.size()), J = static_cast<int>(ib.size());
  std::vector<std::pair<int, int>> arcs;
  arcs.reserve(static_cast<size_t>(I) * J);
  for (int i = 0; i < I; ++i)
    for (int j = 0; j < J; ++j)
      arcs.emplace_back(i, I + j);
  lemon::StaticDigraph graph;
  graph.build(I + J, arcs.begin(), arcs.end());
  lemon::StaticDigraph::NodeMap<std::int64_t> supply(graph);
  for (int i = 0; i < I; ++i)
    supply[graph.node(i)] = ha[ia[i]] * (nb / g);
  for (int j = 0; j < J; ++j)
    supply[graph.node(I + j)] = -hb[ib[j]] * (na / g);
  std::vector<double> distance(arcs.size());
  lemon::StaticDigraph::ArcMap<std::int64_t> cost(graph);
  for (int i = 0; i < I; ++i)
  {
    const auto ci = binCentre(ia[i]);
    for (int j = 0; j < J; ++j)
    {
      const auto cj = binCentre(ib[j]);
      const size_t e = static_cast<size_t>(i) * J + j;
      distance[e] = std::sqrt((ci[0] - cj[0]) * (ci[0] - cj[0]) +
        (ci[1] - cj[1]) * (ci[1] - cj[1]) + (ci[2] - cj[2]) * (ci[2] - cj[2]));
      cost[graph.arc(static_cast<int>(e))] = std::llround(distance[e] * kCostScale);
    }
  }
  lemon::NetworkSimplex<lemon::StaticDigraph, std::int64_t, std::int64_t> simplex(graph);
  if (simplex.costMap(cost).supplyMap(supply).run() != decltype(simplex)::OPTIMAL)
  {
    throw Error("colour-histogram EMD: the transport problem has no optimal solution");
  }
  double total = 0;
  for (size_t e = 0; e < arcs.size(); ++e)
  {
    const std::int64_t flow = simplex.flow(graph.arc(static_cast<int>(e)));
    if (flow != 0)
      total += static_cast<double>(flow) * distance[e];
  }
  return total / (static_cast<double>(na / g) * static_cast<double>(nb));
}

namespace
{
template <size_t D>
std::vector<std::array<double, D>> drawDirections(int count, std::mt19937_64& rng)
{
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<std::array<double, D>> u(static_cast<size_t>(count));
  for (auto& v : u)
  {
    double len = 0;
    do
    {
      len = 0;
      for (double& x : v)
      {
        x = normal(rng);
        len += x * x;
      }
    } while (len < 1e-12);
    len = std::sqrt(len);
    for (double& x : v)
      x /= len;
  }
  return u;
}

template <size_t D>
double project(const std::array<double, D>& v, const std::array<float, D>& p)
{
  double x = 0;
  for (size_t c = 0; c < D; ++c)
    x += v[c] * p[c];
  return x;
}

/// The distance of a to b along `dirs`, b's projections on the d-th ascending from
/// sortedB(d, scratch) (m values): each direction's sum and gradient terms apart,
/// added up in direction order after, so the result does not depend on the thread count.
template <size_t D, typename Sorted>
double slicedWassersteinAlong(const std::vector<std::array<float, D>>& a, size_t m,
  const std::vector<const std::array<double, D>*>& dirs, const Sorted& sortedB,
  std::vector<std::array<float, D>>* gradient, int threads)
{
  const size_t n = a.size();
  const int directions = static_cast<int>(dirs.size());
  std::vector<double> sums(dirs.size(), 0.0);
  std::vector<std::array<float, D>> terms(gradient ? n * dirs.size() : 0);
  struct Scratch
  {
    std::vector<double> pa, pb;
    std::vector<size_t> order;
  };
  const int workers = resolveThreadCount(threads, directions);
  std::vector<Scratch> scratch(static_cast<size_t>(workers));
  parallelFor(directions, workers,
    [&](std::int64_t d, int t)
    {
      Scratch& s = scratch[static_cast<size_t>(t)];
      s.pa.resize(n);
      s.order.resize(n);
      const auto& v = *dirs[static_cast<size_t>(d)];
      for (size_t i = 0; i < n; ++i)
        s.pa[i] = project(v, a[i]);
      const auto pb = sortedB(static_cast<size_t>(d), s.pb);
      std::iota(s.order.begin(), s.order.end(), size_t(0));
      std::sort(
        s.order.begin(), s.order.end(), [&](size_t x, size_t y) { return s.pa[x] < s.pa[y]; });
      double total = 0;
      for (size_t r = 0; r < n; ++r)
      {
        // b's quantile at a's rank r
        const double q = std::clamp((r + 0.5) / n * m - 0.5, 0.0, static_cast<double>(m - 1));
        const size_t lo = std::min(static_cast<size_t>(q), m - 1), hi = std::min(lo + 1, m - 1);
        const double partner = pb[lo] + (q - lo) * (pb[hi] - pb[lo]);
        const size_t i = s.order[r];
        const double diff = s.pa[i] - partner;
        total += diff * diff;
        if (gradient)
          for (size_t c = 0; c < D; ++c)
            terms[static_cast<size_t>(d) * n + i][c] =
              static_cast<float>(2.0 * diff * v[c] / (n * directions));
      }
      sums[static_cast<size_t>(d)] = total;
    });
  if (gradient)
  {
    gradient->assign(n, std::array<float, D>{});
    for (int d = 0; d < directions; ++d)
      for (size_t i = 0; i < n; ++i)
        for (size_t c = 0; c < D; ++c)
          (*gradient)[i][c] += terms[static_cast<size_t>(d) * n + i][c];
  }
  double total = 0;
  for (const double x : sums)
    total += x;
  return total / (static_cast<double>(n) * directions);
}

template <size_t D>
double slicedWassersteinOf(const std::vector<std::array<float, D>>& a,
  const std::vector<std::array<float, D>>& b, int directions, std::mt19937_64& rng,
  std::vector<std::array<float, D>>* gradient, int threads)
{
  if (a.empty() || b.empty() || directions < 1)
    throw Error("slicedWasserstein needs two non-empty sets and at least one direction");
  // the directions first, in the order they were always drawn (the same for any thread count)
  const auto u = drawDirections<D>(directions, rng);
  std::vector<const std::array<double, D>*> dirs;
  for (const auto& v : u)
    dirs.push_back(&v);
  return slicedWassersteinAlong<D>(
    a, b.size(), dirs,
    [&](size_t d, std::vector<double>& pb) -> const double*
    {
      pb.resize(b.size());
      for (size_t j = 0; j < b.size(); ++j)
        pb[j] = project(u[d], b[j]);
      boost::sort::pdqsort_branchless(pb.begin(), pb.end());
      return pb.data();
    },
    gradient, threads);
}

template <size_t D>
SortedProjections<D> sortedProjectionsOf(
  const std::vector<std::array<float, D>>& b, int pool, std::mt19937_64& rng, int threads)
{
  if (b.empty() || pool < 1)
    throw Error("sortedProjections needs a non-empty set and a pool of at least one direction");
  SortedProjections<D> r;
  r.directions = drawDirections<D>(pool, rng);
  r.count = b.size();
  r.sorted.resize(static_cast<size_t>(pool) * b.size());
  parallelFor(pool, resolveThreadCount(threads, pool),
    [&](std::int64_t d, int)
    {
      float* out = r.sorted.data() + static_cast<size_t>(d) * b.size();
      for (size_t j = 0; j < b.size(); ++j)
        out[j] = static_cast<float>(project(r.directions[static_cast<size_t>(d)], b[j]));
      boost::sort::pdqsort_branchless(out, out + b.size());
    });
  return r;
}

template <size_t D>
double slicedWassersteinPooled(const std::vector<std::array<float, D>>& a,
  const SortedProjections<D>& b, int directions, std::mt19937_64& rng,
  std::vector<std::array<float, D>>* gradient, int threads)
{
  if (a.empty() || b.count == 0 || directions < 1)
    throw Error("slicedWasserstein needs two non-empty sets and at least one direction");
  if (b.directions.empty() || b.sorted.size() != b.directions.size() * b.count)
    throw Error("slicedWasserstein: the pooled projections hold no directions or not count per "
                "direction");
  // `directions` distinct ones of the pool (a partial shuffle), or all of them
  std::vector<size_t> pick(b.directions.size());
  std::iota(pick.begin(), pick.end(), size_t(0));
  const size_t k = std::min(pick.size(), static_cast<size_t>(directions));
  for (size_t i = 0; i < k; ++i)
    std::swap(
      pick[i], pick[i + std::uniform_int_distribution<size_t>(0, pick.size() - 1 - i)(rng)]);
  std::vector<const std::array<double, D>*> dirs;
  for (size_t i = 0; i < k; ++i)
    dirs.push_back(&b.directions[pick[i]]);
  return slicedWassersteinAlong<D>(
    a, b.count, dirs,
    [&](size_t d, std::vector<double>&) -> const float*
    { return b.sorted.data() + pick[d] * b.count; },
    gradient, threads);
}
} // namespace

double slicedWasserstein(const std::vector<std::array<float, 3>>& a,
  const std::vector<std::array<float, 3>>& b, int directions, std::mt19937_64& rng,
  std::vector<std::array<float, 3>>* gradient, int threads)
{
  return slicedWassersteinOf<3>(a, b, directions, rng, gradient, threads);
}

double slicedWasserstein(const std::vector<std::array<float, 2>>& a,
  const std::vector<std::array<float, 2>>& b, int directions, std::mt19937_64& rng,
  std::vector<std::array<float, 2>>* gradient, int threads)
{
  return slicedWassersteinOf<2>(a, b, directions, rng, gradient, threads);
}

SortedProjections<3> sortedProjections(
  const std::vector<std::array<float, 3>>& b, int pool, std::mt19937_64& rng, int threads)
{
  return sortedProjectionsOf<3>(b, pool, rng, threads);
}

SortedProjections<2> sortedProjections(
  const std::vector<std::array<float, 2>>& b, int pool, std::mt19937_64& rng, int threads)
{
  return sortedProjectionsOf<2>(b, pool, rng, threads);
}

double slicedWasserstein(const std::vector<std::array<float, 3>>& a, const SortedProjections<3>& b,
  int directions, std::mt19937_64& rng, std::vector<std::array<float, 3>>* gradient, int threads)
{
  return slicedWassersteinPooled<3>(a, b, directions, rng, gradient, threads);
}

double slicedWasserstein(const std::vector<std::array<float, 2>>& a, const SortedProjections<2>& b,
  int directions, std::mt19937_64& rng, std::vector<std::array<float, 2>>* gradient, int threads)
{
  return slicedWassersteinPooled<2>(a, b, directions, rng, gradient, threads);
}

} // namespace ddg
