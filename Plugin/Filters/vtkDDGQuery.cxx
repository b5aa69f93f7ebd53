// vtkDDGQuery.cxx: converts the input, runs ddg::DesignGallery::query, returns the preview image
// and the designs table; under MPI the first rank runs the query, its gallery rendering over
// every rank's piece (DDGBundleSession.h, FilterGallery).
#include "vtkDDGQuery.h"

#include "DDGBundleSession.h"
#include "DDGFilterInputs.h"
#include "DDGFilterSupport.h"
#include "DDGKindCheck.h"
#include "DDGPieces.h"
#include "DDGVolumeAdaptor.h"

#include "Gallery/Export.h"
#include "Gallery/Gallery.h"
#include "Image/Image.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <vtkAlgorithmOutput.h>
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
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

#include <algorithm>
#include <array>
#include <cmath>

vtkStandardNewMacro(vtkDDGQuery);

struct vtkDDGQuery::Internals
{
  ddg::FilterGallery Gallery;                       // in one process or over the ranks' pieces
  std::shared_ptr<ddg::KindChecker> KindReferences; // the kind network and what it keeps
};

namespace
{
constexpr size_t kMaxNeighbourThumbnails = 64; // port 2: a strip, not a second gallery

// The query's outputs: the preview and the designs table (rows, latent, position, the picture's
// figure, a warning, the explicit TF and, 2D, ParaView's boxes).
void writeQuery(const ddg::QueryResult& r, const ddg::DesignOutline& outline,
  const ddg::TransferFunctionFile& tf, const std::string& boxes2D, const ddg::View& view,
  vtkImageData* preview, vtkTable* designs)
{
  ddg::toVTKImage(r.preview, view.background, preview);
  auto row = vtkSmartPointer<vtkIntArray>::New();
  row->SetName("Row");
  auto index = vtkSmartPointer<vtkDoubleArray>::New(); // uint64 indices fit a double exactly
  index->SetName("DesignIndex");
  auto distance = vtkSmartPointer<vtkDoubleArray>::New();
  distance->SetName("Distance");
  for (const auto& n : r.neighbours)
  {
    row->InsertNextValue(n.row);
    index->InsertNextValue(
      static_cast<double>(outline.latents().indices[static_cast<size_t>(n.row)]));
    distance->InsertNextValue(n.distance);
  }
  designs->AddColumn(row);
  designs->AddColumn(index);
  designs->AddColumn(distance);
  auto latent = vtkSmartPointer<vtkFloatArray>::New();
  latent->SetName("Latent");
  for (float v : r.latent)
    latent->InsertNextValue(v);
  designs->GetFieldData()->AddArray(latent);
  auto position = vtkSmartPointer<vtkDoubleArray>::New();
  position->SetName("Position");
  position->InsertNextValue(r.position[0]);
  position->InsertNextValue(r.position[1]);
  designs->GetFieldData()->AddArray(position);
  auto picture = vtkSmartPointer<vtkDoubleArray>::New();
  picture->SetName("PicturePSNR");
  picture->InsertNextValue(r.picturePSNR);
  designs->GetFieldData()->AddArray(picture);
  auto pictureLit = vtkSmartPointer<vtkIntArray>::New();
  pictureLit->SetName("PictureLit");
  pictureLit->InsertNextValue(r.pictureLit ? 1 : 0);
  designs->GetFieldData()->AddArray(pictureLit);
  if (!r.warning.empty())
  {
    auto warning = vtkSmartPointer<vtkStringArray>::New();
    warning->SetName("Warning");
    warning->InsertNextValue(r.warning);
    designs->GetFieldData()->AddArray(warning);
  }
  auto text = vtkSmartPointer<vtkStringArray>::New();
  text->SetName(tf.is2D ? "TransferFunction2D" : "Preset");
  text->InsertNextValue(
    tf.is2D ? ddg::transferFunction2DToJson(tf.tf2D) : ddg::presetToJson(tf.tf1D));
  designs->GetFieldData()->AddArray(text);
  if (tf.is2D)
  {
    auto boxes = vtkSmartPointer<vtkStringArray>::New();
    boxes->SetName("ParaViewTransferFunction2D");
    boxes->InsertNextValue(boxes2D);
    designs->GetFieldData()->AddArray(boxes);
  }
}
} // namespace

vtkDDGQuery::vtkDDGQuery()
  : Internal(new Internals)
{
  this->SetNumberOfOutputPorts(3);
}

vtkDDGQuery::~vtkDDGQuery() = default;

