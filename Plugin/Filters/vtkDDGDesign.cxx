// vtkDDGDesign.cxx: replays the history on the cached gallery, renders, exports the TF (under MPI
// on the first rank, the gallery rendering over every rank's piece).
#include "vtkDDGDesign.h"

#include "DDGBundleSession.h"
#include "DDGFilterInputs.h"
#include "DDGFilterSupport.h"
#include "DDGPieces.h"
#include "DDGVolumeAdaptor.h"

#include "Gallery/Export.h"
#include "Gallery/Gallery.h"
#include "Gallery/History.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

vtkStandardNewMacro(vtkDDGDesign);

struct vtkDDGDesign::Internals
{
  ddg::FilterGallery Gallery; // in one process or over the ranks' pieces
};

vtkDDGDesign::vtkDDGDesign()
  : Internal(new Internals)
{
  this->SetNumberOfOutputPorts(2);
}

vtkDDGDesign::~vtkDDGDesign() = default;

void vtkDDGDesign::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ModelDirectory: " << this->ModelDirectory << "\n";
  os << indent << "History: " << this->History << "\n";
  os << indent << "ViewFile: " << this->ViewFile << "\n";
  os << indent << "ViewJSON: " << this->ViewJSON << "\n";
  os << indent << "LockedRegions:";
  for (int r : this->LockedRegions)
    os << " " << r;
  os << "\n" << indent << "LockHistory: " << this->LockHistory << "\n";
  os << indent << "Clusters: " << this->Clusters << "\n";
  os << indent << "ComputeFidelity: " << this->ComputeFidelity << "\n";
}

void vtkDDGDesign::SetNumberOfLockedRegions(int n)
{
  if (n >= 0 && static_cast<size_t>(n) != this->LockedRegions.size())
  {
    this->LockedRegions.resize(static_cast<size_t>(n), 0);
    this->Modified();
  }
}

void vtkDDGDesign::SetLockedRegion(int i, int region)
{
  if (i >= 0 && static_cast<size_t>(i) < this->LockedRegions.size() &&
    this->LockedRegions[static_cast<size_t>(i)] != region)
  {
    this->LockedRegions[static_cast<size_t>(i)] = region;
    this->Modified();
  }
}

int vtkDDGDesign::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkImageData" : "vtkTable");
  return 1;
}

void vtkDDGDesign::PreviewSize(int& width, int& height)
{
  ddg::filterViewSize(this->ViewJSON, this->ViewFile, width, height);
}

namespace
{
template <class Array, class Values>
void addField(vtkTable* table, const char* name, const Values& values)
{
  auto a = vtkSmartPointer<Array>::New();
  a->SetName(name);
  for (const auto& v : values)
    a->InsertNextValue(v);
  table->GetFieldData()->AddArray(a);
}
} // namespace

int vtkDDGDesign::PieceGhostLevels()
{
  return 1; // the design's renders: gradients for Shade and 2D tables
}

void vtkDDGDesign::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  this->Internal->Gallery.run(this->Ranks(), input, array, this->InputWholeExtent(),
    this->ModelDirectory, [&](ddg::DesignGallery& gallery) { this->Run(gallery, outputVector); });
}

void vtkDDGDesign::Run(ddg::DesignGallery& gallery, vtkInformationVector* outputVector)
{
  vtkImageData* preview = vtkImageData::GetData(outputVector, 0);
  vtkTable* design = vtkTable::GetData(outputVector, 1);
  if (this->History.empty())
    throw ddg::Error("no History set: the design is a ddg history JSON");
  const ddg::View view = ddg::filterView(this->ViewJSON, this->ViewFile);
  const auto z =
    ddg::replayHistory(gallery, ddg::DesignHistory::fromJson(this->History, "History"));
  std::unique_ptr<ddg::FeatureLock> lock;
  if (!this->LockedRegions.empty())
  {
    const auto from = this->LockHistory.empty()
      ? z
      : ddg::replayHistory(gallery, ddg::DesignHistory::fromJson(this->LockHistory, "LockHistory"));
    lock = std::make_unique<ddg::FeatureLock>(gallery.lockRegions(from, this->LockedRegions));
  }
  this->UpdateProgress(0.3);
  const ddg::Image image = gallery.render(z, view, lock.get());
  const auto tf = gallery.explicitTransferFunction(z, view, lock.get());
  this->UpdateProgress(0.6);

  ddg::toVTKImage(image, view.background, preview);
  const auto clusters = ddg::colorClusters(image, this->Clusters);
  auto id = vtkSmartPointer<vtkIntArray>::New();
  id->SetName("Cluster");
  auto share = vtkSmartPointer<vtkDoubleArray>::New();
  share->SetName("Share");
  design->AddColumn(id);
  design->AddColumn(share);
  vtkSmartPointer<vtkDoubleArray> rgb[3];
  const char* names[3] = { "R", "G", "B" };
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = vtkSmartPointer<vtkDoubleArray>::New();
    rgb[c]->SetName(names[c]);
    design->AddColumn(rgb[c]);
  }
  for (int k = 0; k < clusters.count(); ++k)
  {
    id->InsertNextValue(k);
    share->InsertNextValue(clusters.share[static_cast<size_t>(k)]);
    for (int c = 0; c < 3; ++c)
      rgb[c]->InsertNextValue(clusters.rgb[static_cast<size_t>(k)][c]);
  }

  addField<vtkFloatArray>(design, "Latent", z);
  addField<vtkDoubleArray>(design, "Position", gallery.outline().project(z.data()));
  std::vector<double> regions;
  for (const auto& r : gallery.model().regions())
  {
    regions.push_back(r.lo);
    regions.push_back(r.hi);
  }
  addField<vtkDoubleArray>(design, "Regions", regions);
  const double unit = gallery.space().opacityUnitDistance(view);
  if (tf.is2D)
  {
    addField<vtkStringArray>(design, "TransferFunction2D",
      std::vector<std::string>{ ddg::transferFunction2DToJson(tf.tf2D) });
    addField<vtkStringArray>(design, "ParaViewTransferFunction2D",
      std::vector<std::string>{
        ddg::paraViewTransferFunction2DJson(gallery.space().paraviewMapping2D(view), tf.tf2D) });
  }
  else
  {
    addField<vtkStringArray>(
      design, "Preset", std::vector<std::string>{ ddg::presetToJson(tf.tf1D) });
    addField<vtkStringArray>(design, "Slicer",
      std::vector<std::string>{
        ddg::slicerVolumePropertyJson(tf.tf1D, gallery.space().range(), unit) });
  }
  if (this->ComputeFidelity)
  {
    const auto f = gallery.fidelity(z, view, lock.get());
    addField<vtkDoubleArray>(design, "Fidelity", std::vector<double>{ f.psnr, f.ssim, f.maxError });
  }
  this->UpdateProgress(1.0);
}
