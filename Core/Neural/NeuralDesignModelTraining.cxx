// NeuralDesignModelTraining.cxx: NeuralDesignModel::train — one loop (batches, learning-rate
// schedule, checkpoints, progress and cancel) over a training strategy per model kind: the U-Net's
// adversarial training (pix2pix) and the decoder's TF-parameter regression (with the optional
// image loss through the ray caster).
#include "Neural/NeuralDesignModel.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Common/Parallel.h"
#include "Neural/NeuralDesignModelInternals.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numeric>
#include <random>
#include <utility>

namespace ddg
{
namespace
{
using namespace neural;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// What one step reports (tensors: read only when progress is reported).
struct StepLosses
{
  torch::Tensor lossG, lossD, l1;
  double image = 0;        ///< decoder: mean image L1 through the ray caster
  double imageSeconds = 0; ///< ... and the seconds it took
};

// What differs between the model kinds: the data a step needs, the modules and optimizers
// (by checkpoint name, in checkpoint order) and the step itself. The constructors check the
// data and options against the model (throwing ddg::Error) and record the data's regions,
// spec (and the decoder's volume fingerprint) in the model, as the training did before
// anything else.
class TrainingStrategy
{
public:
  virtual ~TrainingStrategy() = default;
  /// Sets up the optimizers and the per-exemplar tensors for n exemplars at the model's size s.
  virtual void prepare(int n, int s) = 0;
  /// Keeps what a step needs of exemplar i: its viewport (b) and ground truth (c) bytes as
  /// ExemplarDataset::load gives them (the analyzer's input is kept by the loop).
  virtual void store(
    int i, const std::vector<std::uint8_t>& b, const std::vector<std::uint8_t>& c) = 0;
  /// Modules by checkpoint name, the analyzer first (train() / eval() and checkpoints).
  virtual std::vector<std::pair<std::string, nn::Module*>> modules() = 0;
  /// Optimizers by checkpoint name ("optG", then "optD" for the U-Net).
  virtual std::vector<std::pair<std::string, torch::optim::Adam*>> optimizers() = 0;
  /// One optimisation step on the batch `idx` (sel: the same indices as a tensor) whose
  /// analyzer input is x (N x 3 x S x S in [-1, 1]).
  virtual StepLosses step(const std::vector<std::int64_t>& idx, const torch::Tensor& sel,
    const torch::Tensor& x, int iteration) = 0;
  /// Image-loss rays per exemplar (0: no image loss), and setting them from the next step.
  virtual int imageRays() const { return 0; }
  virtual void setImageRays(int) {}
  /// The image loss's sample distance over ParaView's, from the next step.
  virtual void setImageSampleScale(double) {}
};

// Adam as the paper trains with it (beta1 0.5, beta2 0.999).
std::unique_ptr<torch::optim::Adam> adam(std::vector<torch::Tensor> parameters, double learningRate)
{
  return std::make_unique<torch::optim::Adam>(
    std::move(parameters), torch::optim::AdamOptions(learningRate).betas({ 0.5, 0.999 }));
}

// The generator's parameters: the analyzer's, then the decoder's or the renderer's.
std::vector<torch::Tensor> generatorParameters(NeuralDesignModel::Internals& in)
{
  std::vector<torch::Tensor> gParams;
  for (const auto& p : in.A->parameters())
    gParams.push_back(p);
  for (const auto& p : in.generator().parameters())
    gParams.push_back(p);
  return gParams;
}

// --- the U-Net: pix2pix (PatchGAN discriminator + lambda L1) ------------------------------

class UNetTraining : public TrainingStrategy
{
public:
  UNetTraining(
    NeuralDesignModel::Internals& in, const ExemplarDataset& data, const TrainOptions& opt)
    : In(in)
    , Opt(opt)
  {
    if (!data.hasViewport())
      throw Error("the U-Net needs the exemplars' viewport images, and this dataset was generated "
                  "without them (for the decoder): generate it again with them");
    In.Layout.regions = data.regions();
    In.Layout.spec = data.spec();
  }

  void prepare(int n, int s) override
  {
    OptG = adam(generatorParameters(In), Opt.learningRate);
    OptD = adam(In.D->parameters(), Opt.learningRate);
    Viewports = torch::empty({ n, 4, s, s }, torch::kUInt8);
    Truths = torch::empty({ n, 4, s, s }, torch::kUInt8);
    Size = s;
  }

