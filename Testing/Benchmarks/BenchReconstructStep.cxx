// BenchReconstructStep.cxx: where one step of TF reconstruction from a screenshot spends its time.
//
// Emulates the reconstruction step of Core/Reconstruct (the default options: 2048 random rays of
// the view, sorted, 1D table of ParaView's width for 128 bins, or --2d) on a real case: the
// DifferentiableRenderer's forward pass, the L1 loss and its gradient, the backward pass; each
// phase timed per step (median over --steps steps, after one warm-up step), with the samples
// marched per second per thread. Then the whole reconstructTransferFunction for --steps steps
// (no early stop), whose time per step minus forward and backward is the rest (loss, prior,
// parameterisation, Adam). Prints figures; asserts nothing.
//
// Usage: BenchReconstructStep --volume V.vti --target screenshot.png --view view.json
//          [--tf preset.json] [--rays 2048] [--bins 128] [--2d] [--threads 2] [--steps 60]
// --tf renders with that TF (e.g. the case's true TF, as at the end of a reconstruction)
// instead of the reconstruction's start (grey, opacity 0.02).
#include "DDGVolumeAdaptor.h"

#include "Image/Image.h"
#include "Reconstruct/Reconstruction.h"
#include "Render/DifferentiableRenderer.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <time.h>

using namespace ddg;
namespace
{
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
// CPU time of the whole process (all threads) in ms: less sensitive than wall time to other
// programs sharing the cores.
double cpuMs()
{
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}
} // namespace

