// NeuralNetworks.h: the libtorch modules of the neural design model — the paper's Analyzer,
// Renderer (U-Net) and PatchGAN Discriminator, and the lean Decoder — with the tensor helpers
// they share. PRIVATE to Core/Neural: it includes <torch/torch.h>; no public header includes it.
#pragma once

#include "Image/Image.h"
#include "Neural/NeuralDesignModel.h"

#include <torch/torch.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ddg
{
namespace neural
{
namespace nn = torch::nn;

/// Analyzer: RGB image (N x 3 x S x S in [-1, 1]) -> latent TF (N x latent). 4x4 stride-2
/// blocks down to 4 x 4 (InstanceNorm on all but the first), then a 4x4 convolution to 1 x 1.
struct AnalyzerImpl : nn::Module
{
  nn::Sequential body;
  nn::Conv2d head{ nullptr };
  explicit AnalyzerImpl(const NetworkConfig& c);
  torch::Tensor forward(const torch::Tensor& x);
};
TORCH_MODULE(Analyzer);

/// Renderer: U-Net on the viewport image (N x 4 x S x S), the latent (N x latent) concatenated
/// at the 4 x 4 bottleneck; output premultiplied RGBA in [0, 1] (sigmoid).
struct RendererImpl : nn::Module
{
  std::vector<nn::Sequential> downs, ups;
  nn::Sequential bottleneck;
  nn::ConvTranspose2d last{ nullptr };
  int latent = 64;
  explicit RendererImpl(const NetworkConfig& c);
  torch::Tensor forward(const torch::Tensor& z, const torch::Tensor& viewport);
};
TORCH_MODULE(Renderer);

/// PatchGAN discriminator on (image, viewport) (N x 8 x S x S): a sigmoid per patch.
struct DiscriminatorImpl : nn::Module
{
  nn::Sequential body;
  explicit DiscriminatorImpl(const NetworkConfig& c);
  torch::Tensor forward(const torch::Tensor& image, const torch::Tensor& viewport);
};
TORCH_MODULE(Discriminator);

/// Decoder (lean variant): latent (N x latent) -> raw outputs (N x regions x outputsPerRegion):
/// per feature region (active logit, mean shift, stddev scale, r, g, b, opacity; 2D adds the
/// gradient mean shift and stddev), all but the logit squashed by squash().
struct DecoderImpl : nn::Module
{
  nn::Sequential body;
  int outputs = 7;
  DecoderImpl(int latent, int regions, int outputsPerRegion);
  torch::Tensor forward(const torch::Tensor& z);
};
TORCH_MODULE(Decoder);

/// Decoder outputs in [0, 1] (or [-1, 1] for the mean shifts) from raw values; the activity
/// logit (slot 0) stays raw.
torch::Tensor squash(const torch::Tensor& raw);

/// Xavier-normal convolution weights (4D), zero biases.
void xavier(nn::Module& m);

/// Shapes of every parameter and buffer (Module::load does not check them).
std::vector<std::vector<std::int64_t>> shapes(nn::Module& mod);

/// An archive's bytes. libtorch's save_to(path) throws from a destructor when the disk is full
/// (std::terminate); serializing to memory and writing with writeFileAtomic reports it instead.
std::string serialized(torch::serialize::OutputArchive& ar);

/// libtorch intra-op threads: `threads`, or all cores for 0.
void setThreads(int threads);

/// Runs parallelFor's workers (Common/Parallel.h) on libtorch's OpenMP threads. Work done
/// between libtorch's operations (the decoder's image loss) must run there: after an operation
/// those threads spin for some milliseconds, and new std::threads beside them share the cores
/// with the spinning (a decoder training step with the image loss 1.17x slower on 2 cores).
void onTorchThreads(int n, const std::function<void(int threadId)>& worker);

/// Image (any channels; converted to `channels`) -> float tensor channels x H x W.
torch::Tensor imageToTensor(const Image& img, int channels);
/// Float tensor C x H x W -> Image.
Image tensorToImage(const torch::Tensor& t);

} // namespace neural
} // namespace ddg