  void store(int i, const std::vector<std::uint8_t>& b, const std::vector<std::uint8_t>& c) override
  {
    const int s = Size;
    Viewports[i].copy_(
      torch::from_blob(const_cast<std::uint8_t*>(b.data()), { s, s, 4 }, torch::kUInt8)
        .permute({ 2, 0, 1 }));
    Truths[i].copy_(
      torch::from_blob(const_cast<std::uint8_t*>(c.data()), { s, s, 4 }, torch::kUInt8)
        .permute({ 2, 0, 1 }));
  }

  std::vector<std::pair<std::string, nn::Module*>> modules() override
  {
    return { { "analyzer", In.A.get() }, { "renderer", In.R.get() },
      { "discriminator", In.D.get() } };
  }

  std::vector<std::pair<std::string, torch::optim::Adam*>> optimizers() override
  {
    return { { "optG", OptG.get() }, { "optD", OptD.get() } };
  }

  StepLosses step(const std::vector<std::int64_t>&, const torch::Tensor& sel,
    const torch::Tensor& x, int) override
  {
    StepLosses out;
    const auto v = Viewports.index_select(0, sel).to(torch::kFloat32).div(255.0);
    const auto t = Truths.index_select(0, sel).to(torch::kFloat32).div(255.0);
    const auto fake = In.R->forward(In.A->forward(x), v);
    // discriminator: real as real, fake as fake
    OptD->zero_grad();
    const auto dReal = In.D->forward(t, v);
    const auto dFake = In.D->forward(fake.detach(), v);
    out.lossD = 0.5 *
      (torch::binary_cross_entropy(dReal, torch::ones_like(dReal)) +
        torch::binary_cross_entropy(dFake, torch::zeros_like(dFake)));
    out.lossD.backward();
    OptD->step();
    // generator: fool the discriminator, stay close to the ground truth
    OptG->zero_grad();
    const auto dG = In.D->forward(fake, v);
    out.l1 = torch::l1_loss(fake, t);
    out.lossG = torch::binary_cross_entropy(dG, torch::ones_like(dG)) + Opt.lambdaL1 * out.l1;
    out.lossG.backward();
    OptG->step();
    return out;
  }

private:
  NeuralDesignModel::Internals& In;
  const TrainOptions& Opt;
  std::unique_ptr<torch::optim::Adam> OptG, OptD;
  torch::Tensor Viewports, Truths; // N x 4 x S x S, uint8
  int Size = 0;
};

// --- the decoder: TF-parameter regression (+ image loss through the ray caster) -----------

class DecoderTraining : public TrainingStrategy
{
public:
  DecoderTraining(
    NeuralDesignModel::Internals& in, const ExemplarDataset& data, const TrainOptions& opt)
    : In(in)
    , Data(data)
    , Opt(opt)
  {
    if (static_cast<int>(data.regions().size()) != In.Config.regions ||
      data.spec().dimensions != In.Config.dimensions)
      throw Error("the decoder was built for " + std::to_string(In.Config.regions) +
        " regions in " + std::to_string(In.Config.dimensions) + "D, the data has " +
        std::to_string(data.regions().size()) + " in " + std::to_string(data.spec().dimensions) +
        "D");
    In.Layout.regions = data.regions();
    In.Layout.spec = data.spec();
    if (opt.imageWeight > 0 && !In.Diff)
      throw Error("the decoder's image loss needs the volume: attach it before training");
    if (opt.imageWeight > 0 && data.fingerprint() != In.Fingerprint)
      throw Error("the training data belongs to another volume than the attached one");
    In.Fingerprint = data.fingerprint();
    ImageLoss = opt.imageWeight > 0;
    Rays = opt.imageRays;
    SampleScale = opt.adaptiveRays ? 1.0 : opt.imageSampleScale; // the rays are timed at 1
    Outputs = In.Layout.outputs();
  }

  int imageRays() const override { return ImageLoss ? Rays : 0; }
  void setImageRays(int rays) override { Rays = rays; }
  void setImageSampleScale(double scale) override { SampleScale = scale; }

