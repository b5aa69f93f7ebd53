// BuildDesignSpace.cxx: exemplars -> decoder -> bundle -> outline.
#include "Gallery/BuildDesignSpace.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Design/DesignSpace.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

namespace ddg
{

namespace fs = std::filesystem;

std::string metricsToJson(const EvaluationReport& e, const TrainReport* t, std::int64_t parameters)
{
  char buf[512];
  std::snprintf(buf, sizeof(buf),
    "{\"heldout_count\": %d, \"psnr\": %.4f, \"ssim\": %.5f, \"emd\": %.5f, \"invariance\": %.4f, "
    "\"analyzer_ms\": %.3f, \"renderer_ms\": %.3f, \"parameters\": %lld, \"train_iterations\": %d, "
    "\"train_seconds\": %.1f, \"train_exemplars_per_second\": %.2f, \"image_rays\": %d}",
    e.count, e.psnr, e.ssim, e.emd, e.invariance, e.analyzerMs, e.rendererMs,
    static_cast<long long>(parameters), t ? t->iterations : 0, t ? t->seconds : 0.0,
    t ? t->exemplarsPerSecond : 0.0, t ? t->imageRays : 0);
  return buf;
}

namespace
{
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The bundle's files are written to a staging folder inside the bundle folder and moved into it
// when everything is done (bundle.json last); a failed or cancelled build removes the staging
// folder, and the bundle folder when the build created it.
struct Staging
{
  fs::path bundle, dir;
  bool createdBundle = false, committed = false;

  Staging(const std::string& bundleDir)
    : bundle(fs::absolute(bundleDir))
    , dir(bundle / ".ddg-build-partial")
  {
    std::error_code ec;
    createdBundle = !fs::exists(bundle, ec);
    fs::create_directories(bundle, ec);
    if (!ec)
    {
      fs::remove_all(dir, ec); // a crashed build's leftovers (only ever ours)
      fs::create_directory(dir, ec);
    }
    if (ec)
    {
      discard();
      throw Error("cannot create the bundle folder '" + bundle.string() + "': " + ec.message());
    }
  }

  ~Staging()
  {
    if (!committed)
      discard();
  }

  void discard()
  {
    std::error_code ec;
    fs::remove_all(dir, ec);
    if (createdBundle && fs::is_empty(bundle, ec))
      fs::remove(bundle, ec);
  }

