// vtkDDGReconstructTransferFunction.cxx: converts the input, calls
// ddg::reconstructTransferFunction, returns the TF as a table and a preset string.
#include "vtkDDGReconstructTransferFunction.h"

#include "DDGFilterInputs.h"
#include "DDGFilterSupport.h"
#include "DDGVolumeAdaptor.h"
#include "Gallery/Export.h"
#include "Render/RayCaster.h"

#include "Common/FileUtil.h"
#include "Image/Image.h"
#include "Reconstruct/Reconstruction.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

vtkStandardNewMacro(vtkDDGReconstructTransferFunction);

vtkDDGReconstructTransferFunction::vtkDDGReconstructTransferFunction() {}

vtkDDGReconstructTransferFunction::~vtkDDGReconstructTransferFunction() = default;

void vtkDDGReconstructTransferFunction::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetImageFile: " << this->TargetImageFile << "\n";
  os << indent << "ViewFile: " << this->ViewFile << "\n";
  os << indent << "ViewJSON: " << this->ViewJSON << "\n";
  os << indent << "TargetImageData: " << this->TargetImageData.size() << " characters\n";
  os << indent << "OutputFile: " << this->OutputFile << "\n";
  os << indent << "TwoD: " << this->TwoD << "\n";
  os << indent << "Bins: " << this->Bins << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "Smoothness: " << this->Smoothness << "\n";
  os << indent << "LearningRate: " << this->LearningRate << "\n";
}

namespace
{
vtkSmartPointer<vtkDoubleArray> column(vtkTable* table, const char* name)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  table->AddColumn(a);
  return a;
}

void addString(vtkFieldData* fd, const char* name, const std::string& value)
{
  auto s = vtkSmartPointer<vtkStringArray>::New();
  s->SetName(name);
  s->InsertNextValue(value);
  fd->AddArray(s);
}
} // namespace

int vtkDDGReconstructTransferFunction::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
  return 1;
}

void vtkDDGReconstructTransferFunction::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  vtkTable* output = vtkTable::GetData(outputVector);
  ddg::ReconstructionTarget target;
  target.image = ddg::filterImage(this->TargetImageData, this->TargetImageFile, "TargetImage");
  target.view = ddg::filterView(this->ViewJSON, this->ViewFile);
  if (target.image.width != target.view.width || target.image.height != target.view.height)
    throw ddg::Error("the target image is " + std::to_string(target.image.width) + " x " +
      std::to_string(target.image.height) + ", the view " + std::to_string(target.view.width) +
      " x " + std::to_string(target.view.height) + ": save the screenshot at the view's size");
  if (target.image.channels == 1 || target.image.channels == 2)
    target.image = ddg::toChannels(target.image, target.image.channels == 2 ? 4 : 3);
  const ddg::Volume volume = ddg::toCoreVolume(input, array);
  const ddg::DifferentiableRenderer renderer(volume);
  ddg::ReconstructionOptions opt;
  opt.twoD = this->TwoD;
  opt.bins = this->Bins;
  opt.iterations = this->Iterations;
  opt.smoothness = this->Smoothness;
  opt.learningRate = this->LearningRate;
  const auto result = ddg::reconstructTransferFunction(renderer, { target }, opt,
    [this](int step, double, const ddg::ReconstructionResult*)
    {
      this->UpdateProgress(static_cast<double>(step) / this->Iterations);
      return !this->GetAbortExecute();
    });

  auto value = column(output, "Value");
  vtkSmartPointer<vtkDoubleArray> gradient;
  if (result.twoD)
    gradient = column(output, "GradientMagnitude");
  auto r = column(output, "Red"), g = column(output, "Green"), b = column(output, "Blue"),
       a = column(output, "Opacity");
  std::string json;
  if (result.twoD)
  {
    const auto& t = result.table2D;
    for (int j = 0; j < t.height; ++j)
      for (int i = 0; i < t.width; ++i)
      {
        const float* e = t.rgba.data() + 4 * (static_cast<size_t>(j) * t.width + i);
        value->InsertNextValue(
          t.valueRange[0] + i * (t.valueRange[1] - t.valueRange[0]) / (t.width - 1));
        gradient->InsertNextValue(
          t.gradientRange[0] + j * (t.gradientRange[1] - t.gradientRange[0]) / (t.height - 1));
        r->InsertNextValue(e[0]);
        g->InsertNextValue(e[1]);
        b->InsertNextValue(e[2]);
        a->InsertNextValue(e[3]);
      }
    ddg::TransferFunction2D tf;
    tf.name = "DDG reconstruction";
    tf.table = t;
    json = ddg::transferFunction2DToJson(tf);
    addString(output->GetFieldData(), "TransferFunction2D", json);
    addString(output->GetFieldData(), "ParaViewTransferFunction2D",
      ddg::paraViewTransferFunction2DJson(ddg::RayCaster(volume), tf, target.view));
  }
  else
  {
    const auto& t = result.table1D;
    for (int i = 0; i < t.width; ++i)
    {
      value->InsertNextValue(t.min + i * (t.max - t.min) / (t.width - 1));
      r->InsertNextValue(t.rgba[4 * i]);
      g->InsertNextValue(t.rgba[4 * i + 1]);
      b->InsertNextValue(t.rgba[4 * i + 2]);
      a->InsertNextValue(t.rgba[4 * i + 3]);
    }
    json = ddg::presetToJson(ddg::tableToTransferFunction(t, 1.0 / 512.0, "DDG reconstruction"));
    addString(output->GetFieldData(), "Preset", json);
  }
  auto info = vtkSmartPointer<vtkIntArray>::New();
  info->SetName("Iterations");
  info->InsertNextValue(result.iterations);
  output->GetFieldData()->AddArray(info);
  auto converged = vtkSmartPointer<vtkIntArray>::New();
  converged->SetName("Converged");
  converged->InsertNextValue(result.converged ? 1 : 0);
  output->GetFieldData()->AddArray(converged);
  if (!this->OutputFile.empty())
    ddg::writeFileAtomic(this->OutputFile, json, "transfer function");
}
