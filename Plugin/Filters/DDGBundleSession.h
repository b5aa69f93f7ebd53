// DDGBundleSession.h: the filters' side of Core's bundle session (Gallery/BundleSession.h): the
// session of a bundle for the filter's input volume, reopened when the bundle directory or the
// input's data changes.
#pragma once

#include "DDGFiltersModule.h" // export macro
#include "Gallery/BundleSession.h"

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

} // namespace ddg
