// DDGVolumeAdaptor.cxx: vtkImageData <-> ddg::Volume / ddg::Image, and volume file reading.
#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Common/Hash.h"
#include "Volume/VolumeIO.h"

#include <vtkAlgorithm.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkMatrix3x3.h>
#include <vtkMetaImageReader.h>
#include <vtkNIFTIImageReader.h>
#include <vtkNew.h>
#include <vtkNrrdReader.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStructuredPointsReader.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLImageDataReader.h>

#include <cmath>
#include <fstream>
#include <memory>

namespace ddg
{
namespace
{

ScalarType scalarTypeOf(int vtkType)
{
  switch (vtkType)
  {
    case VTK_UNSIGNED_CHAR:
      return ScalarType::UInt8;
    case VTK_CHAR:
    case VTK_SIGNED_CHAR:
      return ScalarType::Int8;
    case VTK_UNSIGNED_SHORT:
      return ScalarType::UInt16;
    case VTK_SHORT:
      return ScalarType::Int16;
    case VTK_UNSIGNED_INT:
      return ScalarType::UInt32;
    case VTK_INT:
      return ScalarType::Int32;
    case VTK_FLOAT:
      return ScalarType::Float32;
    case VTK_DOUBLE:
      return ScalarType::Float64;
    case VTK_LONG:
    case VTK_LONG_LONG:
    case VTK_ID_TYPE:
    case VTK_UNSIGNED_LONG:
    case VTK_UNSIGNED_LONG_LONG:
      return ScalarType::Float64;
    default:
      throw Error("volume array has a non-numeric type");
  }
}

// Class-agnostic error capture for a reader: VTK readers report errors through the output
// window and ErrorEvent; we turn them into one ddg::Error.
class ReaderErrors
{
public:
  explicit ReaderErrors(vtkAlgorithm* reader)
  {
    reader->AddObserver(vtkCommand::ErrorEvent, this, &ReaderErrors::onError);
  }
  void onError(vtkObject*, unsigned long, void* data)
  {
    if (data && Message.empty())
    {
      Message = static_cast<const char*>(data);
    }
  }
  std::string Message;
};

} // namespace

std::uint64_t volumeVersion(vtkImageData* image, vtkDataArray* array)
{
  if (!image)
    return 0;
  if (!array)
    array = image->GetPointData()->GetScalars();
  Fnv1a hash;
  // the array: which one, when modified, and its memory (re-pointed or resized without a new
  // modification time: VTK's SetArray and SetNumberOfTuples only mark the data changed); the
  // point ghosts a piece is cut by
  vtkDataArray* ghosts = image->GetPointData()->GetGhostArray();
  const void* fields[] = { array, ghosts,
    array && array->HasStandardMemoryLayout() ? array->GetVoidPointer(0) : nullptr };
  const vtkMTimeType times[] = { array ? array->GetMTime() : 0, ghosts ? ghosts->GetMTime() : 0 };
  const long long layout[] = { array ? static_cast<long long>(array->GetNumberOfTuples()) : 0,
    array ? array->GetNumberOfComponents() : 0, array ? array->GetDataType() : 0 };
  hash.add(fields, sizeof fields);
  hash.add(times, sizeof times);
  hash.add(layout, sizeof layout);
  hash.add(image->GetExtent(), 6 * sizeof(int));
  hash.add(image->GetOrigin(), 3 * sizeof(double));
  hash.add(image->GetSpacing(), 3 * sizeof(double));
  hash.add(image->GetDirectionMatrix()->GetData(), 9 * sizeof(double));
  return hash.value() == 0 ? 1 : hash.value();
}

Volume toCoreVolume(vtkImageData* image, vtkDataArray* array)
{
  if (!image)
  {
    throw Error("no input volume");
  }
  int dims[3];
  image->GetDimensions(dims);
  if (image->GetNumberOfPoints() == 0 || dims[0] < 1 || dims[1] < 1 || dims[2] < 1)
  {
    throw Error("input volume is empty (no points)");
  }
  if (!array)
  {
    array = image->GetPointData()->GetScalars();
  }
  if (!array)
  {
    if (image->GetCellData()->GetScalars() || image->GetCellData()->GetNumberOfArrays() > 0)
    {
      throw Error("the volume has cell data only; apply 'Cell Data to Point Data' first");
    }
    throw Error("the volume has no point scalars to render");
  }
  if (array->GetNumberOfComponents() != 1)
  {
    throw Error(std::string("array '") + (array->GetName() ? array->GetName() : "") + "' has " +
      std::to_string(array->GetNumberOfComponents()) +
      " components; a volume needs a scalar (1-component) array");
  }
  if (array->GetNumberOfTuples() != image->GetNumberOfPoints())
  {
    throw Error("the selected array is not point data of the volume");
  }
  const double* dm = image->GetDirectionMatrix()->GetData();
  const bool identity = dm[0] == 1 && dm[4] == 1 && dm[8] == 1 && dm[1] == 0 && dm[2] == 0 &&
    dm[3] == 0 && dm[5] == 0 && dm[6] == 0 && dm[7] == 0;
  if (!identity)
  {
    throw Error("the volume has a non-identity direction matrix (oriented image); only "
                "axis-aligned volumes are supported");
  }
  const ScalarType type = scalarTypeOf(array->GetDataType());
  const vtkIdType n = array->GetNumberOfTuples();
  const int vtkType = array->GetDataType();
  const bool sameLayout = vtkType == VTK_UNSIGNED_CHAR || vtkType == VTK_SIGNED_CHAR ||
    vtkType == VTK_CHAR || vtkType == VTK_UNSIGNED_SHORT || vtkType == VTK_SHORT ||
    vtkType == VTK_FLOAT;
  std::vector<float> values;
  if (!(sameLayout && array->HasStandardMemoryLayout()))
  {
    values.resize(static_cast<size_t>(n));
    switch (vtkType)
    {
      vtkTemplateMacro({
        if (array->HasStandardMemoryLayout())
        {
          const auto* p = static_cast<const VTK_TT*>(array->GetVoidPointer(0));
          for (vtkIdType i = 0; i < n; ++i)
          {
            values[static_cast<size_t>(i)] = static_cast<float>(p[i]);
          }
        }
        else
        {
          for (vtkIdType i = 0; i < n; ++i)
          {
            values[static_cast<size_t>(i)] = static_cast<float>(array->GetComponent(i, 0));
          }
        }
      });
      default:
        throw Error("volume array has a non-numeric type");
    }
  }
  double origin[3], spacing[3];
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  // Extents may start anywhere: the first point sits at origin + extent_min * spacing.
  int extent[6];
  image->GetExtent(extent);
  std::array<double, 3> o{ origin[0] + extent[0] * spacing[0], origin[1] + extent[2] * spacing[1],
    origin[2] + extent[4] * spacing[2] };
  const std::array<int, 3> d{ dims[0], dims[1], dims[2] };
  const std::array<double, 3> sp{ spacing[0], spacing[1], spacing[2] };
  if (values.empty())
  {
    // 8/16-bit and float arrays are read in place: the Volume keeps a reference to the array
    // (no copy of the data; ParaView's pipeline makes new arrays when it re-executes)
    vtkSmartPointer<vtkDataArray> keep = array;
    std::shared_ptr<const void> owner(array->GetVoidPointer(0), [keep](const void*) {});
    return Volume::sharing(d, o, sp, type, array->GetVoidPointer(0), std::move(owner));
  }
  return Volume(d, o, sp, std::move(values), type);
}

Volume readVolumeFile(const std::string& path, const std::string& arrayName)
{
  if (!std::ifstream(path).good())
  {
    throw Error("cannot open volume '" + path + "': no such file or not readable");
  }
  const std::string ext = fileExtension(path);
  if (isRawVolumePath(path))
  {
    return readRawVolume(path);
  }
  vtkSmartPointer<vtkAlgorithm> reader;
  if (ext == ".vti")
  {
    auto r = vtkSmartPointer<vtkXMLImageDataReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == ".nrrd" || ext == ".nhdr")
  {
    auto r = vtkSmartPointer<vtkNrrdReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == ".mha" || ext == ".mhd")
  {
    auto r = vtkSmartPointer<vtkMetaImageReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == ".nii" || ext == ".nii.gz")
  {
    auto r = vtkSmartPointer<vtkNIFTIImageReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == ".vtk")
  {
    auto r = vtkSmartPointer<vtkStructuredPointsReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else
  {
    throw Error("cannot read volume '" + path +
      "': unknown extension (use .vti, .vtk, .nrrd, .nhdr, .mha, .mhd, .nii, .nii.gz, or "
      ".json/.raw/.raw.gz)");
  }
  ReaderErrors errors(reader);
  reader->Update();
  auto* image = vtkImageData::SafeDownCast(reader->GetOutputDataObject(0));
  if (!errors.Message.empty() || !image || image->GetNumberOfPoints() == 0)
  {
    std::string reason = errors.Message;
    while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' '))
    {
      reason.pop_back();
    }
    throw Error("cannot read volume '" + path + "'" +
      (reason.empty() ? ": it holds no image data" : ": " + reason));
  }
  vtkDataArray* array = nullptr;
  if (!arrayName.empty())
  {
    array = image->GetPointData()->GetArray(arrayName.c_str());
    if (!array)
    {
      throw Error("volume '" + path + "' has no point array named '" + arrayName + "'");
    }
  }
  try
  {
    return toCoreVolume(image, array);
  }
  catch (const Error& e)
  {
    throw Error("volume '" + path + "': " + e.what());
  }
}

