// vtkDDGQuery.h: queries a model bundle's design space with an image (ddg::DesignGallery::query).
#ifndef vtkDDGQuery_h
#define vtkDDGQuery_h

#include "DDGFiltersModule.h" // export macro
#include "vtkDDGAlgorithm.h"

#include <memory>
#include <string>

/**
 * @class vtkDDGQuery
 * @brief Image -> latent TF -> nearest designs, preview and explicit TF, on a model bundle.
 *
 * Input: the bundle's volume (vtkImageData, 1-component point array; another volume is refused).
 * ModelDirectory: a model bundle with its outline (Data/Models/<volume>, `ddg outline`);
 * ImageFile: the query (screenshot, figure; any size, RGB/RGBA/gray); ViewFile: the view of the
 * preview and the TF (the current camera, DDG view JSON).
 *
 * Output port 0 ("Preview"): the model's render of the queried design at the view, as
 * vtkDDGVolumeRender's output ("Image" RGB over the view's background, "RGBA").
 * Output port 1 ("Designs"): a vtkTable of the nearest outline designs ("Row", "DesignIndex",
 * "Distance"), its field data holding "Latent" (the query's latent), "Position" (its place on
 * the outline plane), "PicturePSNR" (the design against the picture, both framed on their
 * content: the better of unlit and lit, the picture's lighting not being known), "PictureLit" (1
 * when that figure is of the lit render), "Warning" (only when the picture cannot be read as a
 * rendered volume, e.g. a photograph: the design is a guess; also a VTK warning) and "Preset"
 * (the design's explicit TF as a ParaView preset JSON string; 2D models: "TransferFunction2D").
 * A picture of lines or text (a chart) is refused.
 * Output port 2 ("Neighbour Thumbnails"): with ThumbnailSize > 0, the nearest designs'
 * thumbnails at the view's camera (ThumbnailSize square), in the table's order in one row, 2
 * pixels between and around them ("Image" RGB over the view's background, "RGBA"); else empty.
 * The table then also holds "NeighbourPicturePSNR": each of those designs against the picture as
 * the query's own design is judged (NaN for rows without a thumbnail).
 * With KindNetwork, the table's field data also holds "Kind": whether the picture shows a
 * volume of the input's kind (ddg::addKindCheck; under MPI addKindCheckOnRanks), warned when
 * it may not.
 *
 * The bundle and its outline are loaded once per ModelDirectory and input. Bad input (missing
 * or corrupt bundle, another volume's bundle, an unusable image, a degenerate view) gives one
 * error message and empty outputs.
 */
namespace ddg
{
class DesignGallery;
struct Image;
}

class DDGFILTERS_EXPORT vtkDDGQuery : public vtkDDGAlgorithm
{
public:
  static vtkDDGQuery* New();
  vtkTypeMacro(vtkDDGQuery, vtkDDGAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Model bundle directory (with outline.bin). (default: empty)
  vtkSetStdStringFromCharMacro(ModelDirectory);
  vtkGetCharFromStdStringMacro(ModelDirectory);
  ///@}

  ///@{
  /// Query image file. (default: empty)
  vtkSetStdStringFromCharMacro(ImageFile);
  vtkGetCharFromStdStringMacro(ImageFile);
  ///@}

  ///@{
  /// View file of the preview and the TF. (default: empty)
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
  /// The query image as a base64-encoded image file (PNG, JPEG, TIFF, BMP, GIF or WebP); when set,
  /// used instead of ImageFile (a screenshot dropped or pasted into the panel). (default: empty)
  vtkSetStdStringFromCharMacro(ImageData);
  vtkGetCharFromStdStringMacro(ImageData);
  ///@}

  ///@{
  /// Nearest designs listed. (default: 5)
  vtkSetClampMacro(Neighbours, int, 0, 1000);
  vtkGetMacro(Neighbours, int);
  ///@}

  ///@{
  /// Side of the nearest designs' thumbnails (output port 2), at most 64 of them; 0: none.
  /// (default: 0)
  vtkSetClampMacro(ThumbnailSize, int, 0, 512);
  vtkGetMacro(ThumbnailSize, int);
  ///@}

  ///@{
  /// The kind network (a directory such as Data/Models/kind; ddg::KindNetwork) that checks
  /// whether the picture shows a volume of the input's kind (the field "Kind"; about 10 s the
  /// first time for a volume, then kept). (default: empty, no check)
  vtkSetStdStringFromCharMacro(KindNetwork);
  vtkGetCharFromStdStringMacro(KindNetwork);
  ///@}

protected:
  vtkDDGQuery();
  ~vtkDDGQuery() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  void PreviewSize(int& width, int& height) override;
  int PieceGhostLevels() override;
  void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) override;
  // the query of `gallery`'s design space (under `mpiexec -np N pvserver` on the first rank, the
  // gallery rendering over every rank's piece); `image` gets the picture as the query read it
  void Run(ddg::DesignGallery& gallery, vtkInformationVector* outputVector, ddg::Image& image);

private:
  vtkDDGQuery(const vtkDDGQuery&) = delete;
  void operator=(const vtkDDGQuery&) = delete;

  std::string ModelDirectory;
  std::string ImageFile;
  std::string ViewFile;
  std::string ViewJSON;
  std::string ImageData;
  int Neighbours = 5;
  int ThumbnailSize = 0;
  std::string KindNetwork;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
