// vtkDDGVolumeRender.cxx: converts the input, calls ddg::RayCaster, converts the image back.
#include "vtkDDGVolumeRender.h"

#include "DDGFilterInputs.h"
#include "DDGFilterSupport.h"
#include "DDGVolumeAdaptor.h"

#include "Gallery/Export.h"
#include "Render/RayCaster.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <vtkAlgorithmOutput.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDataSetAttributes.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>

vtkStandardNewMacro(vtkDDGVolumeRender);

// Cache of the prepared volume: rebuilt only when the input data or the array changes.
struct vtkDDGVolumeRender::Internals
{
  std::unique_ptr<ddg::RayCaster> Caster;
  vtkMTimeType InputTime = 0;
  vtkDataArray* Array = nullptr;
};

vtkDDGVolumeRender::vtkDDGVolumeRender()
  : Internal(new Internals)
{
}

vtkDDGVolumeRender::~vtkDDGVolumeRender() = default;

void vtkDDGVolumeRender::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TransferFunctionFile: " << this->TransferFunctionFile << "\n";
  os << indent << "ViewFile: " << this->ViewFile << "\n";
  os << indent << "ViewJSON: " << this->ViewJSON << "\n";
  os << indent << "TransferFunctionJSON: " << this->TransferFunctionJSON.size() << " characters\n";
  os << indent << "Jitter: " << this->Jitter << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}

int vtkDDGVolumeRender::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkImageData");
  return 1;
}

void vtkDDGVolumeRender::PreviewSize(int& width, int& height)
{
  ddg::filterViewSize(this->ViewJSON, this->ViewFile, width, height);
}

void vtkDDGVolumeRender::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector);
  if (this->TransferFunctionFile.empty() && this->TransferFunctionJSON.empty())
  {
    throw ddg::Error("no TransferFunctionFile or TransferFunctionJSON set");
  }
  const ddg::View view = ddg::filterView(this->ViewJSON, this->ViewFile);
  const ddg::TransferFunctionFile file = this->TransferFunctionJSON.empty()
    ? ddg::readTransferFunctionFile(this->TransferFunctionFile)
    : ddg::parseTransferFunctionFile(this->TransferFunctionJSON, "TransferFunctionJSON");

  const vtkMTimeType inputTime =
    std::max(input ? input->GetMTime() : 0, array ? array->GetMTime() : 0);
  if (!this->Internal->Caster || this->Internal->InputTime != inputTime ||
    this->Internal->Array != array)
  {
    this->Internal->Caster.reset();
    const ddg::Volume volume = ddg::toCoreVolume(input, array);
    if (volume.nonFiniteCount() > 0)
    {
      vtkWarningMacro(<< volume.nonFiniteCount()
                      << " NaN/infinite voxels are rendered as the minimum value "
                      << volume.range()[0]);
    }
    this->Internal->Caster = std::make_unique<ddg::RayCaster>(volume);
    this->Internal->InputTime = inputTime;
    this->Internal->Array = array;
  }
  const ddg::RayCaster& caster = *this->Internal->Caster;

  ddg::RenderOptions options;
  options.jitter = this->Jitter;
  options.sampleDistance = this->SampleDistance;
  options.threads = this->NumberOfThreads;
  auto progress = [this](double f)
  {
    this->UpdateProgress(f);
    return !this->GetAbortExecute();
  };
  const ddg::TransferFunctionFile tf = caster.resolve(file, view);
  const ddg::Image image = caster.render(tf, view, options, progress);
  ddg::toVTKImage(image, view.background, output);
  if (tf.is2D) // what ParaView's TransferFunction2D needs to render the same (ddg.apply)
  {
    auto boxes = vtkSmartPointer<vtkStringArray>::New();
    boxes->SetName("ParaViewTransferFunction2D");
    boxes->InsertNextValue(file.isParaView2D
        ? file.paraview2D.toJson() // ParaView's own boxes, as given
        : ddg::paraViewTransferFunction2DJson(caster, tf.tf2D, view));
    output->GetFieldData()->AddArray(boxes);
  }
}
