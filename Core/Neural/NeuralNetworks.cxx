// NeuralNetworks.cxx: the analyzer, U-Net renderer, PatchGAN discriminator and decoder modules,
// and the tensor helpers of Core/Neural.
#include "Neural/NeuralNetworks.h"

#include "Common/Error.h"
#include "Common/Parallel.h"

#include <omp.h>

#include <algorithm>
#include <cstring>
#include <sstream>

namespace ddg
{

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

namespace neural
{
namespace
{

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

} // namespace

// --- analyzer ----------------------------------------------------------------------------

AnalyzerImpl::AnalyzerImpl(const NetworkConfig& c)
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

torch::Tensor AnalyzerImpl::forward(const torch::Tensor& x)
{
  return head(body->forward(x)).flatten(1);
}

// --- renderer (U-Net) --------------------------------------------------------------------

RendererImpl::RendererImpl(const NetworkConfig& c)
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
    ups.push_back(
      register_module("up" + std::to_string(b), up(2 * channels(c, b), channels(c, b - 1), drop)));
  }
  last = register_module("last",
    nn::ConvTranspose2d(nn::ConvTranspose2dOptions(2 * channels(c, 0), 4, 4).stride(2).padding(1)));
}

torch::Tensor RendererImpl::forward(const torch::Tensor& z, const torch::Tensor& viewport)
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

// --- discriminator -----------------------------------------------------------------------

DiscriminatorImpl::DiscriminatorImpl(const NetworkConfig& c)
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

torch::Tensor DiscriminatorImpl::forward(const torch::Tensor& image, const torch::Tensor& viewport)
{
  return torch::sigmoid(body->forward(torch::cat({ image, viewport }, 1)));
}

// --- decoder -----------------------------------------------------------------------------

DecoderImpl::DecoderImpl(int latent, int regions, int outputsPerRegion)
  : outputs(outputsPerRegion)
{
  body = register_module("body",
    nn::Sequential(nn::Linear(latent, 128), nn::ReLU(), nn::Linear(128, 128), nn::ReLU(),
      nn::Linear(128, outputs * regions)));
}

torch::Tensor DecoderImpl::forward(const torch::Tensor& z)
{
  return body->forward(z).view({ z.size(0), -1, outputs });
}

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

// --- helpers -----------------------------------------------------------------------------

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

std::vector<std::vector<std::int64_t>> shapes(nn::Module& mod)
{
  std::vector<std::vector<std::int64_t>> out;
  for (const auto& p : mod.named_parameters())
    out.push_back(p.value().sizes().vec());
  for (const auto& b : mod.named_buffers())
    out.push_back(b.value().sizes().vec());
  return out;
}

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

void onTorchThreads(int n, const std::function<void(int threadId)>& worker)
{
#pragma omp parallel num_threads(n)
  worker(omp_get_thread_num());
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

} // namespace neural
} // namespace ddg