  void prepare(int n, int s) override
  {
    OptG = adam(generatorParameters(In), Opt.learningRate);
    Params = torch::empty({ n, In.Config.regions, Outputs }, torch::kFloat32);
    if (ImageLoss)
      Truth.resize(static_cast<size_t>(n) * s * s * 4);
    Size = s;
  }

  void store(int i, const std::vector<std::uint8_t>&, const std::vector<std::uint8_t>& c) override
  {
    const int s = Size;
    auto t = In.Layout.targets(Data.exemplars()[static_cast<size_t>(i)]);
    Params[i].copy_(torch::from_blob(t.data(), { In.Config.regions, Outputs }, torch::kFloat32));
    if (ImageLoss)
      std::copy(c.begin(), c.end(), Truth.begin() + static_cast<std::ptrdiff_t>(i) * s * s * 4);
  }

  std::vector<std::pair<std::string, nn::Module*>> modules() override
  {
    return { { "analyzer", In.A.get() }, { "decoder", In.Dec.get() } };
  }

  std::vector<std::pair<std::string, torch::optim::Adam*>> optimizers() override
  {
    return { { "optG", OptG.get() } };
  }

  StepLosses step(const std::vector<std::int64_t>& idx, const torch::Tensor& sel,
    const torch::Tensor& x, int iteration) override
  {
    StepLosses out;
    // TF-parameter regression: which regions are active, and their squashed parameters.
    const auto target = Params.index_select(0, sel);
    const auto raw = In.Dec->forward(In.A->forward(x));
    const auto sq = squash(raw);
    const auto active = target.slice(2, 0, 1);
    const auto bce = torch::binary_cross_entropy_with_logits(raw.slice(2, 0, 1), active);
    const auto err = (sq.slice(2, 1) - target.slice(2, 1)).abs() * active;
    out.l1 = err.sum() / (active.sum() * (Outputs - 1) + 1e-6);
    out.lossG = bce + out.l1;
    if (ImageLoss)
    {
      const auto t0 = Clock::now();
      out.image = imageLoss(idx, sq, iteration, out.lossG);
      out.imageSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    }
    out.lossD = torch::zeros({});
    OptG->zero_grad();
    out.lossG.backward();
    OptG->step();
    return out;
  }

private:
  // What the user sees: the decoded TF ray cast at V_view against the ground truth (the batch's
  // mean L1). The adjoint's gradient enters autograd as the surrogate sum(sq * grad) in lossG.
  double imageLoss(const std::vector<std::int64_t>& idx, const torch::Tensor& sq, int iteration,
    torch::Tensor& lossG)
  {
    const int s = Size;
    const auto out = sq.detach().contiguous();
    auto grad = torch::zeros_like(out);
    std::vector<double> losses(idx.size());
    const int stride = In.Config.regions * Outputs; // a batch row's outputs
    parallelFor(
      static_cast<std::int64_t>(idx.size()), Opt.threads,
      [&](std::int64_t b, int thread)
      {
        if (thread == 0 && Opt.interrupt && Opt.interrupt()) // the calling thread
          throw Cancelled();
        const auto i = static_cast<size_t>(idx[static_cast<size_t>(b)]);
        std::mt19937_64 pick(Opt.seed * 0x9E3779B97F4A7C15ull +
          static_cast<std::uint64_t>(iteration) * 4096 + static_cast<std::uint64_t>(b));
        std::vector<int> pixels(static_cast<size_t>(Rays));
        for (int& p : pixels)
          p = static_cast<int>(pick() % static_cast<std::uint64_t>(s * s));
        losses[static_cast<size_t>(b)] = In.Layout.imageLoss(*In.Diff,
          out.data_ptr<float>() + b * stride, Data.exemplars()[i].viewView,
          Truth.data() + i * s * s * 4, pixels, grad.data_ptr<float>() + b * stride, SampleScale);
      },
      onTorchThreads);
    lossG = lossG + (Opt.imageWeight / static_cast<double>(idx.size())) * (sq * grad).sum();
    return std::accumulate(losses.begin(), losses.end(), 0.0) / losses.size();
  }

