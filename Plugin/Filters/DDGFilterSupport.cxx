// DDGFilterSupport.cxx: whole-extent requests, image output information, errors reported once.
#include "DDGFilterSupport.h"

#include <vtkAlgorithm.h>
#include <vtkAlgorithmOutput.h>
#include <vtkDataObject.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <algorithm>

namespace ddg
{

namespace
{
int updatePiece(vtkInformation* info)
{
  return info && info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    ? info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    : 0;
}
} // namespace

void requestWholeInputExtent(vtkInformationVector** inputVector)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (!inInfo || !inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    return;
  // the executive has copied the downstream piece request onto the input
  if (updatePiece(inInfo) > 0)
  {
    const int nothing[6] = { 0, -1, 0, -1, 0, -1 };
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), nothing, 6);
    return;
  }
  // the whole volume as one piece (else the producer splits the extent by the piece request)
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
}

void requestInputPiece(
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, int ghostLevels)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (!inInfo || !outInfo || !inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    return;
  using SDDP = vtkStreamingDemandDrivenPipeline;
  inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()));
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()));
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), ghostLevels);
  // the producer splits the whole extent by the piece request (as vtkFlyingEdges3D asks)
  inInfo->Set(SDDP::UPDATE_EXTENT(), inInfo->Get(SDDP::WHOLE_EXTENT()), 6);
}

bool skipPiece(vtkInformationVector* outputVector)
{
  if (updatePiece(outputVector->GetInformationObject(0)) == 0)
    return false;
  for (int i = 0; i < outputVector->GetNumberOfInformationObjects(); ++i)
  {
    vtkDataObject* data = outputVector->GetInformationObject(i)->Get(vtkDataObject::DATA_OBJECT());
    if (data)
      data->Initialize();
  }
  return true;
}

void setImageInformation(vtkInformation* outInfo, int width, int height)
{
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  if (width > 0 && height > 0)
  {
    extent[1] = width - 1;
    extent[3] = height - 1;
    extent[5] = 0;
  }
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  double origin[3] = { 0, 0, 0 }, spacing[3] = { 1, 1, 1 };
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
}

bool ErrorOnce::report(vtkAlgorithm* filter, const std::string& message)
{
  vtkAlgorithm* producer = filter->GetNumberOfInputConnections(0) > 0
    ? filter->GetInputConnection(0, 0)->GetProducer()
    : nullptr;
  const vtkMTimeType state = std::max(filter->GetMTime(), producer ? producer->GetMTime() : 0);
  if (message == Last && state == LastState)
    return false;
  Last = message;
  LastState = state;
  return true;
}

} // namespace ddg
