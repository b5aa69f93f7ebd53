// vtkDDGDesign.h: one design of a model bundle's design space, given by the path that leads to
// it (a ddg history: pick, query latent, blend, edits, principal-axis moves): its render, its
// explicit TF for ParaView, its fidelity and its colour clusters.
#ifndef vtkDDGDesign_h
#define vtkDDGDesign_h

#include "DDGFiltersModule.h" // export macro
#include "vtkDDGAlgorithm.h"

#include <memory>
#include <string>
#include <vector>

/**
 * @class vtkDDGDesign
 * @brief A design of the gallery (history JSON) -> preview, explicit TF, fidelity, colour clusters.
 *
 * Input: the bundle's volume. ModelDirectory: a model bundle with its outline; History: the
 * design as a ddg history JSON (Core/Gallery/History.h: {"format": "ddg-history", "version": 1,
 * "steps": [...]}, the file `ddg replay` reads); ViewFile or ViewJSON: the view of the preview,
 * the explicit TF (for a U-Net model reconstructed from its render at the view) and the
 * fidelity. LockedRegions: feature regions kept as they are in the design of LockHistory
 * (decoder models; the feature lock of the panel).
 *
 * Output port 0 ("Preview"): the model's render of the design at the view (as vtkDDGQuery's).
 * Output port 1 ("Design"): a vtkTable with one row per colour cluster of the preview (what an
 * edit step's "cluster" names: "Cluster", "Share", "R", "G", "B") and in its field data
 * "Latent", "Position" (on the outline plane), "Preset" (ParaView preset JSON; 2D models
 * "TransferFunction2D"), "Slicer" (3D Slicer .vp.json, 1D), "Regions" (lo hi per feature
 * region), and with ComputeFidelity "Fidelity" (PSNR dB, SSIM, max error of the neural image
 * against the ray cast of the explicit TF).
 *
 * Bad input (no history, an invalid step, another model's latent, another volume, a lock on a
 * region the model does not have) gives one error message and empty outputs.
 */
namespace ddg
{
class DesignGallery;
}

class DDGFILTERS_EXPORT vtkDDGDesign : public vtkDDGAlgorithm
{
public:
  static vtkDDGDesign* New();
  vtkTypeMacro(vtkDDGDesign, vtkDDGAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Model bundle directory (with outline.bin). (default: empty)
  vtkSetStdStringFromCharMacro(ModelDirectory);
  vtkGetCharFromStdStringMacro(ModelDirectory);
  ///@}

  ///@{
  /// The design: a ddg history JSON text. (default: empty)
  vtkSetStdStringFromCharMacro(History);
  vtkGetCharFromStdStringMacro(History);
  ///@}

  ///@{
  /// View file, or view JSON text (used when set). (default: empty)
  vtkSetStdStringFromCharMacro(ViewFile);
  vtkGetCharFromStdStringMacro(ViewFile);
  vtkSetStdStringFromCharMacro(ViewJSON);
  vtkGetCharFromStdStringMacro(ViewJSON);
  ///@}

  ///@{
  /// Feature regions locked (indices) and the design they are locked on (history JSON; empty:
  /// the design itself). (default: none)
  void SetNumberOfLockedRegions(int n);
  void SetLockedRegion(int i, int region);
  vtkSetStdStringFromCharMacro(LockHistory);
  vtkGetCharFromStdStringMacro(LockHistory);
  ///@}

  ///@{
  /// Colour clusters of the preview listed (1..16). (default: 4)
  vtkSetClampMacro(Clusters, int, 1, 16);
  vtkGetMacro(Clusters, int);
  ///@}

  ///@{
  /// Compare the neural image with the ray cast of the explicit TF. (default: off)
  vtkSetMacro(ComputeFidelity, bool);
  vtkGetMacro(ComputeFidelity, bool);
  vtkBooleanMacro(ComputeFidelity, bool);
  ///@}

protected:
  vtkDDGDesign();
  ~vtkDDGDesign() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  void PreviewSize(int& width, int& height) override;
  int PieceGhostLevels() override;
  // the design of `gallery`'s design space (under `mpiexec -np N pvserver` on the first rank, the
  // gallery rendering over every rank's piece)
  void Run(ddg::DesignGallery& gallery, vtkInformationVector* outputVector);
  void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) override;

private:
  vtkDDGDesign(const vtkDDGDesign&) = delete;
  void operator=(const vtkDDGDesign&) = delete;

  std::string ModelDirectory;
  std::string History;
  std::string ViewFile;
  std::string ViewJSON;
  std::string LockHistory;
  std::vector<int> LockedRegions;
  int Clusters = 4;
  bool ComputeFidelity = false;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