  NeuralDesignModel::Internals& In;
  const ExemplarDataset& Data;
  const TrainOptions& Opt;
  std::unique_ptr<torch::optim::Adam> OptG;
  bool ImageLoss = false;
  int Rays = 0;           // image-loss rays per exemplar (Opt.imageRays, or adapted)
  double SampleScale = 1; // Opt.imageSampleScale, once the adaptive rays are chosen
  int Outputs = 7;
  int Size = 0;
  torch::Tensor Params;            // N x regions x outputs: the exemplars' TF targets
  std::vector<std::uint8_t> Truth; // image loss: ground truths, N x S x S x 4
};

} // namespace

// --- the training loop -------------------------------------------------------------------

TrainReport NeuralDesignModel::train(const ExemplarDataset& data, const TrainOptions& opt,
  const std::function<bool(const TrainProgress&)>& progress)
{
  const int s = In->Config.imageSize;
  if (data.size() != s)
    throw Error("the dataset's images are " + std::to_string(data.size()) +
      " pixels, the model's " + std::to_string(s));
  if (opt.batch < 1 || !(opt.learningRate > 0) || !(opt.minutes > 0) || !(opt.lambdaL1 >= 0))
    throw Error("training needs batch >= 1, a positive learning rate and time budget, lambda >= 0");
  std::unique_ptr<TrainingStrategy> strategy;
  if (In->decoder())
    strategy = std::make_unique<DecoderTraining>(*In, data, opt);
  else
    strategy = std::make_unique<UNetTraining>(*In, data, opt);
  if (!(opt.imageSampleScale > 0))
    throw Error("the image loss's sample scale must be positive");
  if (opt.imageWeight < 0 || opt.imageRays < 1)
    throw Error("training needs an image weight >= 0 and at least one ray per exemplar");
  if (!(opt.otherViewFraction >= 0 && opt.otherViewFraction <= 1))
    throw Error("training needs an other-view fraction in [0, 1]");
  setThreads(opt.threads);
  torch::manual_seed(opt.seed);
  // Whole dataset in memory: the analyzer's input (N x 3 x S x S, uint8) here, what the
  // strategy's step needs there.
  const int n = data.count();
  auto rgb = torch::empty({ n, 3, s, s }, torch::kUInt8);
  // with otherViewFraction, the ground truths at V_view too (N x 4 x S x S, premultiplied)
  torch::Tensor other;
  if (opt.otherViewFraction > 0)
    other = torch::empty({ n, 4, s, s }, torch::kUInt8);
  strategy->prepare(n, s);
  {
    std::vector<std::uint8_t> a, b, c;
    for (int i = 0; i < n; ++i)
    {
      data.load(i, a, b, c);
      rgb[i].copy_(torch::from_blob(a.data(), { s, s, 3 }, torch::kUInt8).permute({ 2, 0, 1 }));
      if (other.defined())
        other[i].copy_(torch::from_blob(c.data(), { s, s, 4 }, torch::kUInt8).permute({ 2, 0, 1 }));
      strategy->store(i, b, c);
    }
  }
  const auto modules = strategy->modules();
  const auto optimizers = strategy->optimizers();
  int iteration = 0;
  if (opt.resume && !opt.checkpoint.empty() && fs::exists(opt.checkpoint))
  {
    try
    {
      torch::serialize::InputArchive ar;
      ar.load_from(opt.checkpoint);
      for (auto& [name, module] : modules)
      {
        torch::serialize::InputArchive sub;
        ar.read(name, sub);
        const auto expected = shapes(*module);
        module->load(sub);
        if (shapes(*module) != expected)
          throw Error("cannot resume from checkpoint '" + opt.checkpoint +
            "': it belongs to another architecture");
      }
      for (auto& [name, optimizer] : optimizers)
      {
        torch::serialize::InputArchive sub;
        ar.read(name, sub);
        optimizer->load(sub);
      }
      torch::Tensor it;
      ar.read("iteration", it);
      iteration = static_cast<int>(it.item<std::int64_t>());
    }
    catch (const c10::Error&)
    {
      throw Error("cannot resume from checkpoint '" + opt.checkpoint +
        "': it is corrupt or of another architecture");
    }
  }
  auto saveCheckpoint = [&]
  {
    torch::serialize::OutputArchive ar;
    for (auto& [name, module] : modules)
    {
      torch::serialize::OutputArchive sub;
      module->save(sub);
      ar.write(name, sub);
    }
    for (auto& [name, optimizer] : optimizers)
    {
      torch::serialize::OutputArchive sub;
      optimizer->save(sub);
      ar.write(name, sub);
    }
    ar.write("iteration", torch::tensor(static_cast<std::int64_t>(iteration)));
    writeFileAtomic(opt.checkpoint, serialized(ar), "checkpoint");
  };
  std::mt19937_64 rng(opt.seed + static_cast<std::uint64_t>(iteration));
  std::vector<std::int64_t> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  size_t cursor = order.size();
  const auto start = Clock::now();
  TrainReport report;
  for (auto& m : modules)
    m.second->train();
  const int startIteration = iteration;
  constexpr auto kReportEvery = std::chrono::milliseconds(250);
  auto lastReport = start;
  double timedImage = 0, timedStep = 0; // adaptiveRays: the timed steps' seconds
  const bool adaptRays = opt.adaptiveRays && strategy->imageRays() > 0;
  while (true)
  {
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    if (elapsed > opt.minutes * 60 || (opt.maxIterations > 0 && iteration >= opt.maxIterations))
      break;
    std::vector<std::int64_t> idx;
    for (int b = 0; b < opt.batch; ++b)
    {
      if (cursor >= order.size())
      {
        std::shuffle(order.begin(), order.end(), rng);
        cursor = 0;
      }
      idx.push_back(order[cursor++]);
    }
    if (opt.cosineSchedule)
    {
      // over the iterations when they are capped, else over the time budget
      const double t = opt.maxIterations > 0
        ? std::min(1.0, static_cast<double>(iteration) / opt.maxIterations)
        : std::min(1.0, elapsed / (opt.minutes * 60));
      const double lr = opt.learningRate * (0.05 + 0.95 * 0.5 * (1 + std::cos(M_PI * t)));
      for (auto& [name, optimizer] : optimizers)
        for (auto& group : optimizer->param_groups())
          static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
    }
    const auto sel = torch::tensor(idx, torch::kInt64);
    const auto x = analyzerInput(rgb, other, sel, opt, iteration).div(127.5).sub(1.0);
    const auto stepStart = Clock::now();
    const StepLosses losses = strategy->step(idx, sel, x, iteration);
    ++iteration;
    if (adaptRays)
    {
      const int done = iteration - startIteration; // steps of this call
      if (done > kAdaptiveRaysFrom && done <= kAdaptiveRaysTo)
      {
        timedImage += losses.imageSeconds;
        timedStep += std::chrono::duration<double>(Clock::now() - stepStart).count();
      }
      if (done == kAdaptiveRaysTo)
      {
        strategy->setImageRays(
          adaptiveImageRays(opt.imageRays, timedImage, std::max(0.0, timedStep - timedImage)));
        strategy->setImageSampleScale(opt.imageSampleScale);
      }
    }
    if (!opt.checkpoint.empty() && iteration % opt.checkpointEvery == 0)
      saveCheckpoint();
    // every 10 iterations, and at least every 0.25 s (cancel stays within ~0.3 s)
    if (progress && (iteration % 10 == 0 || Clock::now() - lastReport > kReportEvery))
    {
      lastReport = Clock::now();
      TrainProgress p;
      p.iteration = iteration;
      p.lossG = losses.lossG.item<double>();
      p.lossD = losses.lossD.item<double>();
      p.l1 = losses.l1.item<double>();
      p.image = losses.image;
      p.seconds = std::chrono::duration<double>(Clock::now() - start).count();
      const double rate = (iteration - startIteration) / std::max(1e-9, p.seconds);
      p.eta = opt.maxIterations > 0
        ? std::min(opt.minutes * 60 - p.seconds, (opt.maxIterations - iteration) / rate)
        : opt.minutes * 60 - p.seconds;
      if (!std::isfinite(p.lossG) || !std::isfinite(p.lossD))
        throw Error("training diverged (loss is NaN) at iteration " + std::to_string(iteration));
      if (!progress(p))
      {
        report.cancelled = true;
        if (!opt.checkpoint.empty())
          saveCheckpoint();
        break;
      }
    }
  }
  if (!opt.checkpoint.empty() && !report.cancelled)
    saveCheckpoint();
  report.iterations = iteration;
  report.imageRays = strategy->imageRays();
  report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  report.exemplarsPerSecond =
    (iteration - startIteration) * static_cast<double>(opt.batch) / std::max(1e-9, report.seconds);
  for (auto& m : modules)
    m.second->eval();
  return report;
}

} // namespace ddg
