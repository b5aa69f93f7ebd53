// DesignValidity.cxx: random latents next to their nearest training designs.
#include "Neural/DesignValidity.h"

#include "Common/Error.h"
#include "Image/ImageMetrics.h"

#include <cmath>
#include <limits>
#include <random>

namespace ddg
{

ValidityReport designSpaceValidity(
  NeuralDesignModel& model, const Volume& volume, const View& view, int count, std::uint64_t seed)
{
  const auto& d = model.trainingDesigns();
  if (count < 1)
    throw Error("design-space validity needs at least one random latent");
  if (d.count() < 1)
    throw Error("design-space validity needs a model bundle with its training designs");
  if (model.config().kind == "decoder")
    model.attachVolume(volume);
  const int n = d.count(), k = d.latent;
  // spread of the training latents
  std::vector<double> mean(k, 0.0), sd(k, 0.0);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < k; ++c)
      mean[c] += d.latentOf(i)[c] / static_cast<double>(n);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < k; ++c)
      sd[c] += (d.latentOf(i)[c] - mean[c]) * (d.latentOf(i)[c] - mean[c]) / n;
  for (double& s : sd)
    s = std::sqrt(s);

  const RayCaster caster(volume);
  const int dims = model.spec().dimensions;
  const auto gradientRange =
    dims == 2 ? volume.gradientMagnitudeRange() : std::array<double, 2>{ 0.0, 1.0 };
  auto rayCast = [&](const std::vector<GaussianPrimitive>& tf)
  {
    return compositeOverBackground(
      renderDesign(caster, tf, dims, gradientRange, view), { 0.5, 0.5, 0.5 });
  };
  const Image viewport = renderDesign(
    caster, auxiliaryPrimitives(model.spec(), model.regions()), dims, gradientRange, view);

  ValidityReport report;
  std::vector<Image> cells;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int r = 0; r < count; ++r)
  {
    ValidityRow row;
    row.latent.resize(k);
    double norm = 0;
    for (int c = 0; c < k; ++c)
    {
      row.latent[c] = static_cast<float>(mean[c] + sd[c] * normal(rng));
      norm += row.latent[c] * row.latent[c];
    }
    row.cosine = -2;
    row.euclidean = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i)
    {
      double dot = 0, dist = 0, other = 0;
      for (int c = 0; c < k; ++c)
      {
        const double v = d.latentOf(i)[c];
        dot += v * row.latent[c];
        other += v * v;
        dist += (v - row.latent[c]) * (v - row.latent[c]);
      }
      const double cosine = dot / std::max(1e-30, std::sqrt(norm * other));
      if (cosine > row.cosine)
      {
        row.cosine = cosine;
        row.nearestCosine = i;
      }
      if (dist < row.euclidean)
      {
        row.euclidean = dist;
        row.nearestEuclidean = i;
      }
    }
    row.euclidean = std::sqrt(row.euclidean);
    const Image design =
      compositeOverBackground(model.renderAt(row.latent, viewport, view), { 0.5, 0.5, 0.5 });
    const Image byCosine = rayCast(d.tfs[static_cast<size_t>(row.nearestCosine)]);
    const Image byDistance = rayCast(d.tfs[static_cast<size_t>(row.nearestEuclidean)]);
    row.psnrCosine = std::min(99.0, psnr(design, byCosine));
    row.psnrEuclidean = std::min(99.0, psnr(design, byDistance));
    report.meanPsnrCosine += row.psnrCosine / count;
    report.meanPsnrEuclidean += row.psnrEuclidean / count;
    cells.insert(cells.end(), { design, byCosine, byDistance });
    report.rows.push_back(std::move(row));
  }
  report.sheet = tileImages(cells, 3);
  return report;
}

} // namespace ddg
