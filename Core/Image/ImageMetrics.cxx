// ImageMetrics.cxx: PSNR and Gaussian-window SSIM.
#include "Image/ImageMetrics.h"

#include "TransferFunction/ColorSpace.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

std::vector<double> labHistogram(const Image& img0)
{
  const Image img = toChannels(img0, 3);
  std::vector<double> h(static_cast<size_t>(kBinsL) * kBinsA * kBinsB, 0.0);
  const size_t n = static_cast<size_t>(img.width) * img.height;
  for (size_t i = 0; i < n; ++i)
  {
    const RGB lab = rgbToLab({ std::clamp<double>(img.pixels[3 * i], 0, 1),
      std::clamp<double>(img.pixels[3 * i + 1], 0, 1),
      std::clamp<double>(img.pixels[3 * i + 2], 0, 1) });
    const int l = binOf(lab[0], kL, kBinsL), a = binOf(lab[1], kA, kBinsA),
              b = binOf(lab[2], kB, kBinsB);
    h[(static_cast<size_t>(l) * kBinsA + a) * kBinsB + b] += 1.0 / static_cast<double>(n);
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

// Exact transportation cost between two distributions (equal total mass) with ground cost
// cost[i][j]: successive shortest paths with potentials (Dijkstra on the dense residual graph).
double transport(const std::vector<double>& supply, const std::vector<double>& demand,
  const std::vector<std::vector<double>>& cost)
{
  const size_t n = supply.size(), m = demand.size();
  std::vector<double> left = supply, need = demand;
  std::vector<std::vector<double>> flow(n, std::vector<double>(m, 0.0));
  std::vector<double> potS(n, 0.0), potD(m, 0.0); // potentials of supply and demand nodes
  constexpr double eps = 1e-12;
  const double inf = std::numeric_limits<double>::infinity();
  double total = 0;
  for (int guard = 0; guard < static_cast<int>(4 * (n + m) + 100); ++guard)
  {
    double remaining = 0;
    for (double v : left)
      remaining += v;
    if (remaining <= 1e-9)
    {
      break;
    }
    // Dijkstra from the virtual source (to every supply node with mass left, cost 0).
    std::vector<double> distS(n, inf), distD(m, inf);
    std::vector<int> prevS(n, -1),
      prevD(m, -1); // prevD[j] = supply i; prevS[i] = demand j (backward arc)
    std::vector<char> doneS(n, 0), doneD(m, 0);
    for (size_t i = 0; i < n; ++i)
      if (left[i] > eps)
        distS[i] = 0;
    while (true)
    {
      double best = inf;
      int which = -1;
      bool isSupply = true;
      for (size_t i = 0; i < n; ++i)
        if (!doneS[i] && distS[i] < best)
        {
          best = distS[i];
          which = static_cast<int>(i);
          isSupply = true;
        }
      for (size_t j = 0; j < m; ++j)
        if (!doneD[j] && distD[j] < best)
        {
          best = distD[j];
          which = static_cast<int>(j);
          isSupply = false;
        }
      if (which < 0)
        break;
      if (isSupply)
      {
        doneS[which] = 1;
        for (size_t j = 0; j < m; ++j)
        {
          const double r = cost[which][j] + potS[which] - potD[j];
          if (!doneD[j] && distS[which] + r < distD[j])
          {
            distD[j] = distS[which] + r;
            prevD[j] = which;
          }
        }
      }
      else
      {
        doneD[which] = 1;
        for (size_t i = 0; i < n; ++i)
        {
          if (flow[i][which] <= eps)
            continue;
          const double r = -cost[i][which] + potD[which] - potS[i];
          if (!doneS[i] && distD[which] + r < distS[i])
          {
            distS[i] = distD[which] + r;
            prevS[i] = which;
          }
        }
      }
    }
    // nearest demand node with unmet demand
    int sink = -1;
    for (size_t j = 0; j < m; ++j)
      if (need[j] > eps && distD[j] < inf && (sink < 0 || distD[j] < distD[sink]))
        sink = static_cast<int>(j);
    if (sink < 0)
      break;
    for (size_t i = 0; i < n; ++i)
      if (distS[i] < inf)
        potS[i] += distS[i];
    for (size_t j = 0; j < m; ++j)
      if (distD[j] < inf)
        potD[j] += distD[j];
    // bottleneck along the path sink <- i <- j <- i ... <- source supply
    double amount = need[sink];
    int j = sink;
    while (true)
    {
      const int i = prevD[j];
      if (prevS[i] < 0)
      {
        amount = std::min(amount, left[i]);
        break;
      }
      amount = std::min(amount, flow[i][prevS[i]]);
      j = prevS[i];
    }
    j = sink;
    need[sink] -= amount;
    while (true)
    {
      const int i = prevD[j];
      flow[i][j] += amount;
      total += amount * cost[i][j];
      if (prevS[i] < 0)
      {
        left[i] -= amount;
        break;
      }
      flow[i][prevS[i]] -= amount;
      total -= amount * cost[i][prevS[i]];
      j = prevS[i];
    }
  }
  return total;
}

} // namespace

double colorHistogramEMD(const Image& a, const Image& b)
{
  if (a.empty() || b.empty())
  {
    throw Error("cannot compare empty images");
  }
  const auto ha = labHistogram(a), hb = labHistogram(b);
  std::vector<size_t> ia, ib;
  std::vector<double> sa, sb;
  for (size_t i = 0; i < ha.size(); ++i)
  {
    if (ha[i] > 0)
    {
      ia.push_back(i);
      sa.push_back(ha[i]);
    }
    if (hb[i] > 0)
    {
      ib.push_back(i);
      sb.push_back(hb[i]);
    }
  }
  std::vector<std::vector<double>> cost(ia.size(), std::vector<double>(ib.size()));
  for (size_t i = 0; i < ia.size(); ++i)
  {
    const auto ci = binCentre(ia[i]);
    for (size_t j = 0; j < ib.size(); ++j)
    {
      const auto cj = binCentre(ib[j]);
      cost[i][j] = std::sqrt((ci[0] - cj[0]) * (ci[0] - cj[0]) + (ci[1] - cj[1]) * (ci[1] - cj[1]) +
        (ci[2] - cj[2]) * (ci[2] - cj[2]));
    }
  }
  return transport(sa, sb, cost);
}

} // namespace ddg
