// QueryKey.cxx: the query key's fit (LDA on view pairs), its use and its file.
#include "Gallery/QueryKey.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"

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
  using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const Matrix> m(matrix.data(), components, dim);
  const Eigen::Map<const Matrix> z(latents, static_cast<Eigen::Index>(count), dim);
  std::vector<float> out(count * static_cast<size_t>(components));
  Eigen::Map<Matrix>(out.data(), static_cast<Eigen::Index>(count), components) = z * m.transpose();
  return out;
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
  key.dim = dim;
  key.components = components;
  key.pairs = static_cast<int>(n);
  key.matrix.resize(static_cast<size_t>(components) * dim);
  Eigen::Map<Matrix>(key.matrix.data(), components, dim) = m.cast<float>();
  return key;
}

std::string queryKeyFile(const std::string& bundleDir)
{
  return (std::filesystem::path(bundleDir) / kQueryKeyFileName).string();
}

void writeQueryKey(const QueryKey& key, const std::string& path)
{
  if (key.empty() || key.matrix.size() != static_cast<size_t>(key.components) * key.dim)
    throw Error("an empty or malformed query key cannot be written");
  const nlohmann::json j = { { "format", "ddg-query-key" }, { "version", 1 }, { "dim", key.dim },
    { "components", key.components }, { "pairs", key.pairs }, { "matrix", key.matrix } };
  writeFileAtomic(path, j.dump() + "\n", "query key");
}

QueryKey readQueryKey(const std::string& path)
{
  const std::string text = readTextFile(path, "query key");
  try
  {
    const auto j = nlohmann::json::parse(text);
    if (j.at("format").get<std::string>() != "ddg-query-key" || j.at("version").get<int>() != 1)
      throw Error("not a version-1 ddg-query-key");
    QueryKey key;
    key.dim = j.at("dim").get<int>();
    key.components = j.at("components").get<int>();
    key.pairs = j.at("pairs").get<int>();
    key.matrix = j.at("matrix").get<std::vector<float>>();
    if (key.dim < 1 || key.components < 1 || key.components > key.dim ||
      key.matrix.size() != static_cast<size_t>(key.components) * key.dim)
      throw Error("its sizes do not match");
    for (float v : key.matrix)
      if (!std::isfinite(v))
        throw Error("it holds a non-finite value");
    return key;
  }
  catch (const std::exception& e)
  {
    throw Error("the query key '" + path + "' is not valid: " + e.what());
  }
}

} // namespace ddg
