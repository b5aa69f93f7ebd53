// DDGBundleSession.h: the filters' side of Core's bundle session (Gallery/BundleSession.h): the
// session of a bundle for the filter's input volume, reopened when the bundle directory or the
// input's data changes.
#pragma once

#include "DDGFiltersModule.h" // export macro
#include "DDGPieces.h"
#include "Gallery/BundleSession.h"

#include <functional>
#include <memory>

#include <string>

class vtkDataArray;
class vtkImageData;

namespace ddg
{

/// The gallery of `modelDirectory` for `input`'s `array`, kept in `cache`. Throws ddg::Error as
/// BundleSessionCache::get and toCoreVolume do (no directory, another volume's bundle, a
/// missing outline, not a volume).
DDGFILTERS_EXPORT DesignGallery& galleryFor(BundleSessionCache& cache,
  const std::string& modelDirectory, vtkImageData* input, vtkDataArray* array);

/// The gallery of a filter's bundle, kept between its executions: in one process over the
/// input volume (galleryFor), under MPI over the ranks' pieces.
class DDGFILTERS_EXPORT FilterGallery
{
public:
  /// Runs `work` with the gallery of `bundleDir` for `input`'s `array`. With `ranks` (a
  /// collective request; `wholeExtent` the input's whole extent) `work` runs on the first rank,
  /// while the other ranks render their pieces of its designs (renderForFirstRank): the pieces
  /// and the whole's fingerprint (RankVolumeCache), the bundle refused when it belongs to another
  /// volume. A failure anywhere reaches every rank (RankGroup::step).
  void run(const RankGroup* ranks, vtkImageData* input, vtkDataArray* array,
    const int wholeExtent[6], const std::string& bundleDir,
    const std::function<void(DesignGallery& gallery)>& work);
  /// Collective, after `run` with the same arguments: the pieces it used (kept).
  const RankVolume& pieces(
    const RankGroup& ranks, vtkImageData* input, vtkDataArray* array, const int wholeExtent[6])
  {
    return Pieces.get(ranks, input, array, wholeExtent);
  }
  /// After `run`: the volume's fingerprint (the session's, computed when it opened); under MPI
  /// the whole volume's on the first rank (empty elsewhere).
  const std::string& fingerprint(const RankGroup* ranks) const;

private:
  BundleSessionCache Sessions; // one process, or the first rank's over the pieces
  RankVolumeCache Pieces;
  std::shared_ptr<RanksDesignVolume> Space = std::make_shared<RanksDesignVolume>();
};

} // namespace ddg
