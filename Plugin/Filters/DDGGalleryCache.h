// DDGGalleryCache.h: a model bundle, its volume and its outline loaded once for the filters that
// use the design gallery (vtkDDGQuery, vtkDDGDesignGallery), reloaded when the bundle directory
// or the input changes.
#pragma once

#include "DDGFiltersModule.h" // export macro
#include "Gallery/Gallery.h"

#include <vtkType.h>

#include <memory>
#include <string>

class vtkDataArray;
class vtkImageData;

namespace ddg
{

class DDGFILTERS_EXPORT GalleryCache
{
public:
  /// The gallery of `modelDirectory` for `input` (its `array`): loaded on first use, and again
  /// when the directory or the input's data changes. Throws ddg::Error as loadBundle,
  /// readLatentSet and toCoreVolume do (another volume's bundle, a missing outline, ...).
  DesignGallery& get(const std::string& modelDirectory, vtkImageData* input, vtkDataArray* array);

private:
  std::unique_ptr<Volume> Vol;
  std::unique_ptr<NeuralDesignModel> Model;
  std::unique_ptr<DesignGallery> Gallery;
  std::string Directory;
  vtkMTimeType InputTime = 0;
};

} // namespace ddg
