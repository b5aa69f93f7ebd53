// NeuralModel.cxx: the only file that includes libtorch — networks, training, evaluation,
// bundles.
#include "Neural/NeuralModel.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Common/Parallel.h"
#include "Design/DecoderLayout.h"
#include "Design/DesignJson.h"
#include "Gallery/Outline.h"
#include "Image/ImageMetrics.h"
#include "Render/DifferentiableRenderer.h"

#include <nlohmann/json.hpp>
#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <random>
#include <sstream>

namespace ddg
{
namespace
{
namespace nn = torch::nn;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

int blocksFor(int size)
{
  int b = 0;
  while ((size >> (b + 1)) >= 4)
    ++b;
  return b; // size / 2^b == 4
}

int channels(const NetworkConfig& c, int block)
{
  return c.width * std::min(8, 1 << block);
}

// Appends a 4x4 stride-2 conv block (InstanceNorm optional, LeakyReLU 0.2) to s.
void addDown(nn::Sequential& s, int in, int out, bool norm)
{
  s->push_back(nn::Conv2d(nn::Conv2dOptions(in, out, 4).stride(2).padding(1).bias(!norm)));
  if (norm)
    s->push_back(nn::InstanceNorm2d(nn::InstanceNorm2dOptions(out).affine(true)));
  s->push_back(nn::LeakyReLU(nn::LeakyReLUOptions().negative_slope(0.2)));
}

nn::Sequential down(int in, int out, bool norm)
{
  nn::Sequential s;
  addDown(s, in, out, norm);
  return s;
}

nn::Sequential up(int in, int out, double dropout)
{
  nn::Sequential s;
  s->push_back(
    nn::ConvTranspose2d(nn::ConvTranspose2dOptions(in, out, 4).stride(2).padding(1).bias(false)));
  s->push_back(nn::InstanceNorm2d(nn::InstanceNorm2dOptions(out).affine(true)));
  s->push_back(nn::ReLU());
  if (dropout > 0)
    s->push_back(nn::Dropout(dropout));
  return s;
}

// Analyzer: RGB image -> latent TF (4x4 stride-2 blocks, InstanceNorm on all but first/last).
struct AnalyzerImpl : nn::Module
{
  nn::Sequential body;
  nn::Conv2d head{ nullptr };
  explicit AnalyzerImpl(const NetworkConfig& c)
  {
    int in = 3;
    for (int b = 0; b < blocksFor(c.imageSize); ++b)
    {
      addDown(body, in, channels(c, b), b > 0);
      in = channels(c, b);
    }
    head = nn::Conv2d(nn::Conv2dOptions(in, c.latent, 4)); // 4x4 -> 1x1
    register_module("body", body);
    register_module("head", head);
  }
  torch::Tensor forward(const torch::Tensor& x) { return head(body->forward(x)).flatten(1); }
};
TORCH_MODULE(Analyzer);

// Renderer: U-Net on the viewport image, the latent concatenated at the 4x4 bottleneck.
struct RendererImpl : nn::Module
{
  std::vector<nn::Sequential> downs, ups;
  nn::Sequential bottleneck;
  nn::ConvTranspose2d last{ nullptr };
  int latent = 64;
  explicit RendererImpl(const NetworkConfig& c)
    : latent(c.latent)
  {
    const int blocks = blocksFor(c.imageSize);
    int in = 4;
    for (int b = 0; b < blocks; ++b)
    {
      downs.push_back(register_module("down" + std::to_string(b), down(in, channels(c, b), b > 0)));
      in = channels(c, b);
    }
    const int top = channels(c, blocks - 1);
    bottleneck = register_module("bottleneck",
      nn::Sequential(nn::Conv2d(nn::Conv2dOptions(top + c.latent, top, 3).padding(1).bias(false)),
        nn::InstanceNorm2d(nn::InstanceNorm2dOptions(top).affine(true)), nn::ReLU()));
    for (int b = blocks - 1; b >= 1; --b)
    {
      const double drop = (blocks - 1 - b) < 3 ? c.dropout : 0.0; // dropout in the first up blocks
      ups.push_back(register_module(
        "up" + std::to_string(b), up(2 * channels(c, b), channels(c, b - 1), drop)));
    }
    last = register_module("last",
      nn::ConvTranspose2d(
        nn::ConvTranspose2dOptions(2 * channels(c, 0), 4, 4).stride(2).padding(1)));
  }
  torch::Tensor forward(const torch::Tensor& z, const torch::Tensor& viewport)
  {
    std::vector<torch::Tensor> skips;
    torch::Tensor h = viewport;
    for (auto& d : downs)
    {
      h = d->forward(h);
      skips.push_back(h);
    }
    const auto zz = z.view({ z.size(0), latent, 1, 1 }).expand({ -1, -1, h.size(2), h.size(3) });
    h = bottleneck->forward(torch::cat({ h, zz }, 1));
    for (size_t i = 0; i < ups.size(); ++i)
    {
      h = ups[i]->forward(torch::cat({ h, skips[skips.size() - 1 - i] }, 1));
    }
    return torch::sigmoid(last(torch::cat({ h, skips[0] }, 1)));
  }
};
TORCH_MODULE(Renderer);

// PatchGAN discriminator on (image, viewport): sigmoid per patch.
struct DiscriminatorImpl : nn::Module
{
  nn::Sequential body;
  explicit DiscriminatorImpl(const NetworkConfig& c)
  {
    int in = 8;
    const int blocks = std::min(3, blocksFor(c.imageSize));
    for (int b = 0; b < blocks; ++b)
    {
      addDown(body, in, channels(c, b), b > 0);
      in = channels(c, b);
    }
    body->push_back(nn::Conv2d(nn::Conv2dOptions(in, 1, 4).padding(1)));
    register_module("body", body);
  }
  torch::Tensor forward(const torch::Tensor& image, const torch::Tensor& viewport)
  {
    return torch::sigmoid(body->forward(torch::cat({ image, viewport }, 1)));
  }
};
TORCH_MODULE(Discriminator);

// Decoder (lean variant): latent -> 7 numbers per feature region
// (active logit, mean shift, stddev scale, r, g, b, opacity; all but the logit squashed later).
struct DecoderImpl : nn::Module
{
  nn::Sequential body;
  int outputs = 7;
  DecoderImpl(int latent, int regions, int outputsPerRegion)
    : outputs(outputsPerRegion)
  {
    body = register_module("body",
      nn::Sequential(nn::Linear(latent, 128), nn::ReLU(), nn::Linear(128, 128), nn::ReLU(),
        nn::Linear(128, outputs * regions)));
  }
  torch::Tensor forward(const torch::Tensor& z)
  {
    return body->forward(z).view({ z.size(0), -1, outputs });
  }
};
TORCH_MODULE(Decoder);

// Decoder outputs in [0, 1] (or [-1, 1] for the mean shift) from raw values.
torch::Tensor squash(const torch::Tensor& raw)
{
  std::vector<torch::Tensor> parts{ raw.slice(2, 0, 1), torch::tanh(raw.slice(2, 1, 2)),
    torch::sigmoid(raw.slice(2, 2, 7)) };
  if (raw.size(2) == 9) // 2D: gradient-magnitude mean shift and stddev
  {
    parts.push_back(torch::tanh(raw.slice(2, 7, 8)));
    parts.push_back(torch::sigmoid(raw.slice(2, 8, 9)));
  }
  return torch::cat(parts, 2);
}

void xavier(nn::Module& m)
{
  for (auto& p : m.named_parameters())
  {
    if (p.key().find("weight") != std::string::npos && p.value().dim() == 4)
      nn::init::xavier_normal_(p.value());
    else if (p.key().find("bias") != std::string::npos)
      nn::init::zeros_(p.value());
  }
}

// Shapes of every parameter and buffer (Module::load does not check them).
std::vector<std::vector<std::int64_t>> shapes(nn::Module& mod)
{
  std::vector<std::vector<std::int64_t>> out;
  for (const auto& p : mod.named_parameters())
    out.push_back(p.value().sizes().vec());
  for (const auto& b : mod.named_buffers())
    out.push_back(b.value().sizes().vec());
  return out;
}

// An archive's bytes. libtorch's save_to(path) throws from a destructor when the disk is full
// (std::terminate); serializing to memory and writing with writeFileAtomic reports it instead.
std::string serialized(torch::serialize::OutputArchive& ar)
{
  std::ostringstream out(std::ios::binary);
  ar.save_to(out);
  return out.str();
}

void setThreads(int threads)
{
  at::set_num_threads(threads > 0 ? threads : defaultThreadCount());
}

torch::Tensor imageToTensor(const Image& img, int channels)
{
  const Image c = toChannels(img, channels);
  return torch::from_blob(
    const_cast<float*>(c.pixels.data()), { img.height, img.width, channels }, torch::kFloat32)
    .permute({ 2, 0, 1 })
    .clone();
}

Image tensorToImage(const torch::Tensor& t) // CHW
{
  const auto hwc = t.detach().permute({ 1, 2, 0 }).contiguous();
  Image img(
    static_cast<int>(hwc.size(1)), static_cast<int>(hwc.size(0)), static_cast<int>(hwc.size(2)));
  std::memcpy(img.pixels.data(), hwc.data_ptr<float>(), img.pixels.size() * sizeof(float));
  return img;
}

// Ground-truth and neural RGBA over mid-grey, as the user would look at them.
Image overGrey(const Image& premultipliedRGBA)
{
  return compositeOverBackground(premultipliedRGBA, { 0.5, 0.5, 0.5 });
}

} // namespace

void NetworkConfig::validate() const
{
  if (imageSize < 16 || imageSize > 512 || (imageSize & (imageSize - 1)) != 0)
    throw Error("network image size must be a power of two in 16..512");
  if (width < 2 || width > 256 || latent < 2 || latent > 1024 || !(dropout >= 0 && dropout < 1))
    throw Error("network width 2..256, latent 2..1024 and dropout in [0, 1) are required");
  if (kind != "unet" && kind != "decoder")
    throw Error("network kind must be \"unet\" or \"decoder\", not \"" + kind + "\"");
  if (kind == "decoder" && (regions < 1 || regions > 16))
    throw Error("the decoder needs 1..16 feature regions");
  if (dimensions != 1 && dimensions != 2)
    throw Error("network dimensions must be 1 or 2");
}

struct NeuralDesignModel::Internals
{
  NetworkConfig Config;
  Analyzer A{ nullptr };
  Renderer R{ nullptr };
  Discriminator D{ nullptr };
  Decoder Dec{ nullptr };
  // decoder: what its outputs mean, and the volume it is shown on
  DecoderLayout Layout; // regions and spec
  TrainingDesigns Designs;
  std::string Fingerprint;
  std::shared_ptr<DifferentiableRenderer> Diff; // its caster() renders the decoded TFs

