// BuildPlan.cxx: budget -> build sizes, stage estimates from a timed probe, input checks.
#include "Gallery/BuildPlan.h"

#include "Common/Error.h"
#include "Common/Parallel.h"
#include "Design/DesignSpace.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/QueryImage.h"
#include "Gallery/QueryKey.h"
#include "Image/ImageMetrics.h"
#include "Neural/NeuralDesignModel.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <system_error>

#ifndef _WIN32
#include <unistd.h>
#endif

namespace ddg
{

namespace fs = std::filesystem;

namespace
{
// Costs not probed: a held-out figure's decoder render at V_view is one render; the evaluation
// also times the analyzer and the renderer 21 times; fixed costs (libtorch's model, reading
// the datasets, saving the bundle) ~4 s.
constexpr int kLatencySamples = 21;
constexpr double kOverheadSeconds = 4;
std::int64_t exemplarBytes(int size)
{
  // shard: RGB + 2 x RGBA; dataset.json: ~700 characters per exemplar
  return static_cast<std::int64_t>(size) * size * 11 + 700;
}

std::string minutesText(double seconds)
{
  char buf[32];
  if (seconds < 60)
    std::snprintf(buf, sizeof(buf), "%.0f s", std::max(1.0, seconds));
  else
    std::snprintf(buf, sizeof(buf), "%.1f min", seconds / 60);
  return buf;
}

std::string bytesText(std::int64_t bytes)
{
  char buf[32];
  if (bytes < 1024 * 1024)
    std::snprintf(buf, sizeof(buf), "%.0f KB", bytes / 1024.0);
  else if (bytes < 1024ll * 1024 * 1024)
    std::snprintf(buf, sizeof(buf), "%.0f MB", bytes / (1024.0 * 1024));
  else
    std::snprintf(buf, sizeof(buf), "%.1f GB", bytes / (1024.0 * 1024 * 1024));
  return buf;
}
} // namespace

// --- the plan ------------------------------------------------------------------------------------

std::string BuildPlan::toJson() const
{
  char buf[1024];
  std::snprintf(buf, sizeof(buf),
    "{\"budget_minutes\": %.3f, \"count\": %d, \"heldout\": %d, \"outline_count\": %d, "
    "\"size\": %d, \"training_minutes\": %.3f, \"exemplar_seconds\": %.1f, "
    "\"training_seconds\": %.1f, \"evaluation_seconds\": %.1f, \"outline_seconds\": %.1f, "
    "\"total_seconds\": %.1f, \"disk_bytes\": %lld, \"bundle_bytes\": %lld, "
    "\"design_dims\": [%d, %d, %d], \"downsample\": %d, \"exemplar_ms\": %.3f, "
    "\"analyze_ms\": %.3f, \"figure_ms\": %.3f, \"framed_ms\": %.3f, \"key_fit_us\": %.3f, "
    "\"threads\": %d}",
    budgetMinutes, count, heldout, outlineCount, size, trainingMinutes, exemplarSeconds,
    trainingSeconds, evaluationSeconds, outlineSeconds, totalSeconds,
    static_cast<long long>(diskBytes), static_cast<long long>(bundleBytes), designDims[0],
    designDims[1], designDims[2], downsample, 1000 * rates.exemplarSeconds,
    1000 * rates.analyzeSeconds, 1000 * rates.figureSeconds, 1000 * rates.framedSeconds,
    1e6 * rates.keyFitSeconds, rates.threads);
  return buf;
}

double BuildPlan::trainingMinutesAfter(double elapsedSeconds) const
{
  const double end = totalSeconds - evaluationSeconds - outlineSeconds;
  return std::max(0.5 * trainingMinutes, (end - elapsedSeconds) / 60);
}

std::string BuildPlan::describe() const
{
  std::string s;
  s += "exemplars: " + std::to_string(count) + " + " + std::to_string(heldout) + " held out, " +
    minutesText(exemplarSeconds) + "\n";
  s += "training: " + minutesText(trainingSeconds) + "\n";
  s += "evaluation and saving: " + minutesText(evaluationSeconds) + "\n";
  s += "outline: " + std::to_string(outlineCount) + " designs and the query key, " +
    minutesText(outlineSeconds) + "\n";
  s += "total: about " + minutesText(totalSeconds) + "; disk: " + bytesText(diskBytes) +
    " while building, " + bytesText(bundleBytes) + " kept\n";
  if (downsample > 1)
    s += "the volume is downsampled " + std::to_string(downsample) +
      "x per axis for the design "
      "space (" +
      std::to_string(designDims[0]) + "x" + std::to_string(designDims[1]) + "x" +
      std::to_string(designDims[2]) + "); the model stays the original volume's\n";
  return s;
}

BuildRates measureBuildRates(const Volume& volume, int size, int threads, int probes)
{
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t0)
  { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  BuildRates r;
  r.threads = resolveThreadCount(threads, 1 << 20);
  // exemplars: generated as the build does (the feature regions found once, outside the timing)
  DesignSpaceSpec spec;
  spec.regions = findFeatureRegions(volume, spec.maxRegions);
  const fs::path dir = fs::temp_directory_path() /
    ("ddg-build-probe-" +
      std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
  GenerateOptions g;
  g.count = std::max(4, probes);
  g.size = size;
  g.seed = 7919; // not the build's
  g.threads = threads;
  g.viewport = false; // the build trains the decoder
  auto t0 = Clock::now();
  try
  {
    generateExemplars(volume, spec, dir.string(), g);
  }
  catch (...)
  {
    std::error_code ec;
    fs::remove_all(dir, ec);
    throw;
  }
  r.exemplarSeconds = since(t0) / g.count;
  r.renderSeconds = r.exemplarSeconds / 2; // V_exp and V_view
  // a held-out figure's metrics (PSNR, SSIM, colour-histogram EMD) on two probe images
  std::error_code ec;
  try
  {
    const ExemplarDataset probe(dir.string());
    const Image a = compositeOverBackground(probe.images(0).truth, { 0.5, 0.5, 0.5 });
    const Image b = compositeOverBackground(probe.images(1).truth, { 0.5, 0.5, 0.5 });
    t0 = Clock::now();
    for (int i = 0; i < 3; ++i)
      (void)(psnr(a, b) + ssim(a, b) + colorHistogramEMD(a, b));
    r.figureSeconds = since(t0) / 3;
    // the query key's other views: upsampled 3x and framed as a query is (OpenImageIO's resizes
    // use every thread already: the build's threads framing side by side are no faster)
    t0 = Clock::now();
    for (int i = 0; i < 3; ++i)
    {
      try
      {
        (void)prepareQueryImage(resizeImage(a, 3 * size, 3 * size), size);
      }
      catch (const Error&) // a probe in which nothing shows frames as fast as one refused
      {
      }
    }
    r.framedSeconds = since(t0) / 3;
  }
  catch (...)
  {
    fs::remove_all(dir, ec);
    throw;
  }
  fs::remove_all(dir, ec);
  // the analyzer, alone and batched
  NetworkConfig cfg;
  cfg.kind = "decoder";
  cfg.imageSize = size;
  cfg.regions = static_cast<int>(spec.regions.size());
  const NeuralDesignModel model(cfg, 1);
  const std::vector<Image> images(32, Image(size, size, 3));
  model.analyze(images[0]); // warm-up
  t0 = Clock::now();
  for (int i = 0; i < 4; ++i)
    model.analyze(images[0]);
  r.analyzeSeconds = since(t0) / 4;
  t0 = Clock::now();
  model.analyzeBatch(images);
  r.analyzeBatchSeconds = since(t0) / images.size();
  // the contrastive key's training: one epoch over 512 pairs of random latents
  std::mt19937_64 rng(1);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  std::vector<float> own(static_cast<size_t>(512) * cfg.latent), other(own.size());
  for (size_t i = 0; i < own.size(); ++i)
  {
    own[i] = normal(rng);
    other[i] = own[i] + 0.1f * normal(rng);
  }
  ContrastiveKeyOptions fit;
  fit.epochs = 1;
  t0 = Clock::now();
  (void)fitContrastiveQueryKey(own, other, cfg.latent, fit);
  r.keyFitSeconds = since(t0) / 512;
  return r;
}

namespace
{
// The query key's seconds: its pairs framed and analysed twice, and the contrastive key's
// epochs over them.
double queryKeyCost(const BuildRates& rates, int count)
{
  const int pairs = std::min(count, kQueryKeyPairs);
  const double fit =
    pairs >= kContrastiveKeyPairs ? ContrastiveKeyOptions{}.epochs * rates.keyFitSeconds : 0;
  return pairs * (rates.framedSeconds + 2 * rates.analyzeBatchSeconds + fit);
}

// The outline's seconds: the analyzer for every design, a render for those that are not training
// exemplars (all of them when outlineRendered); and the query key.
double outlineCost(const BuildRates& rates, int outline, int count, bool outlineRendered)
{
  const int rendered = outlineRendered ? outline : std::max(0, outline - count);
  return rendered * rates.renderSeconds + outline * rates.analyzeBatchSeconds +
    queryKeyCost(rates, count);
}
} // namespace

BuildPlan estimateBuild(const std::array<int, 3>& designDims, int downsample,
  const BuildRates& rates, int count, int heldout, int outlineCount, int size,
  double trainingMinutes, bool outlineRendered)
{
  BuildPlan p;
  p.count = count;
  p.heldout = heldout;
  p.outlineCount = outlineCount;
  p.size = size;
  p.trainingMinutes = trainingMinutes;
  p.designDims = designDims;
  p.downsample = downsample;
  p.rates = rates;
  const double render1 = rates.renderSeconds * std::max(1, rates.threads); // one thread
  p.exemplarSeconds = (count + heldout) * rates.exemplarSeconds;
  p.trainingSeconds = 60 * trainingMinutes;
  p.evaluationSeconds = heldout * (render1 + 2 * rates.analyzeSeconds + rates.figureSeconds) +
    kLatencySamples * (render1 + rates.analyzeSeconds) + count * rates.analyzeBatchSeconds;
  p.outlineSeconds = outlineCost(rates, outlineCount, count, outlineRendered);
  p.queryKeySeconds = queryKeyCost(rates, count);
  p.totalSeconds = kOverheadSeconds + p.exemplarSeconds + p.trainingSeconds + p.evaluationSeconds +
    p.outlineSeconds;
  // the bundle: weights (~1.4 MB at width 16), training latents (half floats) and TF
  // parameters (exemplars.json, ~300 characters each), the outline (float latents + index)
  p.bundleBytes = 1500000 + static_cast<std::int64_t>(count) * (64 * 2 + 300) +
    static_cast<std::int64_t>(outlineCount) * (64 * 4 + 8);
  p.diskBytes = p.bundleBytes + static_cast<std::int64_t>(count + heldout) * exemplarBytes(size);
  return p;
}

BuildPlan planBuild(const Volume& volume, double budgetMinutes, int size, int threads,
  const BuildRates& measured, std::int64_t maxDesignVoxels, bool outlineRendered)
{
  if (!(budgetMinutes >= 1))
    throw Error(
      "a build needs a budget of at least 1 minute (got " + std::to_string(budgetMinutes) + ")");
  DesignSpaceInput in;
  in.volume = designSpaceVolume(volume, maxDesignVoxels, &in.factor);
  return planBuild(in, budgetMinutes, size, threads, measured, outlineRendered);
}

BuildPlan planBuild(const DesignSpaceInput& input, double budgetMinutes, int size, int threads,
  const BuildRates& measured, bool outlineRendered)
{
  if (!(budgetMinutes >= 1))
    throw Error(
      "a build needs a budget of at least 1 minute (got " + std::to_string(budgetMinutes) + ")");
  const Volume& design = input.volume;
  const int factor = input.factor;
  const BuildRates rates =
    measured.measured() ? measured : measureBuildRates(design, size, threads);
  const double budget = 60 * budgetMinutes;
  const double target = kBuildBudgetShare * budget - kOverheadSeconds;
  const double perOutline = rates.renderSeconds + rates.analyzeBatchSeconds;
  const double perExemplar = rates.exemplarSeconds;
  const double render1 = rates.renderSeconds * std::max(1, rates.threads);
  const double perFigure = render1 + 2 * rates.analyzeSeconds + rates.figureSeconds;
  const double latency = kLatencySamples * (render1 + rates.analyzeSeconds);
  int outline = std::clamp(static_cast<int>(0.10 * target / perOutline), 1000, 10000);
  int count = std::clamp(static_cast<int>(0.25 * target / perExemplar), 256, 30000);
  int heldout = std::clamp(count / 10, 50, 200);
  auto rest = [&]()
  {
    return target - outlineCost(rates, outline, count, outlineRendered) -
      count * (perExemplar + rates.analyzeBatchSeconds) - heldout * (perExemplar + perFigure) -
      latency;
  };
  // a large volume's renders are slow: shrink the exemplars and the outline (to their minima)
  // until training keeps at least 35 % of the budget
  while (rest() < 0.35 * target && (count > 256 || outline > 1000))
  {
    count = std::max(256, static_cast<int>(count * 0.8));
    outline = std::max(1000, static_cast<int>(outline * 0.8));
    heldout = std::clamp(count / 10, 50, 200);
  }
  // held-out figures cost the analyzer alone: fewer of them when it is slow (at least 50)
  while (rest() < 0.35 * target && heldout > 50)
    heldout = std::max(50, heldout * 4 / 5);
  const double training = std::max(0.1 * target, rest());
  BuildPlan p = estimateBuild(
    design.dims(), factor, rates, count, heldout, outline, size, training / 60, outlineRendered);
  p.budgetMinutes = budgetMinutes;
  return p;
}

// --- the volume ----------------------------------------------------------------------------------

int designSpaceFactor(const std::array<int, 3>& d, std::int64_t maxVoxels)
{
  int f = 1;
  auto voxels = [&](int g)
  {
    std::int64_t n = 1;
    for (int a = 0; a < 3; ++a)
      n *= (d[a] + g - 1) / g;
    return n;
  };
  while (voxels(f) > std::max<std::int64_t>(1, maxVoxels))
    ++f;
  return f;
}

namespace
{
// The design-space voxels of planes k0 .. k1 - 1 (of `nd`) into `values` (the whole design
// volume's): the average of the finite points `at(a, b, c)` of each f x f x f block of the
// volume `d`, rounded to the type's levels for an integer volume (which keeps its type, and so
// ParaView's normalisation of it: half a step of the data at most). One code for the whole
// volume and for slabs of it, so both give the same bits.
template <typename At>
void averageBlocks(const std::array<int, 3>& d, int f, const std::array<int, 3>& nd, int k0, int k1,
  bool integral, const At& at, std::vector<float>& values)
{
  parallelFor(k1 - k0, 0,
    [&](std::int64_t kk, int)
    {
      const int k = k0 + static_cast<int>(kk);
      for (int j = 0; j < nd[1]; ++j)
        for (int i = 0; i < nd[0]; ++i)
        {
          double sum = 0;
          int n = 0;
          for (int c = k * f; c < std::min(d[2], (k + 1) * f); ++c)
            for (int b = j * f; b < std::min(d[1], (j + 1) * f); ++b)
              for (int a = i * f; a < std::min(d[0], (i + 1) * f); ++a)
              {
                const float v = at(a, b, c);
                if (std::isfinite(v))
                {
                  sum += v;
                  ++n;
                }
              }
          values[(static_cast<size_t>(k) * nd[1] + j) * nd[0] + i] =
            n ? static_cast<float>(integral ? std::round(sum / n) : sum / n) : std::nanf("");
        }
    });
}

bool integralType(ScalarType t)
{
  return t != ScalarType::Float32 && t != ScalarType::Float64;
}

std::array<int, 3> reducedDims(const std::array<int, 3>& d, int f)
{
  return { (d[0] + f - 1) / f, (d[1] + f - 1) / f, (d[2] + f - 1) / f };
}
} // namespace

Volume designSpaceVolume(const Volume& volume, std::int64_t maxVoxels, int* factor)
{
  const auto& d = volume.dims();
  const int f = designSpaceFactor(d, maxVoxels);
  if (factor)
    *factor = f;
  if (f == 1)
    return volume;
  const std::array<int, 3> nd = reducedDims(d, f);
  std::vector<float> values(static_cast<size_t>(nd[0]) * nd[1] * nd[2]);
  averageBlocks(
    d, f, nd, 0, nd[2], integralType(volume.originalType()),
    [&](int a, int b, int c) { return volume.at(a, b, c); }, values);
  const auto& s = volume.spacing();
  return Volume(nd, volume.origin(), { s[0] * f, s[1] * f, s[2] * f }, std::move(values),
    volume.originalType());
}

DesignSpaceInput designSpaceInput(const Volume& volume, std::int64_t maxVoxels)
{
  checkBuildVolume(volume);
  DesignSpaceInput in;
  in.volume = designSpaceVolume(volume, maxVoxels, &in.factor);
  if (in.factor > 1)
    in.fingerprint = volumeFingerprint(volume);
  return in;
}

DesignSpaceAssembler::DesignSpaceAssembler(const std::array<int, 3>& dims,
  const std::array<double, 3>& origin, const std::array<double, 3>& spacing, ScalarType type,
  std::int64_t maxVoxels)
  : Dims(dims)
  , Origin(origin)
  , Spacing(spacing)
  , Type(type)
  , Factor(designSpaceFactor(dims, maxVoxels))
{
}

int DesignSpaceAssembler::slabPlanes(std::int64_t values) const
{
  const std::int64_t plane = static_cast<std::int64_t>(Dims[0]) * Dims[1];
  const std::int64_t blocks = std::max<std::int64_t>(1, values / (plane * Factor));
  return static_cast<int>(std::min<std::int64_t>(blocks * Factor, Dims[2]));
}

void DesignSpaceAssembler::add(int z0, int planes, const float* values)
{
  if (z0 != Next || planes < 1 || z0 + planes > Dims[2] ||
    (z0 + planes < Dims[2] && planes % Factor != 0))
    throw Error("the design-space volume's slabs must come in order, whole blocks of " +
      std::to_string(Factor) + " planes");
  const std::int64_t plane = static_cast<std::int64_t>(Dims[0]) * Dims[1];
  const std::array<int, 3> nd = reducedDims(Dims, Factor);
  if (Values.empty()) // the result, allocated with the first slab
    Values.assign(static_cast<size_t>(nd[0]) * nd[1] * nd[2], 0.0f);
  if (Factor == 1)
    std::copy_n(values, plane * planes, Values.begin() + plane * z0);
  else
  {
    averageBlocks(
      Dims, Factor, nd, z0 / Factor, (z0 + planes + Factor - 1) / Factor, integralType(Type),
      [&](int a, int b, int c)
      { return values[(static_cast<std::int64_t>(c - z0) * Dims[1] + b) * Dims[0] + a]; },
      Values);
  }
  Next = z0 + planes;
}

DesignSpaceInput DesignSpaceAssembler::finish(const std::string& fingerprint)
{
  if (Next != Dims[2])
    throw Error("the design-space volume is missing planes " + std::to_string(Next) + " and on");
  DesignSpaceInput in;
  in.factor = Factor;
  in.fingerprint = fingerprint;
  const std::array<double, 3> s{ Spacing[0] * Factor, Spacing[1] * Factor, Spacing[2] * Factor };
  in.volume = Volume(reducedDims(Dims, Factor), Origin, s, std::move(Values), Type);
  Values = {};
  return in;
}

void checkBuildVolume(const Volume& volume)
{
  if (volume.empty())
    throw Error("the volume has no values");
  checkBuildVolume(volume.dims(), volume.range());
}

void checkBuildVolume(const std::array<int, 3>& d, const std::array<double, 2>& r)
{
  if (std::min({ d[0], d[1], d[2] }) < 4)
    throw Error("the volume is " + std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" +
      std::to_string(d[2]) +
      " voxels: a design space needs at least 4 voxels along each axis "
      "(this is a slice or a thin slab; volume rendering shows nothing of it)");
  if (!(r[1] > r[0]))
  {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%g", r[0]);
    throw Error(std::string("the volume has one value (") + buf +
      ") everywhere: there are no features to design transfer functions for");
  }
}

// --- the output folder ---------------------------------------------------------------------------

void checkBuildOutput(const std::string& bundleDir, std::int64_t diskBytes, bool overwrite)
{
  if (bundleDir.empty())
    throw Error("building a design space needs an output bundle directory");
  std::error_code ec;
  const fs::path dir = fs::absolute(bundleDir, ec);
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw Error("'" + bundleDir + "' is a file, not a folder: choose a folder for the bundle");
  if (fs::exists(dir / "bundle.json", ec) && !overwrite)
    throw Error("'" + bundleDir +
      "' already holds a model bundle: choose another folder, or "
      "overwrite it explicitly (--overwrite, Overwrite, overwrite=True)");
  // the folder, or the nearest existing parent it would be created in
  fs::path existing = dir;
  while (
    !fs::exists(existing, ec) && existing.has_parent_path() && existing != existing.parent_path())
    existing = existing.parent_path();
#ifndef _WIN32
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
  {
    const int err = errno;
    throw Error("cannot write in '" + existing.string() + "' (" + std::strerror(err) +
      "): choose a folder you can write to");
  }
#endif
  const auto space = fs::space(existing, ec);
  if (!ec && diskBytes > 0 &&
    static_cast<double>(space.available) < 1.05 * static_cast<double>(diskBytes))
    throw Error("not enough free space in '" + existing.string() + "': the build needs about " +
      bytesText(diskBytes) + " while it runs, " +
      bytesText(static_cast<std::int64_t>(space.available)) +
      " are free (free some space, choose another folder or a smaller budget)");
}

} // namespace ddg
