// NeuralTrainingInputs.cxx: what the analyzer sees in training — the images at V_exp, some of
// them replaced by the exemplar's other view (TrainOptions::otherViewFraction) — and how many
// rays the image loss casts (adaptiveImageRays).
#include "Neural/NeuralDesignModelInternals.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace ddg
{

std::vector<int> otherViewDraw(int count, double fraction, std::uint64_t seed, int iteration)
{
  std::mt19937_64 draw(seed * 0xD1B54A32D192ED03ull + static_cast<std::uint64_t>(iteration));
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<int> out(static_cast<size_t>(std::max(0, count)), -1);
  for (int& o : out)
  {
    const bool other = u(draw) < fraction;
    const int background = u(draw) < 0.5 ? 0 : 1;
    if (other)
      o = background;
  }
  return out;
}

int adaptiveImageRays(int maxRays, double imageSeconds, double restSeconds)
{
  if (maxRays < 1)
    throw Error("adaptive image-loss rays need at least one ray to start from");
  const int floor = std::max(1, maxRays / 4);
  if (!(imageSeconds > 0) || !(restSeconds >= 0) || restSeconds >= imageSeconds)
    return maxRays;
  const double halvings = std::round(-std::log2(std::max(restSeconds / imageSeconds, 1e-9)));
  return std::max(floor, static_cast<int>(maxRays / std::pow(2.0, halvings)));
}

namespace neural
{

// The analyzer's images of the batch `sel` (float, 0..255): the images at V_exp, those that
// otherViewDraw picks replaced by the ground truth at V_view (`other`, premultiplied RGBA)
// composed over black or white and rounded as an 8-bit image is.
torch::Tensor analyzerInput(const torch::Tensor& rgb, const torch::Tensor& other,
  const torch::Tensor& sel, const TrainOptions& opt, int iteration)
{
  auto x = rgb.index_select(0, sel).to(torch::kFloat32);
  if (!other.defined())
    return x;
  const std::vector<int> draw =
    otherViewDraw(static_cast<int>(sel.size(0)), opt.otherViewFraction, opt.seed, iteration);
  std::vector<std::int64_t> rows;
  std::vector<float> backgrounds;
  for (size_t b = 0; b < draw.size(); ++b)
    if (draw[b] >= 0)
    {
      rows.push_back(static_cast<std::int64_t>(b));
      backgrounds.push_back(static_cast<float>(draw[b]));
    }
  if (rows.empty())
    return x;
  const auto where = torch::tensor(rows, torch::kInt64);
  const auto v = other.index_select(0, sel.index_select(0, where)).to(torch::kFloat32);
  const auto background = torch::tensor(backgrounds, torch::kFloat32).view({ -1, 1, 1, 1 });
  const auto composed =
    (v.slice(1, 0, 3) + (255 - v.slice(1, 3, 4)) * background).round().clamp(0, 255);
  x.index_copy_(0, where, composed);
  return x;
}

} // namespace neural
} // namespace ddg
