// vtkDDGAlgorithm.cxx: request dispatch, whole-extent requests, piece skipping, errors once.
#include "vtkDDGAlgorithm.h"

#include "DDGFilterSupport.h"
#include "DDGRanks.h"

#include "Common/Error.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include <vtkDataObject.h>
#include <vtkDataObjectTypes.h>
#include <vtkDataSetAttributes.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>

struct vtkDDGAlgorithm::Internals
{
  ddg::ErrorOnce Errors;
  std::unique_ptr<ddg::RankGroup> Ranks; // the current request's, when distributed
  int WholeExtent[6] = { 0, -1, 0, -1, 0, -1 };
};

vtkDDGAlgorithm::vtkDDGAlgorithm()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

vtkDDGAlgorithm::~vtkDDGAlgorithm() = default;

void vtkDDGAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LastError: " << this->LastError << "\n";
}

void vtkDDGAlgorithm::PreviewSize(int& width, int& height)
{
  width = height = 0;
}

int vtkDDGAlgorithm::PieceGhostLevels()
{
  return -1;
}

const ddg::RankGroup* vtkDDGAlgorithm::Ranks() const
{
  return this->Internal->Ranks.get();
}

const int* vtkDDGAlgorithm::InputWholeExtent() const
{
  return this->Internal->WholeExtent;
}

int vtkDDGAlgorithm::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

int vtkDDGAlgorithm::RequestDataObject(vtkInformationVector* outputVector)
{
  for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
  {
    const char* type = this->GetOutputPortInformation(port)->Get(vtkDataObject::DATA_TYPE_NAME());
    vtkInformation* info = outputVector->GetInformationObject(port);
    vtkDataObject* current = info->Get(vtkDataObject::DATA_OBJECT());
    if (!type || (current && current->IsA(type)))
      continue;
    vtkSmartPointer<vtkDataObject> data =
      vtkSmartPointer<vtkDataObject>::Take(vtkDataObjectTypes::NewDataObject(type));
    if (!data)
      return 0;
    info->Set(vtkDataObject::DATA_OBJECT(), data);
  }
  return 1;
}

void vtkDDGAlgorithm::ResetOutputs(vtkInformationVector* outputVector)
{
  for (int i = 0; i < outputVector->GetNumberOfInformationObjects(); ++i)
  {
    vtkDataObject* data = outputVector->GetInformationObject(i)->Get(vtkDataObject::DATA_OBJECT());
    if (data)
      data->Initialize();
  }
}

vtkTypeBool vtkDDGAlgorithm::ProcessRequest(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_OBJECT()))
    return this->RequestDataObject(outputVector);
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_INFORMATION()))
  {
    for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port)
    {
      vtkInformation* portInfo = this->GetOutputPortInformation(port);
      if (!portInfo->Has(vtkDataObject::DATA_TYPE_NAME()) ||
        std::string(portInfo->Get(vtkDataObject::DATA_TYPE_NAME())) != "vtkImageData")
        continue;
      int width = 0, height = 0; // other image ports: an empty extent unless the filter knows
      if (port == 0)
        this->PreviewSize(width, height);
      ddg::setImageInformation(outputVector->GetInformationObject(port), width, height);
    }
    return 1;
  }
  const int ghosts = this->PieceGhostLevels();
  if (request->Has(vtkStreamingDemandDrivenPipeline::REQUEST_UPDATE_EXTENT()))
  {
    if (ghosts >= 0 && ddg::RankGroup::forRequest(outputVector->GetInformationObject(0)))
      ddg::requestInputPiece(inputVector, outputVector, ghosts);
    else
      ddg::requestWholeInputExtent(inputVector);
    return 1;
  }
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA()))
  {
    this->Internal->Ranks =
      ghosts >= 0 ? ddg::RankGroup::forRequest(outputVector->GetInformationObject(0)) : nullptr;
    if (!this->Internal->Ranks && ddg::skipPiece(outputVector)) // the first piece computes
      return 1;
    vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
    if (inInfo && inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
      inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), this->Internal->WholeExtent);
    this->ResetOutputs(outputVector);
    // VTK 9.2's pipeline does not clear AbortExecute: a run cancelled before must not cancel
    // this one
    this->SetAbortExecute(0);
    try
    {
      this->Execute(vtkImageData::GetData(inputVector[0]),
        this->GetInputArrayToProcess(0, inputVector), outputVector);
      this->Internal->Errors.clear();
      this->LastError.clear();
    }
    catch (const ddg::Cancelled&)
    {
      this->ResetOutputs(outputVector);
      this->LastError = "cancelled";
    }
    catch (const ddg::RankFailed& e) // another rank than the first: the first one reports
    {
      this->ResetOutputs(outputVector);
      this->LastError = e.what();
    }
    catch (const std::exception& e)
    {
      this->ResetOutputs(outputVector);
      this->LastError = e.what();
      if (this->Internal->Errors.report(this, e.what()))
        vtkErrorMacro(<< e.what());
    }
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}