  bool decoder() const { return Config.kind == "decoder"; }
  nn::Module& generator()
  {
    return decoder() ? static_cast<nn::Module&>(*Dec) : static_cast<nn::Module&>(*R);
  }

};

NeuralDesignModel::NeuralDesignModel(const NetworkConfig& config, std::uint64_t seed)
  : In(std::make_unique<Internals>())
{
  config.validate();
  In->Config = config;
  torch::manual_seed(seed);
  In->A = Analyzer(config);
  if (config.kind == "decoder")
  {
    In->Dec = Decoder(config.latent, config.regions, config.dimensions == 2 ? 9 : 7);
  }
  else
  {
    In->R = Renderer(config);
    In->D = Discriminator(config);
    xavier(*In->R);
    xavier(*In->D);
  }
  xavier(*In->A);
}

NeuralDesignModel::~NeuralDesignModel() = default;
NeuralDesignModel::NeuralDesignModel(NeuralDesignModel&&) noexcept = default;
NeuralDesignModel& NeuralDesignModel::operator=(NeuralDesignModel&&) noexcept = default;

const NetworkConfig& NeuralDesignModel::config() const
{
  return In->Config;
}

std::int64_t NeuralDesignModel::parameterCount() const
{
  std::int64_t n = 0;
  for (const auto& p : In->A->parameters())
    n += p.numel();
  for (const auto& p : In->generator().parameters())
    n += p.numel();
  return n;
}

std::vector<float> NeuralDesignModel::analyze(const Image& image) const
{
  torch::NoGradGuard guard;
  In->A->eval();
  const int s = In->Config.imageSize;
  const Image resized = image.width == s && image.height == s ? image : resizeImage(image, s, s);
  const auto x = imageToTensor(resized, 3).unsqueeze(0).mul(2.0).sub(1.0);
  const auto z = In->A->forward(x).contiguous();
  return std::vector<float>(z.data_ptr<float>(), z.data_ptr<float>() + z.numel());
}

std::vector<float> NeuralDesignModel::analyzeBatch(const std::vector<Image>& images) const
{
  torch::NoGradGuard guard;
  In->A->eval();
  const int s = In->Config.imageSize;
  std::vector<float> out;
  out.reserve(images.size() * static_cast<size_t>(In->Config.latent));
  const size_t batch = 256;
  for (size_t first = 0; first < images.size(); first += batch)
  {
    std::vector<torch::Tensor> xs;
    for (size_t i = first; i < std::min(images.size(), first + batch); ++i)
    {
      const Image& image = images[i];
      const Image resized =
        image.width == s && image.height == s ? image : resizeImage(image, s, s);
      xs.push_back(imageToTensor(resized, 3));
    }
    const auto z = In->A->forward(torch::stack(xs).mul(2.0).sub(1.0)).contiguous();
    out.insert(out.end(), z.data_ptr<float>(), z.data_ptr<float>() + z.numel());
  }
  return out;
}

Image NeuralDesignModel::render(const std::vector<float>& latent, const Image& viewport) const
{
  if (In->decoder())
    throw Error("the decoder model renders with a view: use renderAt");
  torch::NoGradGuard guard;
  In->R->eval();
  const int s = In->Config.imageSize;
  if (static_cast<int>(latent.size()) != In->Config.latent)
    throw Error("latent has " + std::to_string(latent.size()) + " values, the model expects " +
      std::to_string(In->Config.latent));
  if (viewport.width != s || viewport.height != s || viewport.channels != 4)
    throw Error("the viewport image must be RGBA at the model's size " + std::to_string(s));
  const auto z =
    torch::from_blob(const_cast<float*>(latent.data()), { 1, In->Config.latent }, torch::kFloat32)
      .clone();
  return tensorToImage(In->R->forward(z, imageToTensor(viewport, 4).unsqueeze(0))[0]);
}

std::vector<GaussianPrimitive> NeuralDesignModel::decode(const std::vector<float>& latent) const
{
  std::vector<GaussianPrimitive> prims;
  for (const auto& g : decodeRegions(latent))
    if (g.opacity >= DecoderLayout::kMinOpacity)
      prims.push_back(g);
  return prims;
}

std::vector<GaussianPrimitive> NeuralDesignModel::decodeRegions(const std::vector<float>& latent) const
{
  if (!In->decoder())
    throw Error("only the decoder model has an explicit TF");
  if (static_cast<int>(latent.size()) != In->Config.latent)
    throw Error("latent has the wrong size");
  if (static_cast<int>(In->Layout.regions.size()) != In->Config.regions)
    throw Error("the decoder has no feature regions yet: train it or load a bundle");
  torch::NoGradGuard guard;
  In->Dec->eval();
  const auto z =
    torch::from_blob(const_cast<float*>(latent.data()), { 1, In->Config.latent }, torch::kFloat32)
      .clone();
  const auto o = squash(In->Dec->forward(z))[0].contiguous();
  return In->Layout.decodeRegions(o.data_ptr<float>());
}

void NeuralDesignModel::attachVolume(const Volume& volume)
{
  const std::string fp = volumeFingerprint(volume);
  if (!In->Fingerprint.empty() && fp != In->Fingerprint)
    throw Error("this model was trained on another volume (" + In->Fingerprint + "), not " + fp);
  In->Diff = std::make_shared<DifferentiableRenderer>(volume);
  In->Fingerprint = fp;
  if (In->Config.dimensions == 2)
    In->Layout.gradientRange = volume.gradientMagnitudeRange();
}

Image NeuralDesignModel::renderAt(
  const std::vector<float>& latent, const Image& viewport, const View& view) const
{
  if (!In->decoder())
  {
    const int s = In->Config.imageSize;
    const Image vp =
      viewport.width == s && viewport.height == s ? viewport : resizeImage(viewport, s, s);
    const Image out = render(latent, vp);
    return out.width == view.width && out.height == view.height
      ? out
      : resizeImage(out, view.width, view.height);
  }
  if (!In->Diff)
    throw Error("the decoder model needs its volume (attachVolume) to render");
  return renderDesign(
    In->Diff->caster(), decode(latent), In->Config.dimensions, In->Layout.gradientRange, view);
}

TrainReport NeuralDesignModel::train(const ExemplarDataset& data, const TrainOptions& opt,
  const std::function<bool(const TrainProgress&)>& progress)
{
  const int s = In->Config.imageSize;
  if (data.size() != s)
    throw Error("the dataset's images are " + std::to_string(data.size()) +
      " pixels, the model's " + std::to_string(s));
  if (opt.batch < 1 || !(opt.learningRate > 0) || !(opt.minutes > 0) || !(opt.lambdaL1 >= 0))
    throw Error("training needs batch >= 1, a positive learning rate and time budget, lambda >= 0");
  const bool decoder = In->decoder();
  if (decoder && (static_cast<int>(data.regions().size()) != In->Config.regions ||
                   data.spec().dimensions != In->Config.dimensions))
    throw Error("the decoder was built for " + std::to_string(In->Config.regions) + " regions in " +
      std::to_string(In->Config.dimensions) + "D, the data has " +
      std::to_string(data.regions().size()) + " in " + std::to_string(data.spec().dimensions) +
      "D");
  In->Layout.regions = data.regions();
  In->Layout.spec = data.spec();
  if (decoder)
  {
    if (opt.imageWeight > 0 && !In->Diff)
      throw Error("the decoder's image loss needs the volume: attach it before training");
    if (opt.imageWeight > 0 && data.fingerprint() != In->Fingerprint)
      throw Error("the training data belongs to another volume than the attached one");
    In->Fingerprint = data.fingerprint();
  }
  if (opt.cosineSchedule && opt.maxIterations < 1)
    throw Error("the cosine learning-rate schedule needs a maximum iteration count");
  if (opt.imageWeight < 0 || opt.imageRays < 1)
    throw Error("training needs an image weight >= 0 and at least one ray per exemplar");
  const bool imageLoss = decoder && opt.imageWeight > 0;
  const int outputs = In->Layout.outputs();
  setThreads(opt.threads);
  torch::manual_seed(opt.seed);
  // Whole dataset in memory (N x C x S x S, uint8); the decoder needs only the analyzer's input
  // and the exemplars' TF parameters.
  const int n = data.count();
  auto rgb = torch::empty({ n, 3, s, s }, torch::kUInt8);
  auto vp = decoder ? torch::Tensor() : torch::empty({ n, 4, s, s }, torch::kUInt8);
  auto gt = decoder ? torch::Tensor() : torch::empty({ n, 4, s, s }, torch::kUInt8);
  auto params =
    decoder ? torch::empty({ n, In->Config.regions, outputs }, torch::kFloat32) : torch::Tensor();
  std::vector<std::uint8_t> truth; // decoder with image loss: ground truths, n x S x S x 4
  if (imageLoss)
    truth.resize(static_cast<size_t>(n) * s * s * 4);
  {
    std::vector<std::uint8_t> a, b, c;
    for (int i = 0; i < n; ++i)
    {
      data.load(i, a, b, c);
      rgb[i].copy_(torch::from_blob(a.data(), { s, s, 3 }, torch::kUInt8).permute({ 2, 0, 1 }));
      if (decoder)
      {
        auto t = In->Layout.targets(data.exemplars()[static_cast<size_t>(i)]);
        params[i].copy_(
          torch::from_blob(t.data(), { In->Config.regions, outputs }, torch::kFloat32));
        if (imageLoss)
          std::copy(c.begin(), c.end(), truth.begin() + static_cast<std::ptrdiff_t>(i) * s * s * 4);
      }
      else
      {
        vp[i].copy_(torch::from_blob(b.data(), { s, s, 4 }, torch::kUInt8).permute({ 2, 0, 1 }));
        gt[i].copy_(torch::from_blob(c.data(), { s, s, 4 }, torch::kUInt8).permute({ 2, 0, 1 }));
      }
    }
  }
  // Modules by name (checkpoints), the generator's optimizer, the discriminator's (U-Net only).
  std::vector<std::pair<std::string, nn::Module*>> modules{ { "analyzer", In->A.get() } };
  if (decoder)
    modules.push_back({ "decoder", In->Dec.get() });
  else
  {
    modules.push_back({ "renderer", In->R.get() });
    modules.push_back({ "discriminator", In->D.get() });
  }
  std::vector<torch::Tensor> gParams;
  for (const auto& p : In->A->parameters())
    gParams.push_back(p);
  for (const auto& p : In->generator().parameters())
    gParams.push_back(p);
  torch::optim::Adam optG(
    gParams, torch::optim::AdamOptions(opt.learningRate).betas({ 0.5, 0.999 }));
  std::unique_ptr<torch::optim::Adam> optD;
  if (!decoder)
    optD = std::make_unique<torch::optim::Adam>(
      In->D->parameters(), torch::optim::AdamOptions(opt.learningRate).betas({ 0.5, 0.999 }));
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
      torch::serialize::InputArchive og;
      ar.read("optG", og);
      optG.load(og);
      if (optD)
      {
        torch::serialize::InputArchive od;
        ar.read("optD", od);
        optD->load(od);
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
    torch::serialize::OutputArchive og;
    optG.save(og);
    ar.write("optG", og);
    if (optD)
    {
      torch::serialize::OutputArchive od;
      optD->save(od);
      ar.write("optD", od);
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
    if (opt.cosineSchedule && opt.maxIterations > 0)
    {
      const double t = std::min(1.0, static_cast<double>(iteration) / opt.maxIterations);
      const double lr = opt.learningRate * (0.05 + 0.95 * 0.5 * (1 + std::cos(M_PI * t)));
      for (auto& group : optG.param_groups())
        static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
      if (optD)
        for (auto& group : optD->param_groups())
          static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
    }
    const auto sel = torch::tensor(idx, torch::kInt64);
    const auto x = rgb.index_select(0, sel).to(torch::kFloat32).div(127.5).sub(1.0);
    torch::Tensor lossG, lossD, l1;
    double imageL1 = 0;
    if (decoder)
    {
      // TF-parameter regression: which regions are active, and their squashed parameters.
      const auto target = params.index_select(0, sel);
      const auto raw = In->Dec->forward(In->A->forward(x));
      const auto sq = squash(raw);
      const auto active = target.slice(2, 0, 1);
      const auto bce = torch::binary_cross_entropy_with_logits(raw.slice(2, 0, 1), active);
      const auto err = (sq.slice(2, 1) - target.slice(2, 1)).abs() * active;
      l1 = err.sum() / (active.sum() * (outputs - 1) + 1e-6);
      lossG = bce + l1;
      if (imageLoss)
      {
        // What the user sees: the decoded TF ray cast at V_view against the ground truth. The
        // adjoint's gradient enters autograd through the surrogate sum(sq * grad).
        const auto out = sq.detach().contiguous();
        auto grad = torch::zeros_like(out);
        std::vector<double> losses(idx.size());
        const int regions = In->Config.regions;
        parallelFor(static_cast<std::int64_t>(idx.size()), opt.threads,
          [&](std::int64_t b, int)
          {
            const auto i = static_cast<size_t>(idx[static_cast<size_t>(b)]);
            std::mt19937_64 pick(opt.seed * 0x9E3779B97F4A7C15ull +
              static_cast<std::uint64_t>(iteration) * 4096 + static_cast<std::uint64_t>(b));
            std::vector<int> pixels(static_cast<size_t>(opt.imageRays));
            for (int& p : pixels)
              p = static_cast<int>(pick() % static_cast<std::uint64_t>(s * s));
            losses[static_cast<size_t>(b)] = In->Layout.imageLoss(*In->Diff,
              out.data_ptr<float>() + b * regions * outputs, data.exemplars()[i].viewView,
              truth.data() + i * s * s * 4, pixels, grad.data_ptr<float>() + b * regions * outputs);
          });
        imageL1 = std::accumulate(losses.begin(), losses.end(), 0.0) / losses.size();
        lossG = lossG + (opt.imageWeight / static_cast<double>(idx.size())) * (sq * grad).sum();
      }
      lossD = torch::zeros({});
      optG.zero_grad();
      lossG.backward();
      optG.step();
    }
    else
    {
      const auto v = vp.index_select(0, sel).to(torch::kFloat32).div(255.0);
      const auto t = gt.index_select(0, sel).to(torch::kFloat32).div(255.0);
      const auto fake = In->R->forward(In->A->forward(x), v);
      optD->zero_grad();
      const auto dReal = In->D->forward(t, v);
      const auto dFake = In->D->forward(fake.detach(), v);
      lossD = 0.5 *
        (torch::binary_cross_entropy(dReal, torch::ones_like(dReal)) +
          torch::binary_cross_entropy(dFake, torch::zeros_like(dFake)));
      lossD.backward();
      optD->step();
      optG.zero_grad();
      const auto dG = In->D->forward(fake, v);
      l1 = torch::l1_loss(fake, t);
      lossG = torch::binary_cross_entropy(dG, torch::ones_like(dG)) + opt.lambdaL1 * l1;
      lossG.backward();
      optG.step();
    }
    ++iteration;
    if (!opt.checkpoint.empty() && iteration % opt.checkpointEvery == 0)
      saveCheckpoint();
    if (progress && (iteration % 10 == 0))
    {
      TrainProgress p;
      p.iteration = iteration;
      p.lossG = lossG.item<double>();
      p.lossD = lossD.item<double>();
      p.l1 = l1.item<double>();
      p.image = imageL1;
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
  report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  report.exemplarsPerSecond =
    (iteration - startIteration) * static_cast<double>(opt.batch) / std::max(1e-9, report.seconds);
  for (auto& m : modules)
    m.second->eval();
  return report;
}

EvaluationReport NeuralDesignModel::evaluate(const ExemplarDataset& data, int maxExemplars) const
{
  const int s = In->Config.imageSize;
  if (data.size() != s)
    throw Error("the dataset's images are " + std::to_string(data.size()) +
      " pixels, the model's " + std::to_string(s));
  EvaluationReport r;
  r.count = std::min(maxExemplars, data.count());
  std::vector<std::vector<float>> latExp, latView;
  for (int i = 0; i < r.count; ++i)
  {
    const auto [rgbExp, viewport, truth] = data.images(i);
    const auto z = analyze(rgbExp);
    const Image pred =
      overGrey(renderAt(z, viewport, data.exemplars()[static_cast<size_t>(i)].viewView));
    const Image gt = overGrey(truth);
    const EvaluationReport::Item item{ std::min(psnr(pred, gt), 99.0), ssim(pred, gt),
      colorHistogramEMD(pred, gt) };
    r.items.push_back(item);
    r.psnr += item.psnr / r.count;
    r.ssim += item.ssim / r.count;
    r.emd += item.emd / r.count;
    // the same TF seen from V_view, over the exemplar's own background
    const double bg = data.exemplars()[static_cast<size_t>(i)].background;
    latExp.push_back(z);
    latView.push_back(analyze(compositeOverBackground(truth, { bg, bg, bg })));
  }
  auto dist = [](const std::vector<float>& p, const std::vector<float>& q)
  {
    double d = 0;
    for (size_t k = 0; k < p.size(); ++k)
      d += (p[k] - q[k]) * (p[k] - q[k]);
    return d;
  };
  int holds = 0, triplets = 0;
  for (int i = 0; i < r.count; ++i)
    for (int j : { (i + 1) % r.count, (i + 7) % r.count })
    {
      if (j == i)
        continue;
      ++triplets;
      holds += dist(latExp[i], latView[i]) < dist(latExp[i], latExp[j]);
    }
  r.invariance = triplets ? static_cast<double>(holds) / triplets : 0;
  // latency, batch 1, median of 21
  const auto first = data.images(0);
  const Image& rgbExp = first.rgbExp;
  const Image& viewport = first.viewport;
  std::vector<double> ta, tr;
  std::vector<float> z;
  for (int k = 0; k < 21; ++k)
  {
    auto t0 = Clock::now();
    z = analyze(rgbExp);
    ta.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    t0 = Clock::now();
    renderAt(z, viewport, data.exemplars()[0].viewView);
    tr.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::sort(ta.begin(), ta.end());
  std::sort(tr.begin(), tr.end());
  r.analyzerMs = ta[10];
  r.rendererMs = tr[10];
  return r;
}

void NeuralDesignModel::saveBundle(
  const std::string& dir, const ExemplarDataset& training, const std::string& metricsJson) const
{
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw Error("cannot create bundle directory '" + dir + "': " + ec.message());
  // bundle.json is written last and removed first: a failed save never leaves an index that
  // describes files of another save
  fs::remove(fs::path(dir) / "bundle.json", ec);
  // weights
  {
    torch::serialize::OutputArchive ar, a, r;
    In->A->save(a);
    In->generator().save(r);
    ar.write("analyzer", a);
    ar.write(In->decoder() ? "decoder" : "renderer", r);
    writeFileAtomic((fs::path(dir) / "model.pt").string(), serialized(ar), "bundle weights");
  }
  // latents of the training exemplars (half floats) and their TF parameters (for the gallery)
  {
    LatentSet set;
    set.dim = In->Config.latent;
    set.seed = training.exemplars().empty() ? 0 : training.exemplars()[0].seed;
    const int chunk = 1024;
    for (int first = 0; first < training.count(); first += chunk)
    {
      std::vector<Image> images;
      for (int i = first; i < std::min(training.count(), first + chunk); ++i)
      {
        images.push_back(training.images(i).rgbExp);
        set.indices.push_back(static_cast<std::uint64_t>(i));
      }
      const auto z = analyzeBatch(images);
      set.values.insert(set.values.end(), z.begin(), z.end());
    }
    writeLatentSet(set, (fs::path(dir) / "latents.bin").string());
  }
  nlohmann::json ex = nlohmann::json::array();
  for (int i = 0; i < training.count(); ++i)
  {
    nlohmann::json p = nlohmann::json::array();
    for (const auto& g : training.exemplars()[static_cast<size_t>(i)].primitives)
      p.push_back(primitiveToJson(g, training.spec().dimensions == 2, true));
    ex.push_back(p);
  }
  writeFileAtomic(
    (fs::path(dir) / "exemplars.json").string(), ex.dump() + "\n", "bundle exemplars");
  nlohmann::json j;
  j["format"] = "ddg-model-bundle";
  j["version"] = 2; // 2: latents.bin is a half-float latent set (Gallery/Outline.h)
  j["architecture"] = { { "kind", In->Config.kind }, { "regions", In->Config.regions },
    { "image_size", In->Config.imageSize }, { "width", In->Config.width },
    { "latent", In->Config.latent }, { "dropout", In->Config.dropout },
    { "dimensions", In->Config.dimensions } };
  j["parameters"] = parameterCount();
  j["volume"] = training.fingerprint();
  j["spec"] = nlohmann::json::parse(designSpaceSpecToJson(training.spec()));
  j["regions"] = nlohmann::json::array();
  for (const auto& r : training.regions())
    j["regions"].push_back(regionToJson(r));
  j["training_exemplars"] = training.count();
  j["metrics"] =
    metricsJson.empty() ? nlohmann::json::object() : nlohmann::json::parse(metricsJson);
  writeFileAtomic((fs::path(dir) / "bundle.json").string(), j.dump(2) + "\n", "bundle index");
}

const TrainingDesigns& NeuralDesignModel::trainingDesigns() const
{
  return In->Designs;
}

const std::vector<FeatureRegion>& NeuralDesignModel::regions() const
{
  return In->Layout.regions;
}

const DesignSpaceSpec& NeuralDesignModel::spec() const
{
  return In->Layout.spec;
}

NeuralDesignModel NeuralDesignModel::loadBundle(
  const std::string& dir, const std::string& expectedFingerprint)
{
  const std::string indexPath = (fs::path(dir) / "bundle.json").string();
  nlohmann::json j;
  try
  {
    j = nlohmann::json::parse(readTextFile(indexPath, "model bundle"));
  }
  catch (const nlohmann::json::parse_error& e)
  {
    throw Error("model bundle '" + indexPath + "' is corrupt: " + e.what());
  }
  NetworkConfig c;
  try
  {
    if (j.value("format", std::string()) != "ddg-model-bundle" || j.value("version", 0) != 2)
      throw Error("'" + indexPath + "' is not a version-2 ddg model bundle");
    const auto& a = j.at("architecture");
    c.kind = a.value("kind", std::string());
    if (c.kind != "unet" && c.kind != "decoder")
      throw Error("model bundle '" + dir + "' has an unknown architecture '" + c.kind + "'");
    c.regions = a.value("regions", 0);
    c.dimensions = a.value("dimensions", 1);
    c.imageSize = a.at("image_size").get<int>();
    c.width = a.at("width").get<int>();
    c.latent = a.at("latent").get<int>();
    c.dropout = a.at("dropout").get<double>();
    if (!expectedFingerprint.empty() && j.at("volume").get<std::string>() != expectedFingerprint)
      throw Error("model bundle '" + dir + "' was trained on another volume (" +
        j.at("volume").get<std::string>() + "), not this one (" + expectedFingerprint + ")");
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error("model bundle '" + indexPath + "' is corrupt: " + e.what());
  }
  NeuralDesignModel m(c);
  try
  {
    m.In->Fingerprint = j.at("volume").get<std::string>();
    m.In->Layout.spec = parseDesignSpaceSpec(j.at("spec").dump(), indexPath);
    for (const auto& r : j.at("regions"))
      m.In->Layout.regions.push_back(regionFromJson(r));
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error("model bundle '" + indexPath + "' is corrupt: " + e.what());
  }
  if (c.kind == "decoder" && static_cast<int>(m.In->Layout.regions.size()) != c.regions)
    throw Error("model bundle '" + indexPath + "' is inconsistent: " + std::to_string(c.regions) +
      " regions in the architecture, " + std::to_string(m.In->Layout.regions.size()) + " listed");
  // Module::load replaces tensors whatever their shape: compare them with the architecture's.
  const auto expectA = shapes(*m.In->A), expectR = shapes(m.In->generator());
  const std::string broken = "model bundle '" + dir +
    "': model.pt is missing, truncated or does not match the architecture in bundle.json";
  try
  {
    torch::serialize::InputArchive ar, a, r;
    ar.load_from((fs::path(dir) / "model.pt").string());
    ar.read("analyzer", a);
    ar.read(c.kind == "decoder" ? "decoder" : "renderer", r);
    m.In->A->load(a);
    m.In->generator().load(r);
  }
  catch (const c10::Error&)
  {
    throw Error(broken);
  }
  if (shapes(*m.In->A) != expectA || shapes(m.In->generator()) != expectR)
  {
    throw Error(broken);
  }
  // the training designs: latents.bin (a half-float latent set) and exemplars.json
  auto& d = m.In->Designs;
  d.latent = c.latent;
  const std::string latentsPath = (fs::path(dir) / "latents.bin").string();
  const std::string designsPath = (fs::path(dir) / "exemplars.json").string();
  try
  {
    const auto count = j.at("training_exemplars").get<std::int64_t>();
    for (const auto& tf : nlohmann::json::parse(readTextFile(designsPath, "model bundle designs")))
    {
      std::vector<GaussianPrimitive> prims;
      for (const auto& p : tf)
        prims.push_back(primitiveFromJson(p));
      validatePrimitives(prims, c.dimensions == 2);
      d.tfs.push_back(std::move(prims));
    }
    LatentSet set;
    try
    {
      set = readLatentSet(latentsPath);
    }
    catch (const Error& e)
    {
      throw Error("model bundle '" + dir + "': " + e.what());
    }
    if (static_cast<std::int64_t>(d.tfs.size()) != count || set.count() != count ||
      set.dim != c.latent)
      throw Error("model bundle '" + dir + "': latents.bin or exemplars.json is truncated (" +
        std::to_string(count) + " training exemplars of latent " + std::to_string(c.latent) +
        " expected)");
    d.latents = std::move(set.values);
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error("model bundle '" + designsPath + "' is corrupt: " + e.what());
  }
  return m;
}

} // namespace ddg
