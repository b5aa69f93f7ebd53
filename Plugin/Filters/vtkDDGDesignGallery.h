// vtkDDGDesignGallery.h: the outline of a model bundle's design space and K thumbnails that cover
// a box of it (ddg::DesignOutline, ddg::selectThumbnails, ddg::DesignGallery renders).
#ifndef vtkDDGDesignGallery_h
#define vtkDDGDesignGallery_h

#include "DDGFiltersModule.h" // export macro
#include "vtkDDGAlgorithm.h"

#include <memory>
#include <string>

/**
 * @class vtkDDGDesignGallery
 * @brief Design-space outline and thumbnails of a model bundle, for the Design Gallery panel.
 *
 * Input: the bundle's volume. ModelDirectory: a model bundle with its outline; ViewFile: the
 * thumbnails' camera (its size is replaced by ThumbnailSize); Box: the part of the outline plane
 * shown (x0, y0, x1, y1; all zero = the whole outline); Count, Seed: how many thumbnails and
 * which sample (farthest-point sampling over the box; another seed resamples).
 *
 * Output port 0 ("Thumbnails"): the chosen thumbnails tiled row by row, columns =
 * ceil(sqrt(Count)), cells of ThumbnailSize with 2 pixels between them, over the view's
 * background ("Image" RGB; unused cells white).
 * Output port 1 ("Designs"): a vtkTable with one row per outline design: "Row", "DesignIndex",
 * "X", "Y" (plane coordinates) and "Thumbnail" (its cell in port 0, -1 for none); field data
 * "Box" (the box shown) and "ExplainedVariance" (of the two plane axes).
 */
class vtkTable;
namespace ddg
{
class DesignGallery;
}

class DDGFILTERS_EXPORT vtkDDGDesignGallery : public vtkDDGAlgorithm
{
public:
  static vtkDDGDesignGallery* New();
  vtkTypeMacro(vtkDDGDesignGallery, vtkDDGAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Model bundle directory (with outline.bin). (default: empty)
  vtkSetStdStringFromCharMacro(ModelDirectory);
  vtkGetCharFromStdStringMacro(ModelDirectory);
  ///@}

  ///@{
  /// View file of the thumbnails; empty: the volume's default view. (default: empty)
  vtkSetStdStringFromCharMacro(ViewFile);
  vtkGetCharFromStdStringMacro(ViewFile);
  ///@}

  ///@{
  /// The view as view JSON text; when set, used instead of ViewFile (the panel's current
  /// camera; needs no file on the server). (default: empty)
  vtkSetStdStringFromCharMacro(ViewJSON);
  vtkGetCharFromStdStringMacro(ViewJSON);
  ///@}

  ///@{
  /// The thumbnails' lighting, a view JSON's "lighting" object ("{}": unlit); when set it
  /// replaces the view's (the panel: the representation's Shade, so that thumbnails look as the
  /// volume is shown). Empty: a given view's own lighting, or at the default view the design
  /// space's (its spec's "lighting" with Shade on). (default: empty)
  vtkSetStdStringFromCharMacro(LightingJSON);
  vtkGetCharFromStdStringMacro(LightingJSON);
  ///@}

  ///@{
  /// Box of the outline plane shown (x0, y0, x1, y1); all zero: the whole outline. (default: 0)
  vtkSetVector4Macro(Box, double);
  vtkGetVector4Macro(Box, double);
  ///@}

  ///@{
  /// Thumbnails. (default: 64)
  vtkSetClampMacro(Count, int, 1, 1024);
  vtkGetMacro(Count, int);
  ///@}

  ///@{
  /// Thumbnail sampling seed. (default: 1)
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /// Thumbnail side in pixels. (default: 64)
  vtkSetClampMacro(ThumbnailSize, int, 8, 512);
  vtkGetMacro(ThumbnailSize, int);
  ///@}

protected:
  vtkDDGDesignGallery();
  ~vtkDDGDesignGallery() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  void PreviewSize(int& width, int& height) override;
  int PieceGhostLevels() override;
  // the sheet and the designs table of `gallery` (under `mpiexec -np N pvserver` on the first
  // rank, the gallery rendering over every rank's piece)
  void Run(ddg::DesignGallery& gallery, vtkInformationVector* outputVector);
  void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) override;

private:
  vtkDDGDesignGallery(const vtkDDGDesignGallery&) = delete;
  void operator=(const vtkDDGDesignGallery&) = delete;

  int columns() const;

  std::string ModelDirectory;
  std::string ViewFile;
  std::string ViewJSON;
  std::string LightingJSON;
  double Box[4] = { 0, 0, 0, 0 };
  int Count = 64;
  int Seed = 1;
  int ThumbnailSize = 64;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
