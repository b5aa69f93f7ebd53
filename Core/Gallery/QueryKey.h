// QueryKey.h: the key a query's nearest designs are found by — the latent seen through a linear
// map that keeps what tells designs apart and leaves out what changes with the camera (linear
// discriminant analysis on pairs of one design's images from two views), and its file in a bundle.
#pragma once

#include <string>
#include <vector>

namespace ddg
{

/// Components the key keeps (chosen on Tooth's validation designs, Documentation/DesignSpaces.md
/// "Users' pictures"), and the view pairs a build fits it on.
constexpr int kQueryKeyComponents = 12;
constexpr int kQueryKeyPairs = 2000;
/// Its file in a bundle (saveBundle removes it: a key of other weights no longer holds).
constexpr const char* kQueryKeyFileName = "query_key.json";

/// key = matrix * latent: `components` x `dim`, row-major. Empty: no key, latents compared as
/// they are.
struct QueryKey
{
  int dim = 0;
  int components = 0;
  int pairs = 0; ///< view pairs it was fitted on
  std::vector<float> matrix;

  bool empty() const { return matrix.empty(); }
  /// The keys of `count` latents of `dim` values each (count x components; the latents as they
  /// are when the key is empty). Throws ddg::Error when `dim` is not the key's.
  std::vector<float> apply(const float* latents, size_t count, int dim) const;
};

/// Fits the key on n pairs of latents of one design each (own: its image at one view, as the
/// outline holds it; other: its image from another view, as a query sees it), each n x dim:
/// the within-design scatter of own - other is whitened, and the `components` directions along
/// which the own latents spread most after it are kept. Throws ddg::Error for sizes that do not
/// match, components outside 1..dim, or fewer than 2 x dim pairs (too few to estimate it).
QueryKey fitQueryKey(
  const std::vector<float>& own, const std::vector<float>& other, int dim, int components);

/// `query_key.json` in a bundle directory.
std::string queryKeyFile(const std::string& bundleDir);
/// Writes a key as JSON ({"format": "ddg-query-key", "version": 1, "dim", "components",
/// "pairs", "matrix"}), atomically. Throws ddg::Error on failure.
void writeQueryKey(const QueryKey& key, const std::string& path);
/// Reads a key; throws ddg::Error naming the file when it is not a valid key file.
QueryKey readQueryKey(const std::string& path);

} // namespace ddg