int main(int argc, char** argv)
{
  std::string volumePath, targetPath, viewPath, tfPath;
  int rays = 2048, bins = 128, threads = 2, steps = 60;
  bool twoD = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--volume")
      volumePath = next();
    else if (a == "--target")
      targetPath = next();
    else if (a == "--view")
      viewPath = next();
    else if (a == "--tf")
      tfPath = next();
    else if (a == "--rays")
      rays = std::stoi(next());
    else if (a == "--bins")
      bins = std::stoi(next());
    else if (a == "--threads")
      threads = std::stoi(next());
    else if (a == "--steps")
      steps = std::max(3, std::stoi(next()));
    else if (a == "--2d")
      twoD = true;
    else
    {
      std::fprintf(stderr,
        "usage: BenchReconstructStep --volume V --target IMG --view J [--tf preset.json] "
        "[--rays N] [--bins N] [--2d] [--threads N] [--steps N]\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (volumePath.empty() || targetPath.empty() || viewPath.empty())
  {
    std::fprintf(stderr, "--volume, --target and --view are required\n");
    return 2;
  }
  auto t0 = Clock::now();
  const Volume vol = readVolumeFile(volumePath);
  const double tRead = since(t0);
  t0 = Clock::now();
  const DifferentiableRenderer renderer(vol);
  const double tPrepare = since(t0);
  const View view = readView(viewPath);
  const Image target = readImage(targetPath);
  const auto range = vol.range();
  const int gradientBins = 32;

  // The table of the step: ParaView's width for `bins` nodes (1D), or bins x 32 (2D).
  std::vector<float> table;
  int width = bins, height = gradientBins;
  std::array<double, 2> gradientRange{ 0, 1 };
  if (!twoD)
  {
    TransferFunction1D probe;
    probe.color = { { range[0], 0, 0, 0 },
      { range[0] + (range[1] - range[0]) / (bins - 1), 0, 0, 0 } };
    probe.opacity = { { range[0], 0 } };
    width = paraviewTableWidth(probe, range[0], range[1]);
    if (!tfPath.empty())
    {
      table = bakeTable(readPreset(tfPath), range[0], range[1], width).rgba;
    }
    else
    {
      table.assign(4 * static_cast<size_t>(width), 0.5f);
      for (int i = 0; i < width; ++i)
        table[4 * i + 3] = 0.02f;
    }
  }
  else
  {
    const auto g = vol.gradientMagnitude();
    gradientRange = { 0.0, static_cast<double>(*std::max_element(g.begin(), g.end())) };
    table.assign(4 * static_cast<size_t>(width) * height, 0.5f);
    for (size_t i = 0; i < table.size() / 4; ++i)
      table[4 * i + 3] = 0.02f;
  }

  RenderOptions opt;
  opt.threads = threads;
  std::mt19937 rng(1);
  std::vector<int> all(static_cast<size_t>(view.width) * view.height);
  for (size_t i = 0; i < all.size(); ++i)
    all[i] = static_cast<int>(i);
  std::vector<int> pixels;
  std::vector<float> rgba, dRGBA, dTable(table.size());
  std::vector<RayRecord> records;
  std::vector<double> fwd, loss, bwd, samplesPerStep, fwdCpu, bwdCpu, fwdWarm;
  for (int step = 0; step <= steps; ++step)
  {
    std::shuffle(all.begin(), all.end(), rng);
    pixels.assign(all.begin(), all.begin() + std::min<size_t>(all.size(), rays));
    std::sort(pixels.begin(), pixels.end());
    auto t = Clock::now();
    double c = cpuMs();
    if (twoD)
      renderer.forward2D(
        table.data(), width, height, range, gradientRange, view, opt, pixels, rgba, records);
    else
      renderer.forward(table.data(), width, range[0], range[1], view, opt, pixels, rgba, records);
    const double f = since(t), fc = cpuMs() - c;
    // The same rays again: the cells they read are now in cache.
    c = cpuMs();
    if (twoD)
      renderer.forward2D(
        table.data(), width, height, range, gradientRange, view, opt, pixels, rgba, records);
    else
      renderer.forward(table.data(), width, range[0], range[1], view, opt, pixels, rgba, records);
    const double fw = cpuMs() - c;
    t = Clock::now();
    dRGBA.assign(rgba.size(), 0.0f);
    for (size_t q = 0; q < pixels.size(); ++q)
    {
      const int y = pixels[q] / view.width, x = pixels[q] % view.width;
      const float a = rgba[4 * q + 3];
      for (int c = 0; c < 3; ++c)
      {
        const float over = rgba[4 * q + c] + (1 - a) * static_cast<float>(view.background[c]);
        const float d = over - target.at(x, y, c);
        dRGBA[4 * q + c] = d > 0 ? 1.0f : -1.0f;
        dRGBA[4 * q + 3] -= (d > 0 ? 1.0f : -1.0f) * static_cast<float>(view.background[c]);
      }
    }
    const double l = since(t);
    std::fill(dTable.begin(), dTable.end(), 0.0f);
    t = Clock::now();
    c = cpuMs();
    if (twoD)
      renderer.backward2D(table.data(), width, height, range, gradientRange, view, opt, pixels,
        records, dRGBA, dTable);
    else
      renderer.backward(
        table.data(), width, range[0], range[1], view, opt, pixels, records, dRGBA, dTable);
    const double b = since(t), bc = cpuMs() - c;
    double samples = 0;
    for (const auto& r : records)
      samples += r.lastSample + 1;
    if (step > 0)
    {
      fwd.push_back(f);
      loss.push_back(l);
      bwd.push_back(b);
      samplesPerStep.push_back(samples);
      fwdCpu.push_back(fc);
      fwdWarm.push_back(fw);
      bwdCpu.push_back(bc);
    }
  }
  // Checksums of the last step's image and gradient: equal between builds that compute the same.
  double sumRGBA = 0, sumGrad = 0;
  for (float x : rgba)
    sumRGBA += x;
  for (float x : dTable)
    sumGrad += std::abs(x);
  const double mf = median(fwd), mb = median(bwd), ml = median(loss);
  const double ms = median(samplesPerStep);
  std::printf("case %s %s, %dx%d, %d rays/step, %s table %dx%d, %d threads; read %.0f ms, "
              "prepare %.0f ms\n",
    targetPath.c_str(), twoD ? "2D" : "1D", view.width, view.height, rays, twoD ? "2D" : "1D",
    width, twoD ? height : 1, threads, tRead, tPrepare);
  std::printf("  samples/step %.0f (%.0f per ray); checksums: image %.9g, |gradient| %.9g\n", ms,
    ms / rays, sumRGBA, sumGrad);
  const double cf = median(fwdCpu), cb = median(bwdCpu);
  std::printf("  forward  %7.2f ms/step wall, %7.2f ms CPU: %6.1f M samples/s per CPU second\n", mf,
    cf, ms / (cf * 1e3));
  std::printf("  (forward again on the same rays, cells in cache: %.2f ms CPU)\n", median(fwdWarm));
  std::printf("  loss     %7.2f ms/step\n", ml);
  std::printf("  backward %7.2f ms/step wall, %7.2f ms CPU: %6.1f M samples/s per CPU second "
              "(backward/forward %.2f CPU)\n",
    mb, cb, ms / (cb * 1e3), cb / cf);

  // The whole optimisation for `steps` steps (no early stop): time per step.
  ReconstructionOptions ropt;
  ropt.twoD = twoD;
  ropt.bins = bins;
  ropt.iterations = steps;
  ropt.patience = steps + 1;
  ropt.raysPerIteration = rays;
  ropt.render.threads = threads;
  ReconstructionTarget rt(target, view);
  if (rt.image.channels == 4)
  {
    // a screenshot: opaque RGB
    Image rgb(target.width, target.height, 3, 0.0f);
    for (int y = 0; y < target.height; ++y)
      for (int x = 0; x < target.width; ++x)
        for (int c = 0; c < 3; ++c)
          rgb.at(x, y, c) = target.at(x, y, c);
    rt.image = rgb;
  }
  const auto result = reconstructTransferFunction(renderer, { rt }, ropt);
  const double perStep = result.seconds * 1e3 / result.iterations;
  std::printf("  reconstruction: %.2f ms/step over %d steps; rest (loss, prior, Adam, tables) "
              "%.2f ms/step = %.0f %%\n",
    perStep, result.iterations, perStep - mf - mb, 100.0 * (perStep - mf - mb) / perStep);
  std::printf("  breakdown: forward %.0f %%, backward %.0f %%, rest %.0f %%\n",
    100.0 * mf / perStep, 100.0 * mb / perStep, 100.0 * (perStep - mf - mb) / perStep);
  return 0;
}
