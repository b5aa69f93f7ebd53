// vtkDDGVolumeRender.cxx: converts the input, calls ddg::RayCaster, converts the image back.
#include "vtkDDGVolumeRender.h"

#include "DDGFilterInputs.h"
#include "DDGFilterSupport.h"
#include "DDGPieces.h"
#include "DDGVolumeAdaptor.h"

#include "Common/FileUtil.h"
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
  std::unique_ptr<ddg::RankVolume> Pieces; // distributed: this rank's piece, agreed with the others
  ddg::InputStamp Stamp;                   // the input and array the cache was made of
};

namespace
{
ddg::RenderOptions optionsOf(vtkDDGVolumeRender* filter)
{
  ddg::RenderOptions options;
  options.jitter = filter->GetJitter();
  options.sampleDistance = filter->GetSampleDistance();
  options.threads = filter->GetNumberOfThreads();
  return options;
}

// Progress reported by the filter; false once ParaView asks it to abort.
ddg::ProgressCallback progressOf(vtkDDGVolumeRender* filter)
{
  return [filter](double f)
  {
    filter->UpdateProgress(f);
    return !filter->GetAbortExecute();
  };
}

// The image and, for 2D TFs, ParaView's 2D boxes as field data.
void writeOutput(const ddg::Image& image, const ddg::RayCaster& caster,
  const ddg::TransferFunctionFile& file, const ddg::TransferFunctionFile& tf, const ddg::View& view,
  vtkImageData* output)
{
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
} // namespace

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

int vtkDDGVolumeRender::PieceGhostLevels()
{
  return 1;
}

void vtkDDGVolumeRender::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector);
  if (const ddg::RankGroup* ranks = this->Ranks())
  {
    this->ExecuteOnRanks(*ranks, input, array, output);
    return;
  }
  if (this->TransferFunctionFile.empty() && this->TransferFunctionJSON.empty())
  {
    throw ddg::Error("no TransferFunctionFile or TransferFunctionJSON set");
  }
  const ddg::View view = ddg::filterView(this->ViewJSON, this->ViewFile);
  const ddg::TransferFunctionFile file = this->TransferFunctionJSON.empty()
    ? ddg::readTransferFunctionFile(this->TransferFunctionFile)
    : ddg::parseTransferFunctionFile(this->TransferFunctionJSON, "TransferFunctionJSON");
  if (this->Internal->Stamp.changed(input, array))
  {
    this->Internal->Stamp.clear();
    this->Internal->Caster.reset();
    this->Internal->Pieces.reset();
    const ddg::Volume volume = ddg::toCoreVolume(input, array);
    if (volume.nonFiniteCount() > 0)
    {
      vtkWarningMacro(<< volume.nonFiniteCount()
                      << " NaN/infinite voxels are rendered as the minimum value "
                      << volume.range()[0]);
    }
    this->Internal->Caster = std::make_unique<ddg::RayCaster>(volume);
    this->Internal->Stamp.keep(input, array);
  }
  const ddg::RayCaster& caster = *this->Internal->Caster;

  const ddg::TransferFunctionFile tf = caster.resolve(file, view);
  const ddg::Image image = caster.render(tf, view, optionsOf(this), progressOf(this));
  writeOutput(image, caster, file, tf, view, output);
}

void vtkDDGVolumeRender::ExecuteOnRanks(
  const ddg::RankGroup& ranks, vtkImageData* input, vtkDataArray* array, vtkImageData* output)
{
  // the files as the first rank sees them (the others may not see its paths)
  std::string viewText = this->ViewJSON, tfText = this->TransferFunctionJSON;
  ranks.step(
    [&]
    {
      if (ranks.rank() != 0)
        return;
      if (tfText.empty() && this->TransferFunctionFile.empty())
        throw ddg::Error("no TransferFunctionFile or TransferFunctionJSON set");
      if (viewText.empty() && this->ViewFile.empty())
        throw ddg::Error("no ViewFile or ViewJSON set");
      if (tfText.empty())
        tfText = ddg::readTextFile(this->TransferFunctionFile, "transfer function");
      if (viewText.empty())
        viewText = ddg::readTextFile(this->ViewFile, "view");
    });
  viewText = ranks.broadcast(viewText);
  tfText = ranks.broadcast(tfText);
  ddg::View view;
  ddg::TransferFunctionFile file;
  ranks.step(
    [&]
    {
      view = ddg::parseView(viewText,
        this->ViewJSON.empty() ? "view '" + this->ViewFile + "'" : std::string("ViewJSON"));
      file = ddg::parseTransferFunctionFile(tfText,
        this->TransferFunctionJSON.empty()
          ? "transfer function '" + this->TransferFunctionFile + "'"
          : std::string("TransferFunctionJSON"));
    });
  // the pieces, agreed again when any rank's input changed
  if (this->Internal->Stamp.changedOnAnyRank(ranks, input, array)) // every rank calls it
  {
    this->Internal->Stamp.clear();
    this->Internal->Caster.reset();
    this->Internal->Pieces.reset();
    auto pieces = std::make_unique<ddg::RankVolume>(
      ddg::RankVolume::gather(ranks, input, array, this->InputWholeExtent()));
    if (ranks.rank() == 0 && pieces->nonFiniteCount > 0)
      vtkWarningMacro(<< pieces->nonFiniteCount
                      << " NaN/infinite voxels are rendered as their piece's minimum value");
    this->Internal->Pieces = std::move(pieces);
    this->Internal->Stamp.keep(input, array);
  }
  const ddg::RankVolume& pieces = *this->Internal->Pieces;
  const ddg::Image image =
    ddg::renderOnRanks(ranks, pieces, file, view, optionsOf(this), progressOf(this));
  if (ranks.rank() != 0)
    return; // the first rank's output is the image
  if (!pieces.caster && (file.is2D || file.isParaView2D))
    throw ddg::Error("the first rank holds no cell of the volume: it cannot describe the 2D "
                     "transfer function for ParaView");
  if (pieces.caster)
    writeOutput(image, *pieces.caster, file, pieces.caster->resolve(file, view), view, output);
  else
    ddg::toVTKImage(image, view.background, output);
}
