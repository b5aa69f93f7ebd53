// vtkDDGVolumeRender.cxx: converts the input, calls ddg::RayCaster, converts the image back.
#include "vtkDDGVolumeRender.h"

#include "DDGVolumeAdaptor.h"

#include "Render/RayCaster.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <vtkAlgorithmOutput.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDataSetAttributes.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkStreamingDemandDrivenPipeline.h>

vtkStandardNewMacro(vtkDDGVolumeRender);

// Cache of the prepared volume: rebuilt only when the input data or the array changes.
struct vtkDDGVolumeRender::Internals
{
  std::unique_ptr<ddg::RayCaster> Caster;
  vtkMTimeType InputTime = 0;
  vtkDataArray* Array = nullptr;
  // The last error and the state it was reported for: the pipeline may re-run a failed
  // request (an empty output never satisfies the update extent); report each failure once.
  std::string LastError;
  vtkMTimeType LastErrorState = 0;
};

vtkDDGVolumeRender::vtkDDGVolumeRender()
  : Internal(new Internals)
{
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

vtkDDGVolumeRender::~vtkDDGVolumeRender() = default;

void vtkDDGVolumeRender::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TransferFunctionFile: " << this->TransferFunctionFile << "\n";
  os << indent << "ViewFile: " << this->ViewFile << "\n";
  os << indent << "Jitter: " << this->Jitter << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}

int vtkDDGVolumeRender::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

int vtkDDGVolumeRender::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  if (!this->ViewFile.empty())
  {
    try
    {
      const ddg::View view = ddg::readView(this->ViewFile);
      extent[1] = view.width - 1;
      extent[3] = view.height - 1;
      extent[5] = 0;
    }
    catch (const std::exception&)
    {
      // Reported once, in RequestData; the output stays empty.
    }
  }
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  double origin[3] = { 0, 0, 0 }, spacing[3] = { 1, 1, 1 };
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  return 1;
}

int vtkDDGVolumeRender::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // The whole volume is needed, whatever image extent is requested downstream.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
  return 1;
}

int vtkDDGVolumeRender::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  output->Initialize();
  try
  {
    if (this->TransferFunctionFile.empty())
    {
      throw ddg::Error("no TransferFunctionFile set");
    }
    if (this->ViewFile.empty())
    {
      throw ddg::Error("no ViewFile set");
    }
    const ddg::View view = ddg::readView(this->ViewFile);
    const ddg::TransferFunctionFile tf = ddg::readTransferFunctionFile(this->TransferFunctionFile);

    vtkDataArray* array = this->GetInputArrayToProcess(0, inputVector);
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
    const ddg::Image image = tf.is2D
      ? caster.render(tf.tf2D.bake(), view, options, progress)
      : caster.render(caster.paraviewTable(tf.tf1D), view, options, progress);
    ddg::toVTKImage(image, view.background, output);
    this->Internal->LastError.clear();
  }
  catch (const ddg::Cancelled&)
  {
    output->Initialize();
  }
  catch (const std::exception& e)
  {
    output->Initialize();
    // State = this filter's and its producer's parameters (not the data's MTime, which moves
    // whenever the producer re-executes).
    vtkAlgorithm* producer = this->GetNumberOfInputConnections(0) > 0
      ? this->GetInputConnection(0, 0)->GetProducer()
      : nullptr;
    const vtkMTimeType state = std::max(this->GetMTime(), producer ? producer->GetMTime() : 0);
    if (e.what() != this->Internal->LastError || state != this->Internal->LastErrorState)
    {
      this->Internal->LastError = e.what();
      this->Internal->LastErrorState = state;
      vtkErrorMacro(<< e.what());
    }
  }
  return 1;
}
