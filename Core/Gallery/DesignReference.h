// DesignReference.h: the one grammar for naming a design on the command line and in scripts
// ("row:N", "image:PATH", "latent:PATH", "history:PATH"), the latent files it reads, and the
// history that leads to a reference.
#pragma once

#include "Gallery/History.h"

#include <string>
#include <vector>

namespace ddg
{

/// A parsed design reference.
///   row:N          row N of the bundle's outline
///   image:PATH     the analyzer's latent of an image, framed as a query
///   latent:PATH    a latent JSON {"latent": [...]} (what --out-latent writes)
///   history:PATH   where a history file's path ends
struct DesignReference
{
  enum class Kind
  {
    Row,
    Image,
    Latent,
    History
  };
  Kind kind = Kind::Row;
  int row = -1;     ///< Row
  std::string path; ///< Image, Latent, History
  std::string text; ///< the reference as given (for messages)

  /// Throws ddg::Error naming the grammar for an unknown kind, an empty argument or a row that
  /// is not an integer.
  static DesignReference parse(const std::string& reference);

  /// The design's latent in `gallery` (reads the file it names; a latent of another size is
  /// refused as another model's).
  std::vector<float> resolve(const DesignGallery& gallery) const;

  /// The history that leads to it: row -> [pick], image -> [query], latent -> [latent],
  /// history -> its steps.
  DesignHistory history() const;
};

/// A latent file's latent ({"latent": [...]}). Throws ddg::Error for a missing or malformed file.
std::vector<float> readLatentFile(const std::string& path);
/// Writes {"latent": [...]} atomically.
void writeLatentFile(const std::vector<float>& latent, const std::string& path);

} // namespace ddg