void toVTKImage(const Image& rgba, const std::array<double, 3>& background, vtkImageData* output)
{
  output->Initialize();
  output->SetDimensions(rgba.width, rgba.height, 1);
  output->SetOrigin(0, 0, 0);
  output->SetSpacing(1, 1, 1);
  const Image rgb = compositeOverBackground(rgba, background);
  vtkNew<vtkFloatArray> premultiplied;
  premultiplied->SetName("RGBA");
  premultiplied->SetNumberOfComponents(4);
  premultiplied->SetNumberOfTuples(static_cast<vtkIdType>(rgba.width) * rgba.height);
  vtkNew<vtkUnsignedCharArray> composed;
  composed->SetName("Image");
  composed->SetNumberOfComponents(3);
  composed->SetNumberOfTuples(premultiplied->GetNumberOfTuples());
  for (int y = 0; y < rgba.height; ++y)
  {
    const int row = rgba.height - 1 - y; // VTK rows go up
    for (int x = 0; x < rgba.width; ++x)
    {
      const vtkIdType id = static_cast<vtkIdType>(row) * rgba.width + x;
      for (int c = 0; c < 4; ++c)
      {
        premultiplied->SetTypedComponent(id, c, rgba.at(x, y, c));
      }
      for (int c = 0; c < 3; ++c)
      {
        composed->SetTypedComponent(
          id, c, static_cast<unsigned char>(std::lround(rgb.at(x, y, c) * 255.0f)));
      }
    }
  }
  output->GetPointData()->AddArray(premultiplied);
  output->GetPointData()->SetScalars(composed);
}

} // namespace ddg
