// DesignValidity.h: the paper's design-space validity check (§7.2.2). Random latents, drawn
// from the spread of the training latents, are rendered by the model next to the training
// designs nearest to them (by cosine similarity and by Euclidean distance): a valid design space
// maps random latents to designs like the ones it was trained on.
#pragma once

#include "Neural/NeuralDesignModel.h"

namespace ddg
{

struct ValidityRow
{
  std::vector<float> latent;
  int nearestCosine = -1, nearestEuclidean = -1; ///< indices of training designs
  double cosine = 0, euclidean = 0;              ///< their similarity / distance
  double psnrCosine = 0, psnrEuclidean = 0;      ///< model render vs. that design's ray cast
};

struct ValidityReport
{
  std::vector<ValidityRow> rows;
  double meanPsnrCosine = 0, meanPsnrEuclidean = 0;
  /// rows x 3: model render of the random latent | nearest by cosine | nearest by Euclidean
  /// distance (ray casts of those training TFs), all at `view` over mid-grey.
  Image sheet;
};

/// Needs a loaded bundle (its training designs) and its volume (attached to a decoder model
/// here). Random latents: each component normal with the training latents' mean and standard
/// deviation, deterministic from `seed`. Throws ddg::Error for count < 1 or a model without
/// training designs.
ValidityReport designSpaceValidity(NeuralDesignModel& model, const Volume& volume, const View& view,
  int count, std::uint64_t seed = 1);

} // namespace ddg
