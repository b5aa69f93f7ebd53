// vtkDDGBuildDesignSpace.cxx: converts the input and calls ddg::buildDesignSpace.
#include "vtkDDGBuildDesignSpace.h"

#include "DDGFilterSupport.h"
#include "DDGVolumeAdaptor.h"

#include "Gallery/BuildDesignSpace.h"

#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkObjectFactory.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

vtkStandardNewMacro(vtkDDGBuildDesignSpace);

vtkDDGBuildDesignSpace::vtkDDGBuildDesignSpace() {}

vtkDDGBuildDesignSpace::~vtkDDGBuildDesignSpace() = default;

void vtkDDGBuildDesignSpace::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "OutputDirectory: " << this->OutputDirectory << "\n";
  os << indent << "SpecFile: " << this->SpecFile << "\n";
  os << indent << "Count: " << this->Count << "\n";
  os << indent << "Size: " << this->Size << "\n";
  os << indent << "Minutes: " << this->Minutes << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "OutlineCount: " << this->OutlineCount << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
}

int vtkDDGBuildDesignSpace::FillOutputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
  return 1;
}

void vtkDDGBuildDesignSpace::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  vtkTable* output = vtkTable::GetData(outputVector);
  if (this->OutputDirectory.empty())
    throw ddg::Error("no OutputDirectory set");
  const ddg::Volume volume = ddg::toCoreVolume(input, array);
  ddg::BuildOptions o;
  if (!this->SpecFile.empty())
    o.spec = ddg::readDesignSpaceSpec(this->SpecFile);
  o.count = this->Count;
  o.size = this->Size;
  o.minutes = this->Minutes;
  o.iterations = this->Iterations;
  o.outlineCount = this->OutlineCount;
  o.seed = static_cast<std::uint64_t>(this->Seed);
  const auto r = ddg::buildDesignSpace(volume, "", this->OutputDirectory, o,
    [this](const std::string&, double f)
    {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    });
  auto add = [output](const char* name, double v)
  {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->InsertNextValue(v);
    output->AddColumn(a);
  };
  add("PSNR", r.evaluation.psnr);
  add("SSIM", r.evaluation.ssim);
  add("EMD", r.evaluation.emd);
  add("Invariance", r.evaluation.invariance);
  add("TrainingSeconds", r.training.seconds);
  add("Iterations", r.training.iterations);
  auto dir = vtkSmartPointer<vtkStringArray>::New();
  dir->SetName("ModelDirectory");
  dir->InsertNextValue(this->OutputDirectory);
  output->GetFieldData()->AddArray(dir);
}
