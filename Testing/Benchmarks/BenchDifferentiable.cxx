// BenchDifferentiable.cxx: cost of the analytic adjoint and of reconstruction.
//  (a) backward time / forward time of DifferentiableRenderer at 256 x 256 on Engine (all pixels,
//      median of N runs), next to RayCaster's forward time for scale; --shade: also lit, with
//      the lit / unlit ratios, and the backward pass of 8 192 random lit rays (a training
//      step's image loss) with the light sums the forward pass kept against relighting;
//  (c) time to reach 40 dB in the self-consistency case (random Gaussian-primitive TF rendered
//      at one view, reconstructed from that image alone) at 256 x 256, on Tooth and Engine:
//      optimisation time only (the PSNR checks every 10 steps are not counted).
//  --memory prints the time and working memory of one forward + backward pass without early
//  termination (for the comparison with the PyTorch autograd version, bench_torch_autograd.py).
// Prints figures; asserts nothing.
#include "DDGVolumeAdaptor.h"
#include "SelfConsistencyCase.h"

#include "Common/Parallel.h"
#include "Image/ImageMetrics.h"
#include "Reconstruct/Reconstruction.h"
#include "TransferFunction/GaussianPrimitive.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

using namespace ddg;
namespace
{
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void timeToQuality(
  const std::string& name, unsigned seed, int size, const ReconstructionOptions& base)
{
  const Volume vol = readVolumeFile(std::string(DDG_DATA_DIR) + "/Volumes/" + name + ".vti");
  const DifferentiableRenderer renderer(vol);
  View view = readView(std::string(DDG_DATA_DIR) + "/Views/" + name + "_oblique.json");
  view.width = view.height = size;
  const auto range = vol.range();
  const Image truth = renderer.caster().render(
    rasterize1D(testcase::randomPrimitives(seed), range[0], range[1], 256), view);
  const Image target = testcase::straightAlpha(truth);
  const Image truthRGB = compositeOverBackground(truth, view.background);
  ReconstructionOptions opt = base;
  opt.snapshotEvery = 10;
  double evalMs = 0, reached = -1;
  int reachedStep = -1;
  double lastDb = 0;
  const auto t0 = Clock::now();
  const auto result = reconstructTransferFunction(renderer, { { target, view, {} } }, opt,
    [&](int step, double, const ReconstructionResult* snap)
    {
      if (!snap || reached >= 0)
        return true;
      const auto e0 = Clock::now();
      lastDb =
        psnr(compositeOverBackground(renderResult(renderer.caster(), *snap, view), view.background),
          truthRGB);
      evalMs += since(e0);
      if (lastDb >= 40.0)
      {
        reached = since(t0) - evalMs;
        reachedStep = step + 1;
      }
      return true;
    });
  const double finalDb =
    psnr(compositeOverBackground(renderResult(renderer.caster(), result, view), view.background),
      truthRGB);
  if (reached >= 0)
    std::printf("(c) %-7s %dx%d: 40 dB reached after %d steps in %.2f s (optimisation only); final "
                "%.2f dB after %d steps, %.2f s\n",
      name.c_str(), size, size, reachedStep, reached / 1000, finalDb, result.iterations,
      result.seconds - evalMs / 1000);
  else
    std::printf("(c) %-7s %dx%d: 40 dB NOT reached (final %.2f dB after %d steps)\n", name.c_str(),
      size, size, finalDb, result.iterations);
}
} // namespace

