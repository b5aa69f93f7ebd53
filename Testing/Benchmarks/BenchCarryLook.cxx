// BenchCarryLook.cxx: where the carried look's time goes. Its fit compares colour distributions
// by sliced Wasserstein distance (Core's slicedWasserstein): per step, view and direction the
// picture's projections (up to 16 384 colours) were sorted, which had taken about 60 % of the
// carried look's time. Prints, side by side in one run, the sort of a real picture's projections
// with std::sort and with Boost's pattern-defeating quicksort (pdqsort_branchless, what
// slicedWasserstein uses; sorted values are the same whichever sort); one call of the distance
// with fresh directions (the picture sorted in the call) and with directions drawn from the
// picture's pooled projections (sorted once: SortedProjections); then the carried look of
// Engine's shipped screenshot onto Tooth (Core's carryLook, 2 threads) with fresh directions
// (directionPool 0) and with a pool of 512 (the carried look's default). A program that prints
// figures: no timed assertions.
//
//   BenchCarryLook [--repeat N]    (default 5)
#include "DDGVolumeAdaptor.h"

#include "Image/Image.h"
#include "Image/ImageMetrics.h"
#include "Reconstruct/CarryLook.h"
#include "Reconstruct/Reconstruction.h"
#include "Render/DifferentiableRenderer.h"
#include "TransferFunction/ColorSpace.h"

#include <boost/sort/pdqsort/pdqsort.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace ddg;

namespace
{
double seconds(std::chrono::steady_clock::time_point since)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
} // namespace

int main(int argc, char** argv)
{
  int repeat = 5;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--repeat") == 0)
      repeat = std::max(1, std::atoi(argv[i + 1]));
  const std::string data = DDG_DATA_DIR;
  const Image picture = readImage(data + "/Screenshots/engine_block_oblique.png");

  // the picture's CIELAB colours, thinned evenly to 16 384 as the fit thins them
  std::vector<std::array<float, 3>> colours;
  const size_t pixels = static_cast<size_t>(picture.width) * picture.height;
  const size_t step = std::max<size_t>(1, pixels / 16384);
  for (size_t i = 0; i < pixels && colours.size() < 16384; i += step)
  {
    const RGB lab = rgbToLab({ picture.pixels[picture.channels * i],
      picture.pixels[picture.channels * i + 1], picture.pixels[picture.channels * i + 2] });
    colours.push_back({ float(lab[0]), float(lab[1]), float(lab[2]) });
  }
  // 64 directions' projections, sorted by each method (one call of the fit's distance)
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<std::vector<double>> projections(64);
  for (auto& p : projections)
  {
    std::array<double, 3> u{ normal(rng), normal(rng), normal(rng) };
    const double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (const auto& c : colours)
      p.push_back((u[0] * c[0] + u[1] * c[1] + u[2] * c[2]) / len);
  }
  std::vector<double> stdTimes, pdqTimes;
  for (int r = 0; r < repeat; ++r)
  {
    auto a = projections, b = projections;
    auto t = std::chrono::steady_clock::now();
    for (auto& p : a)
      std::sort(p.begin(), p.end());
    stdTimes.push_back(seconds(t));
    t = std::chrono::steady_clock::now();
    for (auto& p : b)
      boost::sort::pdqsort_branchless(p.begin(), p.end());
    pdqTimes.push_back(seconds(t));
  }
  std::printf("sort of 64 x %zu projections of the picture's colours (median of %d):\n",
    colours.size(), repeat);
  std::printf("  std::sort           %.2f ms\n  pdqsort_branchless  %.2f ms  (%.2fx faster)\n",
    1e3 * median(stdTimes), 1e3 * median(pdqTimes), median(stdTimes) / median(pdqTimes));

  // one call of the distance at the fit's sizes (a render's 4 096 colours against the picture's)
  std::vector<std::array<float, 3>> render(colours.begin(), colours.begin() + 4096);
  std::mt19937_64 poolRng(1);
  auto t = std::chrono::steady_clock::now();
  const auto pool = sortedProjections(colours, 512, poolRng, 2);
  const double poolSeconds = seconds(t);
  std::vector<double> swTimes, pooledTimes;
  for (int r = 0; r < repeat; ++r)
  {
    std::vector<std::array<float, 3>> gradient;
    std::mt19937_64 g(1);
    t = std::chrono::steady_clock::now();
    slicedWasserstein(render, colours, 64, g, &gradient, 2);
    swTimes.push_back(seconds(t));
    t = std::chrono::steady_clock::now();
    slicedWasserstein(render, pool, 64, g, &gradient, 2);
    pooledTimes.push_back(seconds(t));
  }
  std::printf(
    "slicedWasserstein with its gradient, 4 096 against %zu colours, 64 directions, 2 "
    "threads (median of %d):\n  fresh directions     %.2f ms a call\n  from a pool of 512 "
    "  %.2f ms a call  (%.2fx faster; the pool sorted once in %.1f ms)\n",
    colours.size(), repeat, 1e3 * median(swTimes), 1e3 * median(pooledTimes),
    median(swTimes) / median(pooledTimes), 1e3 * poolSeconds);

  // the whole carried look, fresh directions and pooled, side by side
  const Volume volume = readVolumeFile(data + "/Volumes/tooth.vti");
  const DifferentiableRenderer renderer(volume);
  double freshTotal = 0;
  for (const int poolSize : { 0, 512 })
  {
    CarryLookOptions opt;
    opt.fit.render.threads = 2;
    opt.fit.directionPool = poolSize;
    t = std::chrono::steady_clock::now();
    const CarryLookResult result = carryLook(renderer, picture, opt);
    const double total = seconds(t);
    if (poolSize == 0)
    {
      freshTotal = total;
      std::printf("carried look, Engine's screenshot onto Tooth (%d steps, 2 threads), fresh "
                  "directions: %.2f s; the distance's calls at the ratio above (6 a step) ~%.2f s "
                  "of it; final colour distance %.3f\n",
        result.fit.iterations, total, result.fit.iterations * 6 * median(swTimes),
        result.distanceEnd);
    }
    else
      std::printf("carried look, the same, directions from a pool of %d: %.2f s (%.2fx faster); "
                  "final colour distance %.3f\n",
        poolSize, total, freshTotal / total, result.distanceEnd);
  }
  return 0;
}
