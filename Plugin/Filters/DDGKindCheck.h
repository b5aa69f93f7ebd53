// DDGKindCheck.h: the kind check of a filter's picture against its volume (ddg::KindChecker):
// what DDG Query and DDG Reconstruct Transfer Function (Carry Look) add to their results.
#pragma once

#include "DDGFiltersModule.h" // export macro
#include "DDGPieces.h"        // InputStamp

#include <cstdint>
#include <memory>
#include <string>

class vtkAlgorithm;
class vtkDataArray;
class vtkFieldData;
class vtkImageData;

namespace ddg
{
struct Image;
class Volume;
class KindChecker;
class RankGroup;
struct RankVolume;

/// With the kind network `dir` (empty: nothing is done; a build without libtorch: nothing
/// either): the field "Kind" on `fd`, JSON {"agreement", "threshold", "differs", "picture_like",
/// "volume_like"}, and a warning from `filter` (Output Messages) when the picture may show a
/// volume of another kind. `checker` (created on first use) keeps the network and each volume's
/// reference for the next run. A network that cannot be read (any failure of the check) is a
/// warning, not an error; the filter's progress text is "kind" meanwhile and its AbortExecute
/// cancels (ddg::Cancelled is thrown on, as the filter's own cancel).
/// `fingerprint`, when known, is the volume's volumeFingerprint (not computed again).
DDGFILTERS_EXPORT void addKindCheck(vtkAlgorithm* filter, vtkFieldData* fd,
  std::shared_ptr<KindChecker>& checker, const std::string& dir, const Image& picture,
  const Volume& volume, const std::string& fingerprint = {});

/// addKindCheck under MPI, collective over `ranks` (every rank calls it with the same `dir`): the
/// field and the warning on the first rank. `firstRankFingerprint` is the whole volume's
/// (fingerprintOnRanks of `pieces`, on the first rank; RankVolumeCache or RanksFingerprint keep
/// it). When the first rank keeps no reference of the volume (in memory or on disk), every rank
/// streams its points to it, which assembles the design-space volume (designSpaceInputOnRanks,
/// kMaxDesignSpaceVoxels) and draws the reference's exemplars from it; no other rank holds more
/// than its piece and a slab. A reference drawn from a volume averaged down is kept under the
/// fingerprint and the factor, apart from one process's of the whole. `picture` is read on the
/// first rank only. Failures are warnings on the first rank; the user's Abort stops every rank
/// (ddg::Cancelled on the first, RankFailed elsewhere).
DDGFILTERS_EXPORT void addKindCheckOnRanks(vtkAlgorithm* filter, vtkFieldData* fd,
  std::shared_ptr<KindChecker>& checker, const std::string& dir, const Image& picture,
  const RankGroup& ranks, const RankVolume& pieces, const std::string& firstRankFingerprint);

/// A filter's whole-volume fingerprint under MPI (fingerprintOnRanks: on the first rank, empty
/// elsewhere), kept between its runs and streamed again only when any rank's input or array
/// changed (collective).
class DDGFILTERS_EXPORT RanksFingerprint
{
public:
  const std::string& get(
    const RankGroup& ranks, const RankVolume& pieces, vtkImageData* input, vtkDataArray* array);

private:
  InputStamp Stamp;
  std::string Value;
};

} // namespace ddg
