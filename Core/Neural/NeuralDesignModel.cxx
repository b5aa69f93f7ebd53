// NeuralDesignModel.cxx: a neural design model's construction, inference (analyze, render,
// decode), its volume, and its evaluation on held-out exemplars. Training is in
// NeuralDesignModelTraining.cxx, bundles in NeuralDesignModelBundle.cxx, the networks in
// NeuralNetworks.cxx.
#include "Neural/NeuralDesignModel.h"

#include "Common/Error.h"
#include "Gallery/Outline.h"
#include "Image/ImageMetrics.h"
#include "Neural/NeuralDesignModelInternals.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include <algorithm>
#include <chrono>

namespace ddg
{
namespace
{
using namespace neural;
using Clock = std::chrono::steady_clock;

// Ground-truth and neural RGBA over mid-grey, as the user would look at them.
Image overGrey(const Image& premultipliedRGBA)
{
  return compositeOverBackground(premultipliedRGBA, { 0.5, 0.5, 0.5 });
}

} // namespace

// --- construction ------------------------------------------------------------------------

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

std::vector<GaussianPrimitive> NeuralDesignModel::decodeRegions(
  const std::vector<float>& latent) const
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
    throw Error("this model was trained on another volume (" +
      describeFingerprint(In->Fingerprint) + "), not this one (" + describeFingerprint(fp) + ")");
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

// --- evaluation --------------------------------------------------------------------------

EvaluationReport NeuralDesignModel::evaluate(
  const ExemplarDataset& data, int maxExemplars, const std::function<bool(double)>& progress) const
{
  const int s = In->Config.imageSize;
  if (data.size() != s)
    throw Error("the dataset's images are " + std::to_string(data.size()) +
      " pixels, the model's " + std::to_string(s));
  if (!In->decoder() && !data.hasViewport())
    throw Error("the U-Net needs the exemplars' viewport images, and this dataset was generated "
                "without them (for the decoder)");
  EvaluationReport r;
  r.count = std::min(maxExemplars, data.count());
  std::vector<std::vector<float>> latExp, latView;
  // the analyzer runs on chunks of exemplars (batch 1 was 10x slower after training on a loaded
  // machine: 195 ms a figure), the renders and metrics per exemplar
  const int chunk = 20;
  const int dim = In->Config.latent;
  for (int first = 0; first < r.count; first += chunk)
  {
    const int n = std::min(chunk, r.count - first);
    std::vector<ExemplarDataset::Images> items;
    std::vector<Image> exp, view;
    for (int i = first; i < first + n; ++i)
    {
      items.push_back(data.images(i));
      // the same TF seen from V_view, over the exemplar's own background
      const double bg = data.exemplars()[static_cast<size_t>(i)].background;
      exp.push_back(items.back().rgbExp);
      view.push_back(compositeOverBackground(items.back().truth, { bg, bg, bg }));
    }
    const auto zExp = analyzeBatch(exp), zView = analyzeBatch(view);
    for (int q = 0; q < n; ++q)
    {
      const int i = first + q;
      const std::vector<float> z(zExp.begin() + q * dim, zExp.begin() + (q + 1) * dim);
      const Image pred =
        overGrey(renderAt(z, items[q].viewport, data.exemplars()[static_cast<size_t>(i)].viewView));
      const Image gt = overGrey(items[q].truth);
      const EvaluationReport::Item item{ std::min(psnr(pred, gt), 99.0), ssim(pred, gt),
        colorHistogramEMD(pred, gt) };
      r.items.push_back(item);
      r.psnr += item.psnr / r.count;
      r.ssim += item.ssim / r.count;
      r.emd += item.emd / r.count;
      latExp.push_back(z);
      latView.emplace_back(zView.begin() + q * dim, zView.begin() + (q + 1) * dim);
      if (progress && !progress(static_cast<double>(i + 1) / r.count))
        throw Cancelled();
    }
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

// --- what the model was trained with ----------------------------------------------------

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

} // namespace ddg
