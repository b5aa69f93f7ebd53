// QueryKey.h: the key a query's nearest designs are found by — the latent seen through a map
// that keeps what tells designs apart and leaves out what changes with the camera, learnt from
// pairs of one design's images from two views — and its file in a bundle. Two fits: linear
// discriminant analysis and, given enough pairs, a small network trained contrastively
// (QueryKeyTraining.cxx: its forward and backward pass in Eigen, checked against finite
// differences in the tests).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ddg
{

/// Components the linear key keeps (chosen on Tooth's validation designs,
/// Documentation/DesignSpaces.md "Users' pictures"), the view pairs a build fits its key on,
/// and the pairs from which the contrastive network replaces the linear fit (below them it
/// does worse, measured on the same validation designs).
constexpr int kQueryKeyComponents = 12;
constexpr int kQueryKeyPairs = 2000;
constexpr int kContrastiveKeyPairs = 1000;
/// Its file in a bundle (saveBundle removes it: a key of other weights no longer holds).
constexpr const char* kQueryKeyFileName = "query_key.json";

/// One affine layer of a key: out = weights * in + bias (weights rows x cols, row-major; bias
/// rows values, or empty for none).
struct QueryKeyLayer
{
  int rows = 0, cols = 0;
  std::vector<float> weights, bias;
};

/// key = layers applied in turn to the latent, standardised first when `mean` is not empty
/// ((z - mean) / scale), with GELU between layers, scaled to unit length when `normalized`.
/// Empty: no key, latents compared as they are.
struct QueryKey
{
  std::string method; ///< "lda" or "contrastive"
  int dim = 0;        ///< latent values in
  int components = 0; ///< key values out (the last layer's rows)
  int pairs = 0;      ///< view pairs it was fitted on
  std::vector<float> mean, scale;
  std::vector<QueryKeyLayer> layers;
  bool normalized = false;

  bool empty() const { return layers.empty(); }
  /// The keys of `count` latents of `dim` values each (count x components; the latents as they
  /// are when the key is empty). Throws ddg::Error when `dim` is not the key's.
  std::vector<float> apply(const float* latents, size_t count, int dim) const;
  /// Throws ddg::Error when the sizes do not chain or a value is not finite.
  void validate() const;
};

/// The linear key fitted on n pairs of latents of one design each (own: its image at one view,
/// as the outline holds it; other: its image from another view, as a query sees it), each n x
/// dim: the within-design scatter of own - other is whitened, and the `components` directions
/// along which the own latents spread most after it are kept. Throws ddg::Error for sizes that
/// do not match, components outside 1..dim, or fewer than 2 x dim pairs (too few to estimate it).
QueryKey fitQueryKey(
  const std::vector<float>& own, const std::vector<float>& other, int dim, int components);

/// The contrastive key's network and training, chosen on Tooth's validation designs
/// (Documentation/DesignSpaces.md "The contrastive query key"): the latent standardised, two
/// hidden layers of GELU, a unit-length key; InfoNCE over batches of view pairs (each pair's
/// other view must pick its own view among the batch's, and the other way round), AdamW with a
/// cosine schedule to 0.
struct ContrastiveKeyOptions
{
  int hidden = 256;
  int components = 32;
  double temperature = 0.2;
  int epochs = 60;
  int batch = 256;
  double learningRate = 2e-3;
  double weightDecay = 1e-4;
  std::uint64_t seed = 1;
};

/// The contrastive key fitted on n pairs (own, other: n x dim each, as fitQueryKey).
/// `progress(fraction)` returning false cancels (ddg::Cancelled). Throws ddg::Error for
/// sizes that do not match, bad options, or fewer than 2 x dim pairs.
QueryKey fitContrastiveQueryKey(const std::vector<float>& own, const std::vector<float>& other,
  int dim, const ContrastiveKeyOptions& options = {},
  const std::function<bool(double)>& progress = {});

/// The contrastive loss of one batch (InfoNCE both ways, over `batch` pairs in own, other) and,
/// into `gradient` (one vector per layer: weights then bias), its gradient with respect to the
/// key's layers; the key must be a contrastive one. For the tests' finite-difference check.
double contrastiveKeyLoss(const QueryKey& key, const float* own, const float* other, int batch,
  double temperature, std::vector<std::vector<float>>* gradient);

/// `query_key.json` in a bundle directory.
std::string queryKeyFile(const std::string& bundleDir);
/// Writes a key as JSON ({"format": "ddg-query-key", "version": 2, "method", "dim",
/// "components", "pairs", "mean", "scale", "layers": [{"rows", "cols", "weights", "bias"}],
/// "normalized"}), atomically. Throws ddg::Error on failure.
void writeQueryKey(const QueryKey& key, const std::string& path);
/// Reads a key (version 2, or version 1's {"matrix"}: a linear key); throws ddg::Error naming
/// the file when it is not a valid key file.
QueryKey readQueryKey(const std::string& path);

} // namespace ddg
