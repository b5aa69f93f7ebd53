// TrainCommand.cxx: `ddg train` — train a model on generated exemplars and write a model bundle:
// the Neural DVR Analyzer .
#ifdef DDG_WITH_TORCH
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/BuildDesignSpace.h"
#include "Neural/NeuralDesignModel.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct TrainArgs
{
  std::string data, out, evalData, checkpoint, kind = "decoder";
  double minutes = 10, lr = 0, lambda = 1000, dropout = 0.5, imageWeight = 100;
  int width = 16, latent = 64, batch = 16, threads = 0, maxIterations = 0, evalCount = 1000;
  int imageRays = 512;
  double imageSampleScale = 1;
  double otherView = 0;
  std::uint64_t seed = 1;
  int checkCount = 100;
  bool resume = false, quiet = false, cosine = false, adaptiveRays = false;
  std::string volume;
};

int runTrain(const TrainArgs& a)
{
  const ddg::ExemplarDataset data(a.data);
  ddg::NetworkConfig cfg;
  cfg.imageSize = data.size();
  cfg.width = a.width;
  cfg.latent = a.latent;
  cfg.dropout = a.dropout;
  cfg.kind = a.kind;
  cfg.regions = static_cast<int>(data.regions().size());
  cfg.dimensions = data.spec().dimensions;
  ddg::NeuralDesignModel model(cfg, a.seed);
  std::unique_ptr<ddg::ExemplarDataset> heldout;
  if (!a.evalData.empty())
  {
    heldout = std::make_unique<ddg::ExemplarDataset>(a.evalData);
    if (heldout->fingerprint() != data.fingerprint())
      throw ddg::Error(
        "the held-out data '" + a.evalData + "' belongs to another volume than the training data");
  }
  ddg::TrainOptions opt;
  opt.batch = a.batch;
  opt.learningRate = a.lr > 0 ? a.lr : (a.kind == "decoder" ? 1e-3 : 2e-4);
  opt.lambdaL1 = a.lambda;
  opt.minutes = a.minutes;
  opt.maxIterations = a.maxIterations;
  opt.seed = a.seed;
  opt.threads = a.threads;
  opt.checkpoint = a.checkpoint;
  opt.resume = a.resume;
  opt.imageWeight = a.kind == "decoder" ? a.imageWeight : 0.0;
  opt.imageRays = a.imageRays;
  opt.imageSampleScale = a.imageSampleScale;
  opt.adaptiveRays = a.adaptiveRays;
  opt.otherViewFraction = a.otherView;
  opt.cosineSchedule = a.cosine;
  // the decoder ray casts its TFs: the volume given, or the one the data was generated from
  const std::string volumeFile = a.volume.empty() ? data.volumeFile() : a.volume;
  if (a.kind == "decoder")
  {
    if (volumeFile.empty())
      throw ddg::Error(
        "the decoder needs its volume: pass --volume (the dataset does not name it)");
    model.attachVolume(ddg::readVolumeFile(volumeFile));
  }
  std::printf("training %lld parameters on %d exemplars of %d x %d for up to %.1f min\n",
    static_cast<long long>(model.parameterCount()), data.count(), data.size(), data.size(),
    a.minutes);
  int lastPrint = -1000;
  const auto report = model.train(data, opt,
    [&](const ddg::TrainProgress& p)
    {
      if (!a.quiet && p.iteration - lastPrint >= 200)
      {
        if (a.kind == "decoder")
          std::printf("iteration %6d  parameter L1 %.4f  image L1 %.4f  %.0f s, ETA %.0f s\n",
            p.iteration, p.l1, p.image, p.seconds, p.eta);
        else
          std::printf("iteration %6d  G %.3f  D %.3f  L1 %.4f  %.0f s, ETA %.0f s\n", p.iteration,
            p.lossG, p.lossD, p.l1, p.seconds, p.eta);
        std::fflush(stdout);
        lastPrint = p.iteration;
      }
      return true;
    });
  std::printf("trained %d iterations in %.1f s (%.1f exemplars/s, %d image-loss rays)\n",
    report.iterations, report.seconds, report.exemplarsPerSecond, report.imageRays);
  ddg::EvaluationReport e;
  std::string metrics = ddg::metricsToJson(e, &report, model.parameterCount());
  if (heldout)
  {
    e = model.evaluate(*heldout, a.evalCount);
    printEvaluation(e);
    // the first checkCount held-out exemplars again: what a quick test can reproduce
    const auto check = model.evaluate(*heldout, a.checkCount);
    metrics = ddg::metricsToJson(e, &report, model.parameterCount());
    metrics.pop_back();
    metrics += ", \"check\": " + ddg::metricsToJson(check, nullptr, model.parameterCount()) + "}";
  }
  model.saveBundle(a.out, data, metrics);
  std::printf("wrote model bundle %s\n", a.out.c_str());
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addTrainCommand(CLI::App& app)
{
  auto ta = std::make_shared<TrainArgs>();
  auto* train = app.add_subcommand("train",
    "Train a model on generated exemplars and write a model bundle: the Neural DVR Analyzer "
    "with the explicit-TF decoder (default; TF-parameter loss + image L1 through the "
    "differentiable ray caster, Adam 1e-3) or with the paper's U-Net renderer and PatchGAN "
    "discriminator (L = L_adv + lambda L1, Adam 2e-4, beta 0.5/0.999).");
  train->add_option("--data", ta->data, "Exemplar directory from ddg generate")->required();
  train->add_option("--out", ta->out, "Output model bundle directory")->required();
  train->add_option("--minutes", ta->minutes, "Wall-clock budget (default 10)")
    ->check(CLI::PositiveNumber);
  train->add_option("--max-iterations", ta->maxIterations,
    "Stop after this many iterations (default 0: budget only)");
  train->add_option(
    "--eval-data", ta->evalData, "Held-out exemplars to evaluate on and record in the bundle");
  train->add_option("--eval-count", ta->evalCount, "Held-out exemplars used (default 1000)");
  train->add_option("--check-count", ta->checkCount,
    "Also record the figures of the first N held-out exemplars, for quick reproduction tests "
    "(default 100)");
  train
    ->add_option("--kind", ta->kind,
      "decoder (default): latent -> explicit Gaussian-primitive TF, ray cast (what ParaView is "
      "given); unet: the paper's U-Net renderer with a PatchGAN discriminator")
    ->check(CLI::IsMember({ "unet", "decoder" }));
  train->add_option("--volume", ta->volume,
    "The volume the decoder ray casts (default: the file the data was generated from)");
  train->add_option("--image-weight", ta->imageWeight,
    "Decoder: weight of the image L1 through the differentiable ray caster, added to the "
    "TF-parameter loss (default 100; 0: parameters only)");
  train
    ->add_option("--image-rays", ta->imageRays,
      "Decoder: random pixels per exemplar in the "
      "image loss (default 512)")
    ->check(CLI::Range(1, 1 << 20));
  train
    ->add_option("--image-sample-scale", ta->imageSampleScale,
      "Decoder: the image loss's sample distance over ParaView's (opacity corrected; default 1: "
      "the ground truths' own step)")
    ->check(CLI::Range(0.25, 8.0));
  train->add_flag("--adaptive-rays", ta->adaptiveRays,
    "Decoder: time the image loss and the rest of a step over steps 6-25, then cast --image-rays "
    "x min(1, rest / image) rays (to a power of two, at least a quarter), as ddg build does "
    "when bounded by minutes: the image loss costs no more than the rest of a step");
  train
    ->add_option("--other-view", ta->otherView,
      "Share of the analyzer's images taken from each exemplar's other view (its ground truth "
      "over black or white) instead of its image at V_exp: more pictures of each design, no "
      "more renders (default 0)")
    ->check(CLI::Range(0.0, 1.0));
  train->add_option("--width", ta->width, "Channels of the first block (default 16)")
    ->check(CLI::Range(2, 256));
  train->add_option("--latent", ta->latent, "Latent TF size (default 64)")
    ->check(CLI::Range(2, 1024));
  train->add_option("--dropout", ta->dropout, "Dropout in the renderer's up blocks (default 0.5)");
  train->add_option("--batch", ta->batch, "Batch size (default 16)")->check(CLI::Range(1, 4096));
  train->add_option("--lr", ta->lr, "Adam learning rate (default 1e-3 decoder, 2e-4 unet)")
    ->check(CLI::PositiveNumber);
  train->add_option("--lambda", ta->lambda, "Weight of the L1 term (default 1000)");
  train->add_option("--seed", ta->seed, "Seed of initialisation and batch order (default 1)");
  train->add_option("--threads", ta->threads, "libtorch threads (default 0: all cores)");
  train->add_option(
    "--checkpoint", ta->checkpoint, "Checkpoint file, written every 500 iterations and at the end");
  train->add_flag("--resume", ta->resume, "Continue from --checkpoint");
  train->add_flag("--cosine", ta->cosine,
    "Cosine learning-rate schedule down to 5 % at --max-iterations, or without it at the end "
    "of --minutes");
  train->add_flag("--quiet", ta->quiet, "Do not print progress");
  return { train, [ta] { return runTrain(*ta); } };
}
#endif
