// DDGKindCheck.h: the kind check of a filter's picture against its volume (ddg::KindChecker):
// what DDG Query and DDG Reconstruct Transfer Function (Carry Look) add to their results.
#pragma once

#include "DDGFiltersModule.h" // export macro

#include <memory>
#include <string>

class vtkAlgorithm;
class vtkFieldData;

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
DDGFILTERS_EXPORT void addKindCheck(vtkAlgorithm* filter, vtkFieldData* fd,
  std::shared_ptr<KindChecker>& checker, const std::string& dir, const Image& picture,
  const Volume& volume);

/// addKindCheck under MPI, collective over `ranks` (every rank calls it with the same `dir`): the
/// field and the warning on the first rank. When the first rank keeps no reference of the whole
/// volume (`firstRankFingerprint`, the first rank's fingerprintOnRanks of `pieces`, or empty on
/// every rank to have it computed here), every rank streams its points to the first, which
/// assembles the design-space volume (designSpaceInputOnRanks, kMaxDesignSpaceVoxels) and draws
/// the reference's exemplars from it; no other rank holds more than its piece and a slab.
/// `picture` is read on the first rank only. Failures are warnings on the first rank; the user's
/// Abort stops every rank (ddg::Cancelled on the first, RankFailed elsewhere).
DDGFILTERS_EXPORT void addKindCheckOnRanks(vtkAlgorithm* filter, vtkFieldData* fd,
  std::shared_ptr<KindChecker>& checker, const std::string& dir, const Image& picture,
  const RankGroup& ranks, const RankVolume& pieces, const std::string& firstRankFingerprint);

} // namespace ddg
