// NeuralDesignModelInternals.h: what a NeuralDesignModel holds (its networks, the decoder's layout
// and volume, a loaded bundle's designs). PRIVATE to Core/Neural (includes libtorch through
// NeuralNetworks.h): shared by the model, its training and its bundle I/O.
#pragma once

#include "Design/DecoderLayout.h"
#include "Neural/NeuralDesignModel.h"
#include "Neural/NeuralNetworks.h"
#include "Render/DifferentiableRenderer.h"

#include <memory>
#include <string>

namespace ddg
{

struct NeuralDesignModel::Internals
{
  NetworkConfig Config;
  neural::Analyzer A{ nullptr };
  neural::Renderer R{ nullptr };      // U-Net only
  neural::Discriminator D{ nullptr }; // U-Net only (training)
  neural::Decoder Dec{ nullptr };     // decoder only
  // decoder: what its outputs mean, and the volume it is shown on
  DecoderLayout Layout; // regions and spec
  TrainingDesigns Designs;
  std::string Fingerprint;
  std::shared_ptr<DifferentiableRenderer> Diff; // its caster() renders the decoded TFs

  bool decoder() const { return Config.kind == "decoder"; }
  /// What turns a latent into an image: the decoder or the U-Net renderer.
  torch::nn::Module& generator()
  {
    return decoder() ? static_cast<torch::nn::Module&>(*Dec) : static_cast<torch::nn::Module&>(*R);
  }
};

namespace neural
{
/// The analyzer's images of the batch `sel` (float, 0..255): `rgb`'s images at V_exp, those that
/// otherViewDraw picks replaced by `other`'s ground truth at V_view (premultiplied RGBA; undefined
/// when opt.otherViewFraction is 0) composed over black or white (NeuralTrainingInputs.cxx).
torch::Tensor analyzerInput(const torch::Tensor& rgb, const torch::Tensor& other,
  const torch::Tensor& sel, const TrainOptions& opt, int iteration);
} // namespace neural

} // namespace ddg
