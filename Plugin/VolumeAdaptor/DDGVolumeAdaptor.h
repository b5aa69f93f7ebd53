// DDGVolumeAdaptor.h: VTK <-> Core conversions and volume files, shared by the filters, the `ddg`
// program, the reconstruction tests and the benchmarks (ddg::VolumeAdaptor: no libtorch).
#pragma once

#include "Image/Image.h"
#include "Volume/Volume.h"

#include <cstdint>
#include <string>

class vtkDataArray;
class vtkImageData;

namespace ddg
{

/// Converts point-data scalars of an image to a Core volume (dims, origin, spacing, original
/// scalar type kept). `array` may be null: the point scalars are used. Throws ddg::Error for
/// no/empty data, cell data, a multi-component array or a non-numeric array. A non-identity
/// direction matrix throws too (ParaView 5.11's volume mapper and Core both assume axis-aligned).
Volume toCoreVolume(vtkImageData* image, vtkDataArray* array = nullptr);

/// The version of what toCoreVolume reads: the array's identity, modification time, memory and
/// layout, the point ghosts' identity and time, and the image's geometry (extent, origin,
/// spacing, direction), hashed; 0 without an image. Values written into the array in place need
/// `array->Modified()`, as VTK asks of any change a pipeline should see. The image's
/// own modification time is not used: ParaView hands a filter its input through a post filter
/// that copies the same arrays into it again at every request, so it changes while nothing
/// that the volume is made of does (the filters' caches would open the bundle at every query).
std::uint64_t volumeVersion(vtkImageData* image, vtkDataArray* array = nullptr);

/// Reads a volume file: .vti, .vtk (legacy structured points), .nrrd/.nhdr, .mha/.mhd,
/// .nii/.nii.gz through ParaView's bundled VTK readers, and the project's raw(.gz) + JSON
/// pairs through Core. `arrayName` selects a point array (empty: the active scalars).
/// Throws ddg::Error with the path and the reason.
Volume readVolumeFile(const std::string& path, const std::string& arrayName = "");

/// Fills a 2D vtkImageData (width x height x 1, VTK's bottom-up rows) from a premultiplied RGBA
/// render: point array "RGBA" (float, premultiplied) and "Image" (unsigned char RGB over
/// `background`, ParaView's compositing), "Image" being the active scalars.
void toVTKImage(
  const Image& premultipliedRGBA, const std::array<double, 3>& background, vtkImageData* output);

} // namespace ddg