int main(int argc, char** argv)
{
  int size = 256, runs = 5;
  ReconstructionOptions ropt;
  bool memoryOnly = false, timingOnly = false, shade = false;
  double samplesPerVoxel = 2; // ParaView's rule: sample distance = mean spacing / 2
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h")
    {
      std::printf(
        "BenchDifferentiable [--size N] [--runs N] [--memory] [--rays N] [--lr X] [--bins N]\n"
        "                    [--samples-per-voxel S] [--timing-only] [--shade]\n"
        "(a) backward/forward time on Engine, (c) time to 40 dB on Tooth and Engine\n"
        "(not with --timing-only). Sample distance = mean spacing / S (2: ParaView's rule).\n"
        "--memory: time and working memory of one forward + backward on Engine.\n"
        "--shade: (a) also with Shade on (ParaView's default coefficients) and the lit / unlit\n"
        "ratios of forward, backward and both, measured in the same run.\n");
      return 0;
    }
    if (a == "--size" && i + 1 < argc)
      size = std::stoi(argv[++i]);
    else if (a == "--runs" && i + 1 < argc)
      runs = std::max(3, std::stoi(argv[++i]));
    else if (a == "--memory")
      memoryOnly = true;
    else if (a == "--timing-only")
      timingOnly = true;
    else if (a == "--shade")
      shade = true;
    else if (a == "--samples-per-voxel" && i + 1 < argc)
      samplesPerVoxel = std::stod(argv[++i]);
    else if (a == "--rays" && i + 1 < argc)
      ropt.raysPerIteration = std::stoi(argv[++i]);
    else if (a == "--lr" && i + 1 < argc)
      ropt.learningRate = std::stod(argv[++i]);
    else if (a == "--bins" && i + 1 < argc)
      ropt.bins = std::stoi(argv[++i]);
    else
    {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const Volume engine = readVolumeFile(std::string(DDG_DATA_DIR) + "/Volumes/engine.vti");
  const DifferentiableRenderer renderer(engine);
  View view = readView(std::string(DDG_DATA_DIR) + "/Views/engine_oblique.json");
  view.width = view.height = size;
  const TransferTable1D table = renderer.caster().paraviewTable(
    readPreset(std::string(DDG_DATA_DIR) + "/TransferFunctions/engine_block.json"));
  if (!(samplesPerVoxel > 0))
  {
    std::fprintf(stderr, "--samples-per-voxel must be positive\n");
    return 2;
  }
  RenderOptions opt;
  opt.sampleDistance = renderer.caster().defaultSampleDistance() * 2.0 / samplesPerVoxel;
  std::vector<float> rgba, dTable(table.rgba.size()), dRGBA;
  std::vector<RayRecord> records;
  if (memoryOnly)
  {
    opt.terminationOpacity = 2.0; // same samples as the autograd version (no early termination)
    renderer.forward(
      table.rgba.data(), table.width, table.min, table.max, view, opt, {}, rgba, records);
    dRGBA.assign(rgba.size(), 1.0f);
    renderer.backward(
      table.rgba.data(), table.width, table.min, table.max, view, opt, {}, records, dRGBA, dTable);
    std::fill(dTable.begin(), dTable.end(), 0.0f); // backward accumulates: start from zero
    const auto t0 = Clock::now();
    renderer.forward(
      table.rgba.data(), table.width, table.min, table.max, view, opt, {}, rgba, records);
    renderer.backward(
      table.rgba.data(), table.width, table.min, table.max, view, opt, {}, records, dRGBA, dTable);
    const double ms = since(t0);
    // Working memory of the pass, counted exactly: per pixel the output, its gradient and the
    // ray record with the sample values it keeps (at most kRecordBudget floats in all); per
    // thread one gradient table; the prepared table.
    const int threads = ddg::defaultThreadCount();
    double kept = 0;
    for (const auto& r : records)
      kept += static_cast<double>(r.samples.capacity()) * sizeof(float);
    const double bytes = static_cast<double>(rgba.size()) * sizeof(float) * 2 +
      records.size() * sizeof(RayRecord) + kept +
      (threads + 2.0) * table.rgba.size() * sizeof(float);
    std::printf("ours: forward+backward %.1f ms, working memory %.2f MB (engine %dx%d, no early "
                "termination)\n",
      ms, bytes / (1024.0 * 1024.0), size, size);
    double sum = 0;
    for (float g : dTable)
      sum += g;
    std::printf("ours: sum of dL/dTable %.6g (L = sum of premultiplied RGBA)\n", sum);
    return 0;
  }
  // (a) forward, backward and the ray caster's forward at `v`, medians of `runs` (after one
  // unmeasured run, which also computes the lit gradients once)
  auto timeAt = [&](const View& v, double& f, double& b, double& q)
  {
    std::vector<double> fwd, bwd, fast;
    for (int r = 0; r < runs + 1; ++r)
    {
      auto t0 = Clock::now();
      renderer.forward(
        table.rgba.data(), table.width, table.min, table.max, v, opt, {}, rgba, records);
      const double tf = since(t0);
      dRGBA.assign(rgba.size(), 1.0f);
      t0 = Clock::now();
      renderer.backward(
        table.rgba.data(), table.width, table.min, table.max, v, opt, {}, records, dRGBA, dTable);
      const double tb = since(t0);
      t0 = Clock::now();
      renderer.caster().render(table, v, opt);
      const double tq = since(t0);
      if (r > 0)
      {
        fwd.push_back(tf);
        bwd.push_back(tb);
        fast.push_back(tq);
      }
    }
    f = median(fwd);
    b = median(bwd);
    q = median(fast);
  };
  double f = 0, b = 0, q = 0;
  timeAt(view, f, b, q);
  std::printf("(a) engine %dx%d, engine_block, median of %d: forward %.1f ms, backward %.1f ms, "
              "backward/forward %.2f (RayCaster forward with skipping %.1f ms)\n",
    size, size, runs, f, b, b / f, q);
  if (shade)
  {
    View lit = view;
    lit.lighting = Lighting{};
    lit.lighting.shade = true;
    double fl = 0, bl = 0, ql = 0;
    timeAt(lit, fl, bl, ql);
    std::printf(
      "(a) Shade on (ParaView's default coefficients): forward %.1f ms, backward %.1f ms, "
      "backward/forward %.2f (RayCaster %.1f ms)\n"
      "    lit / unlit, same samples: forward %.2fx, backward %.2fx, forward + backward "
      "%.2fx, RayCaster %.2fx\n",
      fl, bl, bl / fl, ql, fl / f, bl / b, (fl + bl) / (f + b), ql / q);
    // A training step's image loss: 16 exemplars x 512 random rays. The backward pass with the
    // light sums the forward pass kept, against the same records holding the values alone
    // (the backward pass then lights every sample again, as it did before it kept them).
    std::vector<int> pixels(16 * 512);
    std::mt19937 pick(7);
    for (int& p : pixels)
      p = static_cast<int>(pick() % static_cast<unsigned>(lit.width * lit.height));
    std::vector<double> kept, relit;
    for (int r = 0; r < runs + 1; ++r)
    {
      renderer.forward(
        table.rgba.data(), table.width, table.min, table.max, lit, opt, pixels, rgba, records);
      dRGBA.assign(rgba.size(), 1.0f);
      auto t0 = Clock::now();
      renderer.backward(table.rgba.data(), table.width, table.min, table.max, lit, opt, pixels,
        records, dRGBA, dTable);
      const double tk = since(t0);
      for (auto& rec : records) // values only: every (1 + kLightFloats)-th float
      {
        for (size_t i = 0; i * (1 + kLightFloats) < rec.samples.size(); ++i)
          rec.samples[i] = rec.samples[i * (1 + kLightFloats)];
        rec.samples.resize(rec.samples.size() / (1 + kLightFloats));
      }
      t0 = Clock::now();
      renderer.backward(table.rgba.data(), table.width, table.min, table.max, lit, opt, pixels,
        records, dRGBA, dTable);
      if (r > 0)
      {
        kept.push_back(tk);
        relit.push_back(since(t0));
      }
    }
    std::printf("(a) Shade on, 8192 random rays (a training step's image loss), median of %d: "
                "backward with the kept light sums %.2f ms, relighting %.2f ms (%.2fx)\n",
      runs, median(kept), median(relit), median(relit) / median(kept));
  }
  if (timingOnly)
    return 0;
  timeToQuality("tooth", 11, size, ropt);
  timeToQuality("engine", 12, size, ropt);
  return 0;
}
