// QueryKey.cxx: the query key's fit (LDA on view pairs), its use and its file.
#include "Gallery/QueryKey.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Common/Parallel.h"
#include "Gallery/QueryKeyGelu.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

namespace ddg
{

std::vector<float> QueryKey::apply(const float* latents, size_t count, int latentDim) const
{
  if (empty())
    return std::vector<float>(latents, latents + count * static_cast<size_t>(latentDim));
  if (latentDim != dim)
    throw Error("the query key is for latents of " + std::to_string(dim) + " values, not " +
      std::to_string(latentDim) + " (another model's key)");
  using Matrix = QueryKeyMatrix;
  std::vector<float> out(count * static_cast<size_t>(components));
  // in blocks of rows, on every core (an outline's 50 000 latents at bundle load)
  constexpr std::int64_t kBlock = 2048;
  const auto blocks = static_cast<std::int64_t>((count + kBlock - 1) / kBlock);
  parallelFor(blocks, blocks > 1 ? 0 : 1,
    [&](std::int64_t b, int)
    {
      const auto first = b * kBlock;
      const auto n = std::min<std::int64_t>(kBlock, static_cast<std::int64_t>(count) - first);
      Matrix x = standardisedLatents(*this, latents + first * dim, n);
      for (size_t l = 0; l < layers.size(); ++l)
      {
        Matrix y = layerOutput(layers[l], x);
        if (l + 1 < layers.size())
          geluInPlace(y);
        x = std::move(y);
      }
      if (normalized)
        x.rowwise().normalize();
      Eigen::Map<Matrix>(out.data() + first * components, n, components) = x;
    });
  return out;
}

void QueryKey::validate() const
{
  if (dim < 1 || layers.empty() || components != layers.back().rows)
    throw Error("its sizes do not match");
  if (!mean.empty() && (mean.size() != static_cast<size_t>(dim) || scale.size() != mean.size()))
    throw Error("its standardisation does not match its latents");
  int in = dim;
  for (const auto& layer : layers)
  {
    if (layer.cols != in || layer.rows < 1 ||
      layer.weights.size() != static_cast<size_t>(layer.rows) * layer.cols ||
      (!layer.bias.empty() && layer.bias.size() != static_cast<size_t>(layer.rows)))
      throw Error("its layers' sizes do not chain");
    in = layer.rows;
    for (const auto* values : { &layer.weights, &layer.bias })
      for (float v : *values)
        if (!std::isfinite(v))
          throw Error("it holds a non-finite value");
  }
  for (float v : scale)
    if (!(v > 0) || !std::isfinite(v))
      throw Error("its scale is not positive");
  for (float v : mean)
    if (!std::isfinite(v))
      throw Error("it holds a non-finite value");
}

QueryKey fitQueryKey(
  const std::vector<float>& own, const std::vector<float>& other, int dim, int components)
{
  if (dim < 1 || components < 1 || components > dim)
    throw Error("a query key needs 1..dim components");
  if (own.size() != other.size() || own.size() % static_cast<size_t>(dim) != 0)
    throw Error("a query key's pairs need as many own as other latents, dim values each");
  const auto n = static_cast<Eigen::Index>(own.size() / static_cast<size_t>(dim));
  if (n < 2 * dim)
    throw Error("a query key needs at least " + std::to_string(2 * dim) + " view pairs, not " +
      std::to_string(n));
  using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::MatrixXd zo = Eigen::Map<const Matrix>(own.data(), n, dim).cast<double>();
  const Eigen::MatrixXd zq = Eigen::Map<const Matrix>(other.data(), n, dim).cast<double>();
  // within-design scatter (what a change of view does to the latent), whitened
  const Eigen::MatrixXd d = zo - zq;
  Eigen::MatrixXd within = d.transpose() * d / static_cast<double>(n);
  within += 1e-6 * (within.trace() / dim + 1e-12) * Eigen::MatrixXd::Identity(dim, dim);
  const Eigen::LLT<Eigen::MatrixXd> llt(within);
  if (llt.info() != Eigen::Success)
    throw Error("the query key's view pairs give no usable scatter");
  const Eigen::MatrixXd whiten = llt.matrixL().solve(Eigen::MatrixXd::Identity(dim, dim)); // L^-1
  // between designs: the own latents' spread in the whitened space, its largest directions
  Eigen::MatrixXd y = zo * whiten.transpose();
  y.rowwise() -= y.colwise().mean();
  const Eigen::MatrixXd between = y.transpose() * y / static_cast<double>(n);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(between);
  const Eigen::MatrixXd axes = eigen.eigenvectors().rightCols(components); // ascending order
  const Eigen::MatrixXd m = axes.rowwise().reverse().transpose() * whiten;
  if (!m.allFinite())
    throw Error("the query key's fit is not finite");
  QueryKey key;
  key.method = "lda";
  key.dim = dim;
  key.components = components;
  key.pairs = static_cast<int>(n);
  QueryKeyLayer layer;
  layer.rows = components;
  layer.cols = dim;
  layer.weights.resize(static_cast<size_t>(components) * dim);
  Eigen::Map<Matrix>(layer.weights.data(), components, dim) = m.cast<float>();
  key.layers.push_back(std::move(layer));
  return key;
}

std::string queryKeyFile(const std::string& bundleDir)
{
  return (std::filesystem::path(bundleDir) / kQueryKeyFileName).string();
}

void writeQueryKey(const QueryKey& key, const std::string& path)
{
  if (key.empty())
    throw Error("an empty query key cannot be written");
  key.validate();
  nlohmann::json layers = nlohmann::json::array();
  for (const auto& l : key.layers)
    layers.push_back(
      { { "rows", l.rows }, { "cols", l.cols }, { "weights", l.weights }, { "bias", l.bias } });
  const nlohmann::json j = { { "format", "ddg-query-key" }, { "version", 2 },
    { "method", key.method }, { "dim", key.dim }, { "components", key.components },
    { "pairs", key.pairs }, { "mean", key.mean }, { "scale", key.scale }, { "layers", layers },
    { "normalized", key.normalized } };
  writeFileAtomic(path, j.dump() + "\n", "query key");
}

QueryKey readQueryKey(const std::string& path)
{
  const std::string text = readTextFile(path, "query key");
  try
  {
    const auto j = nlohmann::json::parse(text);
    const int version = j.at("version").get<int>();
    if (j.at("format").get<std::string>() != "ddg-query-key" || (version != 1 && version != 2))
      throw Error("not a version-1 or -2 ddg-query-key");
    QueryKey key;
    key.dim = j.at("dim").get<int>();
    key.components = j.at("components").get<int>();
    key.pairs = j.at("pairs").get<int>();
    if (version == 1) // a linear key: one matrix
    {
      key.method = "lda";
      QueryKeyLayer layer;
      layer.rows = key.components;
      layer.cols = key.dim;
      layer.weights = j.at("matrix").get<std::vector<float>>();
      key.layers.push_back(std::move(layer));
    }
    else
    {
      key.method = j.at("method").get<std::string>();
      key.mean = j.at("mean").get<std::vector<float>>();
      key.scale = j.at("scale").get<std::vector<float>>();
      key.normalized = j.at("normalized").get<bool>();
      for (const auto& l : j.at("layers"))
        key.layers.push_back({ l.at("rows").get<int>(), l.at("cols").get<int>(),
          l.at("weights").get<std::vector<float>>(), l.at("bias").get<std::vector<float>>() });
    }
    key.validate();
    return key;
  }
  catch (const std::exception& e)
  {
    throw Error("the query key '" + path + "' is not valid: " + e.what());
  }
}

} // namespace ddg
