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

} // namespace ddg