void vtkDDGQuery::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ModelDirectory: " << this->ModelDirectory << "\n";
  os << indent << "ImageFile: " << this->ImageFile << "\n";
  os << indent << "ViewFile: " << this->ViewFile << "\n";
  os << indent << "ViewJSON: " << this->ViewJSON << "\n";
  os << indent << "ImageData: " << this->ImageData.size() << " characters\n";
  os << indent << "Neighbours: " << this->Neighbours << "\n";
  os << indent << "ThumbnailSize: " << this->ThumbnailSize << "\n";
  os << indent << "KindNetwork: " << this->KindNetwork << "\n";
}

int vtkDDGQuery::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 1 ? "vtkTable" : "vtkImageData");
  return 1;
}

void vtkDDGQuery::PreviewSize(int& width, int& height)
{
  ddg::filterViewSize(this->ViewJSON, this->ViewFile, width, height);
}

int vtkDDGQuery::PieceGhostLevels()
{
  return 1; // the designs' renders: gradients for Shade and 2D tables
}

void vtkDDGQuery::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  const ddg::RankGroup* ranks = this->Ranks();
  auto& gallery = this->Internal->Gallery;
  ddg::Image picture; // read by the query on the first rank (a failure there stops every rank)
  gallery.run(ranks, input, array, this->InputWholeExtent(), this->ModelDirectory,
    [&](ddg::DesignGallery& g) { this->Run(g, outputVector, picture); });
  if (ranks && !this->KindNetwork.empty()) // after the query, every rank together
  {
    ddg::addKindCheckOnRanks(this, vtkTable::GetData(outputVector, 1)->GetFieldData(),
      this->Internal->KindReferences, this->KindNetwork, picture, *ranks,
      gallery.pieces(*ranks, input, array, this->InputWholeExtent()), gallery.fingerprint(ranks));
  }
}

void vtkDDGQuery::Run(
  ddg::DesignGallery& gallery, vtkInformationVector* outputVector, ddg::Image& image)
{
  const ddg::View view = ddg::filterView(this->ViewJSON, this->ViewFile);
  // read as the query reads it (at most kQueryPictureSide a side: an 8K picture is not held whole)
  image = ddg::filterImage(this->ImageData, this->ImageFile, "Image", ddg::kQueryPictureSide);
  this->UpdateProgress(0.5);
  const auto r = gallery.query(image, view, this->Neighbours);
  const auto tf = gallery.explicitTransferFunction(r.latent, view);
  if (!r.warning.empty())
    vtkWarningMacro(<< "Query: " << r.warning << ".");
  writeQuery(r, gallery.outline(), tf,
    tf.is2D ? ddg::paraViewTransferFunction2DJson(gallery.space().paraviewMapping2D(view), tf.tf2D)
            : "",
    view, vtkImageData::GetData(outputVector, 0), vtkTable::GetData(outputVector, 1));
  if (!this->Ranks()) // under MPI after the query (Execute)
    ddg::addKindCheck(this, vtkTable::GetData(outputVector, 1)->GetFieldData(),
      this->Internal->KindReferences, this->KindNetwork, image, gallery.volume(),
      this->Internal->Gallery.fingerprint(nullptr));
  const size_t shown = std::min<size_t>(r.neighbours.size(), kMaxNeighbourThumbnails);
  if (this->ThumbnailSize > 0 && shown > 0) // the nearest designs as the outline shows them
  {
    ddg::View at = view;
    at.width = at.height = this->ThumbnailSize;
    std::vector<const ddg::Image*> cells;
    std::vector<std::vector<float>> latents;
    for (size_t k = 0; k < shown; ++k)
    {
      cells.push_back(&gallery.thumbnail(r.neighbours[k].row, at));
      latents.push_back(gallery.latent(r.neighbours[k].row));
    }
    ddg::toVTKImage(ddg::tileRenders(cells, static_cast<int>(shown), 1, this->ThumbnailSize),
      view.background, vtkImageData::GetData(outputVector, 2));
    // and how each looks against the picture, as the query's own design is judged
    const auto figures = gallery.picturePSNR(image, latents, view);
    auto against = vtkSmartPointer<vtkDoubleArray>::New();
    against->SetName("NeighbourPicturePSNR");
    for (size_t k = 0; k < r.neighbours.size(); ++k)
      against->InsertNextValue(k < shown ? figures[k] : std::nan(""));
    vtkTable::GetData(outputVector, 1)->AddColumn(against);
  }
  this->UpdateProgress(1.0);
}
