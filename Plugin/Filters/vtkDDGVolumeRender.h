// vtkDDGVolumeRender.h: renders a volume with a TF file and a view file on the CPU (ddg::Core).
#ifndef vtkDDGVolumeRender_h
#define vtkDDGVolumeRender_h

#include "DDGFiltersModule.h" // export macro
#include "vtkDDGAlgorithm.h"

#include <memory>
#include <string>

/**
 * @class vtkDDGVolumeRender
 * @brief Volume-renders image data with the Design Gallery's CPU ray caster.
 *
 * Input: vtkImageData with a 1-component point array (SetInputArrayToProcess(0, ...); default:
 * the point scalars). Output: a 2D vtkImageData of the view's size with point arrays
 * "Image" (unsigned char RGB composited over the view's background, active scalars) and
 * "RGBA" (float, premultiplied colour and opacity).
 *
 * TransferFunctionFile: a ParaView preset JSON (1D) or the project's 2D TF JSON.
 * ViewFile: the project's view JSON (camera as ParaView states it, size, background,
 * opacity unit distance). The same files as `ddg render`.
 *
 * Bad input (missing files, malformed JSON, degenerate camera, constant volume, ...) gives one
 * error message and an empty output.
 *
 * Under `mpiexec -np N pvserver` it works on pieces: every rank renders its own piece of the
 * volume (with one ghost level, what Shade's and 2D tables' gradients need) and the first rank
 * composites the images sort-last (ddg::renderOnRanks): no rank holds the whole volume. The
 * image equals the one-process render up to float rounding and each piece's own early ray
 * termination (at most 1/255 per channel). The first rank outputs the image, the others empty
 * data (what the client fetches is the first rank's).
 */
class DDGFILTERS_EXPORT vtkDDGVolumeRender : public vtkDDGAlgorithm
{
public:
  static vtkDDGVolumeRender* New();
  vtkTypeMacro(vtkDDGVolumeRender, vtkDDGAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Transfer function file (ParaView preset JSON or 2D TF JSON). (default: empty)
  vtkSetStdStringFromCharMacro(TransferFunctionFile);
  vtkGetCharFromStdStringMacro(TransferFunctionFile);
  ///@}

  ///@{
  /// View file (camera, size, background, opacity unit distance). (default: empty)
  vtkSetStdStringFromCharMacro(ViewFile);
  vtkGetCharFromStdStringMacro(ViewFile);
  ///@}

  ///@{
  /// The TF and the view as JSON text; when set, used instead of the files (scripts and the
  /// panel: nothing needed on the server's disk). (default: empty)
  vtkSetStdStringFromCharMacro(TransferFunctionJSON);
  vtkGetCharFromStdStringMacro(TransferFunctionJSON);
  vtkSetStdStringFromCharMacro(ViewJSON);
  vtkGetCharFromStdStringMacro(ViewJSON);
  ///@}

  ///@{
  /// Jitter the first sample per pixel. (default: off)
  vtkSetMacro(Jitter, bool);
  vtkGetMacro(Jitter, bool);
  vtkBooleanMacro(Jitter, bool);
  ///@}

  ///@{
  /// Sample distance in world units; 0 uses ParaView's rule (mean spacing / 2). (default: 0)
  vtkSetClampMacro(SampleDistance, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(SampleDistance, double);
  ///@}

  ///@{
  /// Worker threads; 0 = all cores. (default: 0)
  vtkSetClampMacro(NumberOfThreads, int, 0, 256);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

protected:
  vtkDDGVolumeRender();
  ~vtkDDGVolumeRender() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  void PreviewSize(int& width, int& height) override;
  int PieceGhostLevels() override;
  // Distributed: the ranks' pieces agreed (cached while the input stays), rendered sort-last.
  void ExecuteOnRanks(
    const ddg::RankGroup& ranks, vtkImageData* input, vtkDataArray* array, vtkImageData* output);

  void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) override;

private:
  vtkDDGVolumeRender(const vtkDDGVolumeRender&) = delete;
  void operator=(const vtkDDGVolumeRender&) = delete;

  std::string TransferFunctionFile;
  std::string ViewFile;
  std::string TransferFunctionJSON;
  std::string ViewJSON;
  bool Jitter = false;
  double SampleDistance = 0.0;
  int NumberOfThreads = 0;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
