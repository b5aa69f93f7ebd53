// DDGGalleryCache.cxx: loads a bundle with its volume and outline for the gallery filters.
#include "DDGGalleryCache.h"

#include "DDGVolumeAdaptor.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>

#include <algorithm>

namespace ddg
{

DesignGallery& GalleryCache::get(
  const std::string& modelDirectory, vtkImageData* input, vtkDataArray* array)
{
  if (modelDirectory.empty())
    throw Error("no ModelDirectory set");
  const vtkMTimeType inputTime =
    std::max(input ? input->GetMTime() : 0, array ? array->GetMTime() : 0);
  if (!Gallery || Directory != modelDirectory || InputTime != inputTime)
  {
    Gallery.reset();
    Model.reset();
    Vol = std::make_unique<Volume>(toCoreVolume(input, array));
    Model = std::make_unique<NeuralDesignModel>(
      NeuralDesignModel::loadBundle(modelDirectory, volumeFingerprint(*Vol)));
    LatentSet latents;
    try
    {
      latents = readLatentSet(outlineFile(modelDirectory));
    }
    catch (const Error& e)
    {
      throw Error(std::string(e.what()) + " (build it with: ddg outline --model " + modelDirectory +
        " --volume VOLUME)");
    }
    Gallery = std::make_unique<DesignGallery>(*Model, *Vol, std::move(latents));
    Directory = modelDirectory;
    InputTime = inputTime;
  }
  return *Gallery;
}

} // namespace ddg
