// vtkDDGDesignGallery.cxx: outline table and thumbnail sheet of a model bundle; under MPI the
// first rank lays out the sheet and every rank renders its piece of the thumbnails.
#include "vtkDDGDesignGallery.h"

#include "DDGBundleSession.h"
#include "DDGFilterInputs.h"
#include "DDGFilterSupport.h"
#include "DDGPieces.h"
#include "DDGVolumeAdaptor.h"

#include "Gallery/Gallery.h"
#include "Image/Image.h"

#include <vtkAlgorithmOutput.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkTable.h>

#include <cmath>

vtkStandardNewMacro(vtkDDGDesignGallery);

struct vtkDDGDesignGallery::Internals
{
  ddg::FilterGallery Gallery; // in one process or over the ranks' pieces
};

vtkDDGDesignGallery::vtkDDGDesignGallery()
  : Internal(new Internals)
{
  this->SetNumberOfOutputPorts(2);
}

vtkDDGDesignGallery::~vtkDDGDesignGallery() = default;

void vtkDDGDesignGallery::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ModelDirectory: " << this->ModelDirectory << "\n";
  os << indent << "ViewFile: " << this->ViewFile << "\n";
  os << indent << "ViewJSON: " << this->ViewJSON << "\n";
  os << indent << "LightingJSON: " << this->LightingJSON << "\n";
  os << indent << "Box: " << this->Box[0] << " " << this->Box[1] << " " << this->Box[2] << " "
     << this->Box[3] << "\n";
  os << indent << "Count: " << this->Count << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "ThumbnailSize: " << this->ThumbnailSize << "\n";
}

int vtkDDGDesignGallery::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkImageData" : "vtkTable");
  return 1;
}

int vtkDDGDesignGallery::columns() const
{
  return static_cast<int>(std::ceil(std::sqrt(static_cast<double>(this->Count))));
}

void vtkDDGDesignGallery::PreviewSize(int& width, int& height)
{
  const int cols = this->columns(), rows = (this->Count + cols - 1) / cols;
  const int gap = 2, cell = this->ThumbnailSize;
  width = cols * (cell + gap) + gap;
  height = rows * (cell + gap) + gap;
}

int vtkDDGDesignGallery::PieceGhostLevels()
{
  return 1; // the thumbnails' renders: gradients for Shade and 2D tables
}

void vtkDDGDesignGallery::Execute(
  vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector)
{
  this->Internal->Gallery.run(this->Ranks(), input, array, this->InputWholeExtent(),
    this->ModelDirectory, [&](ddg::DesignGallery& gallery) { this->Run(gallery, outputVector); });
}

void vtkDDGDesignGallery::Run(ddg::DesignGallery& gallery, vtkInformationVector* outputVector)
{
  vtkImageData* sheet = vtkImageData::GetData(outputVector, 0);
  vtkTable* designs = vtkTable::GetData(outputVector, 1);
  const auto& outline = gallery.outline();
  ddg::View view = this->ViewFile.empty() && this->ViewJSON.empty()
    ? ddg::designDefaultView(gallery.space().bounds(), gallery.model().spec(), this->ThumbnailSize)
    : ddg::filterView(this->ViewJSON, this->ViewFile);
  view.width = view.height = this->ThumbnailSize;
  if (!this->LightingJSON.empty())
    view.lighting = ddg::parseLighting(this->LightingJSON, "the thumbnails' lighting");
  const bool whole =
    this->Box[0] == 0 && this->Box[1] == 0 && this->Box[2] == 0 && this->Box[3] == 0;
  const ddg::OutlineBox box = whole
    ? outline.bounds()
    : ddg::OutlineBox{ this->Box[0], this->Box[1], this->Box[2], this->Box[3] };
  const auto rows =
    ddg::selectThumbnails(outline, box, this->Count, static_cast<std::uint64_t>(this->Seed));

  // the sheet: cells row by row, top row first
  const int cols = this->columns(), gridRows = (this->Count + cols - 1) / cols;
  std::vector<const ddg::Image*> cells;
  for (size_t k = 0; k < rows.size(); ++k)
  {
    cells.push_back(&gallery.thumbnail(rows[k], view)); // the cache keeps one view's renders
    this->UpdateProgress(static_cast<double>(k + 1) / rows.size());
    if (this->GetAbortExecute())
      throw ddg::Cancelled();
  }
  const ddg::Image canvas = ddg::tileRenders(cells, cols, gridRows, this->ThumbnailSize);
  ddg::toVTKImage(canvas, view.background, sheet);

  auto column = [designs](vtkDataArray* a, const char* name)
  {
    a->SetName(name);
    a->SetNumberOfTuples(0);
    designs->AddColumn(a);
  };
  auto row = vtkSmartPointer<vtkIntArray>::New();
  auto index = vtkSmartPointer<vtkDoubleArray>::New();
  auto px = vtkSmartPointer<vtkDoubleArray>::New();
  auto py = vtkSmartPointer<vtkDoubleArray>::New();
  auto thumb = vtkSmartPointer<vtkIntArray>::New();
  column(row, "Row");
  column(index, "DesignIndex");
  column(px, "X");
  column(py, "Y");
  column(thumb, "Thumbnail");
  std::vector<int> cellOf(static_cast<size_t>(outline.count()), -1);
  for (size_t k = 0; k < rows.size(); ++k)
    cellOf[static_cast<size_t>(rows[k])] = static_cast<int>(k);
  for (int i = 0; i < outline.count(); ++i)
  {
    const auto p = outline.point(i);
    row->InsertNextValue(i);
    index->InsertNextValue(static_cast<double>(outline.latents().indices[static_cast<size_t>(i)]));
    px->InsertNextValue(p[0]);
    py->InsertNextValue(p[1]);
    thumb->InsertNextValue(cellOf[static_cast<size_t>(i)]);
  }
  auto boxArray = vtkSmartPointer<vtkDoubleArray>::New();
  boxArray->SetName("Box");
  for (double v : { box.x0, box.y0, box.x1, box.y1 })
    boxArray->InsertNextValue(v);
  designs->GetFieldData()->AddArray(boxArray);
  auto explained = vtkSmartPointer<vtkDoubleArray>::New();
  explained->SetName("ExplainedVariance");
  explained->InsertNextValue(outline.explainedVariance(0));
  explained->InsertNextValue(outline.explainedVariance(1));
  designs->GetFieldData()->AddArray(explained);
}