  // Moves the bundle's files into place: an older bundle.json first out (and an older query key
  // the new bundle may not have), the new one last.
  void commit(const std::string& keep)
  {
    fs::remove(bundle / "bundle.json");
    fs::remove(queryKeyFile(bundle.string()));
    for (const auto& entry : fs::directory_iterator(dir))
      if (entry.path().filename() != "bundle.json" && entry.path().filename() != keep)
        fs::rename(entry.path(), bundle / entry.path().filename());
    fs::rename(dir / "bundle.json", bundle / "bundle.json");
    committed = true;
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

// The bundle records the original volume's fingerprint when the design space was built on a
// downsampled copy (the panel and the filters match bundles to volumes by it).
void setBundleVolume(const fs::path& bundleJson, const std::string& fingerprint)
{
  std::ifstream in(bundleJson);
  nlohmann::json j = nlohmann::json::parse(in);
  in.close();
  j["volume"] = fingerprint;
  writeFileAtomic(bundleJson.string(), j.dump(2), "bundle index");
}

void checkBuildOptions(const std::string& bundleDir, const BuildOptions& o)
{
  if (bundleDir.empty())
    throw Error("building a design space needs an output bundle directory");
  if (o.budgetMinutes < 0 || (o.budgetMinutes > 0 && o.budgetMinutes < 1))
    throw Error("a build budget is at least 1 minute");
}
} // namespace

BuildReport buildDesignSpace(const Volume& original, const std::string& volumeFile,
  const std::string& bundleDir, const BuildOptions& options,
  const std::function<bool(const std::string&, double)>& progress)
{
  checkBuildOptions(bundleDir, options);
  if (options.maxDesignVoxels < 1)
    throw Error("the design space's voxel cap (maxDesignVoxels) must be positive");
  const auto start = Clock::now();
  const DesignSpaceInput input = designSpaceInput(original, options.maxDesignVoxels);
  return buildDesignSpace(input, volumeFile, bundleDir, options, progress, start);
}

BuildReport buildDesignSpace(const DesignSpaceInput& input, const std::string& volumeFile,
  const std::string& bundleDir, const BuildOptions& options,
  const std::function<bool(const std::string&, double)>& progress,
  std::chrono::steady_clock::time_point start)
{
  BuildOptions o = options;
  checkBuildOptions(bundleDir, o);
  if (input.volume.empty())
    throw Error("the design space's volume has no values");
  if (input.factor > 1 && input.fingerprint.empty())
    throw Error("a downsampled design space needs its volume's fingerprint");
  // 0. the volume the design space is built on, and the plan
  const int factor = input.factor;
  const Volume& volume = input.volume;
  BuildReport r;
  const bool outlineRendered = o.spec.pictureFraction > 0; // outlineFromExemplars renders then
  if (o.budgetMinutes > 0)
  {
    r.plan = planBuild(input, o.budgetMinutes, o.size, o.threads, o.rates, outlineRendered);
    o.count = r.plan.count;
    o.heldout = r.plan.heldout;
    o.minutes = r.plan.trainingMinutes;
    o.outlineCount = r.plan.outlineCount;
    o.iterations = 0;
  }
  if (o.count < 8 || o.heldout < 1 || o.outlineCount < 3 || !(o.minutes > 0))
    throw Error("building a design space needs >= 8 exemplars, >= 1 held out, >= 3 outline "
                "designs and a positive time budget");
  if (o.budgetMinutes <= 0)
    r.plan = estimateBuild(volume.dims(), factor,
      o.rates.measured() ? o.rates : measureBuildRates(volume, o.size, o.threads, 4), o.count,
      o.heldout, o.outlineCount, o.size, o.minutes, outlineRendered);
  r.plan.downsample = factor;
  checkBuildOutput(bundleDir, r.plan.diskBytes, o.overwrite);
  // stage weights from the estimate: the overall fraction grows about linearly with time
  const double total = std::max(1e-6,
    r.plan.exemplarSeconds + r.plan.trainingSeconds + r.plan.evaluationSeconds +
      r.plan.outlineSeconds);
  const double wE = r.plan.exemplarSeconds / total, wT = r.plan.trainingSeconds / total,
               wV = r.plan.evaluationSeconds / total;
  auto keepGoing = [&](const std::string& stage, double f)
  { return !progress || progress(stage, std::clamp(f, 0.0, 1.0)); };
  auto report = [&](const std::string& stage, double f)
  {
    if (!keepGoing(stage, f))
      throw Cancelled();
  };
  report("exemplars", 0);
  Staging staging(bundleDir);
  const std::string work =
    o.workDirectory.empty() ? (staging.dir / "exemplars").string() : o.workDirectory;
  // 1. exemplars: training and held-out sets
  auto t0 = Clock::now();
  GenerateOptions g;
  g.count = o.count;
  g.size = o.size;
  g.seed = o.seed;
  g.threads = o.threads;
  g.volumeFile = volumeFile;
  g.screen = o.screen;
  g.viewport = false; // the decoder does not read it
  g.workers = o.workers;
  const double trainShare = static_cast<double>(o.count) / (o.count + o.heldout);
  r.exemplars = generateExemplars(volume, o.spec, (fs::path(work) / "train").string(), g,
    [&](double f) { return keepGoing("exemplars", wE * trainShare * f); });
  g.count = o.heldout;
  g.firstIndex = 1000000;
  r.workerCandidates = r.exemplars.workerCandidates;
  r.workerCandidates += generateExemplars(volume, o.spec, (fs::path(work) / "heldout").string(), g,
    [&](double f) {
      return keepGoing("exemplars", wE * (trainShare + (1 - trainShare) * f));
    }).workerCandidates;
  r.generateSeconds = secondsSince(t0);
  report("training", wE);
  const ExemplarDataset train((fs::path(work) / "train").string());
  const ExemplarDataset heldout((fs::path(work) / "heldout").string());
  // 2. the decoder
  NetworkConfig cfg;
  cfg.kind = "decoder";
  cfg.imageSize = o.size;
  cfg.width = o.width;
  cfg.regions = static_cast<int>(train.regions().size());
  cfg.dimensions = train.spec().dimensions;
  NeuralDesignModel model(cfg, o.seed);
  model.attachVolume(volume);
  TrainOptions t;
  t.learningRate = 1e-3;
  t.minutes = o.minutes;
  if (o.budgetMinutes > 0) // the exemplars' estimate from a few probes errs either way
    t.minutes = r.plan.trainingMinutesAfter(secondsSince(start));
  t.maxIterations = o.iterations;
  t.cosineSchedule = true; // over the iterations when given, else over the time budget
  t.imageWeight = 100;
  // bounded by minutes, its steps go where they buy most (Documentation/DesignSpaces.md);
  // with a fixed iteration count it repeats to the byte
  t.adaptiveRays = o.iterations == 0;
  t.otherViewFraction = o.otherViewFraction;
  t.imageSampleScale = o.imageSampleScale;
  t.seed = o.seed;
  t.threads = o.threads;
  double trained = wE; // the overall fraction at the last report
  t.interrupt = [&]() { return !keepGoing("training", trained); };
  r.training = model.train(train, t,
    [&](const TrainProgress& p)
    {
      const double f = o.iterations > 0 ? static_cast<double>(p.iteration) / o.iterations
                                        : p.seconds / (60 * t.minutes);
      trained = wE + wT * std::min(1.0, f);
      return keepGoing("training", trained);
    });
  if (r.training.cancelled)
    throw Cancelled();
  // 3. its figures on the held-out exemplars, the bundle
  t0 = Clock::now();
  report("evaluation", wE + wT);
  // (the figures' share of the stage: the held-out count against the training latents saved)
  const double figures = o.heldout / (o.heldout + 0.2 * o.count);
  r.evaluation = model.evaluate(heldout, o.heldout,
    [&](double f) { return keepGoing("evaluation", wE + wT + figures * wV * f); });
  r.evaluationSeconds = secondsSince(t0);
  t0 = Clock::now();
  model.saveBundle(staging.dir.string(), train,
    metricsToJson(r.evaluation, &r.training, model.parameterCount()),
    [&](double f)
    { return keepGoing("evaluation", wE + wT + (figures + (1 - figures) * f) * wV); });
  if (factor > 1)
    setBundleVolume(staging.dir / "bundle.json", input.fingerprint);
  r.savingSeconds = secondsSince(t0);
  // 4. the outline, and the query key (the training exemplars' two views)
  t0 = Clock::now();
  report("outline", wE + wT + wV);
  const double wO = 1 - wE - wT - wV;
  const double keyShare = r.plan.outlineSeconds > 0
    ? std::clamp(r.plan.queryKeySeconds / r.plan.outlineSeconds, 0.0, 1.0)
    : 0.5;
  const auto set = outlineFromExemplars(
    model, volume, train, o.outlineCount, o.seed, o.threads,
    [&](double f) { return keepGoing("outline", wE + wT + wV + (1 - keyShare) * wO * f); },
    o.screen, o.workers);
  writeLatentSet(set, outlineFile(staging.dir.string()));
  try
  {
    const QueryKey key = queryKeyFromExemplars(model, train, kQueryKeyPairs, o.threads,
      [&](double f)
      { return keepGoing("outline", wE + wT + wV + (1 - keyShare + keyShare * f) * wO); });
    if (!key.empty())
    {
      writeQueryKey(key, queryKeyFile(staging.dir.string()));
      r.queryKeyPairs = key.pairs;
    }
    else
      r.queryKeyNote = "too few exemplars show their design from both views";
  }
  catch (const Cancelled&)
  {
    throw;
  }
  catch (const Error& e) // the bundle works without one: queries compare latents as they are
  {
    r.queryKeyNote = e.what();
  }
  r.outlineSeconds = secondsSince(t0);
  report("outline", 1.0);
  staging.commit(o.workDirectory.empty() ? "exemplars" : "");
  r.totalSeconds = secondsSince(start);
  if (progress)
    progress("done", 1.0);
  return r;
}

} // namespace ddg
