// ImageMetrics.cxx: PSNR and Gaussian-window SSIM.
#include "Image/ImageMetrics.h"

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

} // namespace ddg
