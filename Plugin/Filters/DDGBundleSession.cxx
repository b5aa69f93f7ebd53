// DDGBundleSession.cxx: the input's version and volume for Core's bundle session cache.
#include "DDGBundleSession.h"

#include "DDGVolumeAdaptor.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>

#include <algorithm>

namespace ddg
{

DesignGallery& galleryFor(BundleSessionCache& cache, const std::string& modelDirectory,
  vtkImageData* input, vtkDataArray* array)
{
  const vtkMTimeType version =
    std::max(input ? input->GetMTime() : 0, array ? array->GetMTime() : 0);
  return cache
    .get(modelDirectory, static_cast<std::uint64_t>(version),
      [&] { return toCoreVolume(input, array); })
    .gallery();
}

} // namespace ddg
