// BuildDesignSpace.cxx: exemplars -> decoder -> bundle -> outline.
#include "Gallery/BuildDesignSpace.h"

#include "Common/Error.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace ddg
{

namespace fs = std::filesystem;

std::string metricsToJson(const EvaluationReport& e, const TrainReport* t, std::int64_t parameters)
{
  char buf[512];
  std::snprintf(buf, sizeof(buf),
    "{\"heldout_count\": %d, \"psnr\": %.4f, \"ssim\": %.5f, \"emd\": %.5f, \"invariance\": %.4f, "
    "\"analyzer_ms\": %.3f, \"renderer_ms\": %.3f, \"parameters\": %lld, \"train_iterations\": %d, "
    "\"train_seconds\": %.1f, \"train_exemplars_per_second\": %.2f}",
    e.count, e.psnr, e.ssim, e.emd, e.invariance, e.analyzerMs, e.rendererMs,
    static_cast<long long>(parameters), t ? t->iterations : 0, t ? t->seconds : 0.0,
    t ? t->exemplarsPerSecond : 0.0);
  return buf;
}

BuildReport buildDesignSpace(const Volume& volume, const std::string& volumeFile,
  const std::string& bundleDir, const BuildOptions& o,
  const std::function<bool(const std::string&, double)>& progress)
{
  if (bundleDir.empty())
    throw Error("building a design space needs an output bundle directory");
  if (o.count < 8 || o.heldout < 1 || o.outlineCount < 3 || !(o.minutes > 0))
    throw Error("building a design space needs >= 8 exemplars, >= 1 held out, >= 3 outline "
                "designs and a positive time budget");
  using Clock = std::chrono::steady_clock;
  auto report = [&](const std::string& stage, double f)
  {
    if (progress && !progress(stage, f))
      throw Cancelled();
  };
  const std::string work =
    o.workDirectory.empty() ? (fs::path(bundleDir) / "exemplars").string() : o.workDirectory;
  BuildReport r;
  // 1. exemplars (10 % of the progress)
  auto t0 = Clock::now();
  GenerateOptions g;
  g.count = o.count;
  g.size = o.size;
  g.seed = o.seed;
  g.threads = o.threads;
  g.volumeFile = volumeFile;
  g.screen = o.screen;
  r.exemplars = generateExemplars(volume, o.spec, (fs::path(work) / "train").string(), g,
    [&](double f) { return !progress || progress("exemplars", 0.1 * f); });
  g.count = o.heldout;
  g.firstIndex = 1000000;
  generateExemplars(volume, o.spec, (fs::path(work) / "heldout").string(), g);
  r.generateSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const ExemplarDataset train((fs::path(work) / "train").string());
  const ExemplarDataset heldout((fs::path(work) / "heldout").string());
  // 2. the decoder (80 %)
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
  t.maxIterations = o.iterations;
  t.cosineSchedule = true; // over the iterations when given, else over the time budget
  t.imageWeight = 100;
  t.seed = o.seed;
  t.threads = o.threads;
  r.training = model.train(train, t,
    [&](const TrainProgress& p)
    {
      const double f = o.iterations > 0 ? static_cast<double>(p.iteration) / o.iterations
                                        : p.seconds / (60 * o.minutes);
      return !progress || progress("training", 0.1 + 0.8 * std::min(1.0, f));
    });
  if (r.training.cancelled)
    throw Cancelled();
  r.evaluation = model.evaluate(heldout, o.heldout);
  model.saveBundle(
    bundleDir, train, metricsToJson(r.evaluation, &r.training, model.parameterCount()));
  // 3. the outline (10 %)
  t0 = Clock::now();
  try
  {
    const auto set = buildOutlineLatents(
      model, volume, o.outlineCount, o.seed, 0, o.threads,
      [&](double f) { return !progress || progress("outline", 0.9 + 0.1 * f); }, o.screen);
    writeLatentSet(set, outlineFile(bundleDir));
  }
  catch (...)
  {
    // a bundle without its outline does not look finished
    fs::remove(fs::path(bundleDir) / "bundle.json");
    throw;
  }
  r.outlineSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (o.workDirectory.empty())
    fs::remove_all(work);
  report("done", 1.0);
  return r;
}

} // namespace ddg
