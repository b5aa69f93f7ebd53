// vtkDDGReconstructTransferFunction.h: finds the TF whose rendering of the input volume matches a
// target image (ddg::reconstructTransferFunction: the differentiable ray caster and Adam).
#ifndef vtkDDGReconstructTransferFunction_h
#define vtkDDGReconstructTransferFunction_h

#include "DDGFiltersModule.h" // export macro
#include "vtkDDGAlgorithm.h"

#include <string>

/**
 * @class vtkDDGReconstructTransferFunction
 * @brief Reconstructs a volume's transfer function from a screenshot and its view.
 *
 * Input: vtkImageData with a 1-component point array (SetInputArrayToProcess(0, ...); default:
 * the point scalars). TargetImageFile: the screenshot (RGB over the view's background, or RGBA),
 * exactly the view's size; ViewFile: the project's view JSON it was taken from.
 *
 * Output: a vtkTable of the reconstructed 1D TF, one row per bin: "Value", "Red", "Green",
 * "Blue", "Opacity" (uncorrected opacity, as ParaView's Points hold it); its field data holds
 * "Preset" (the TF as a ParaView preset JSON string: RGBPoints, Points, ColorSpace, ready for
 * LookupTable.RGBPoints / ScalarOpacityFunction.Points), "Converged" and "Iterations". With
 * TwoD on, the rows are the 2D table (value fastest, plus "GradientMagnitude") and the field
 * data holds "TransferFunction2D" (the DDG 2D TF JSON) instead of "Preset". OutputFile, when
 * set, receives the same JSON (written atomically).
 *
 * Progress is reported per step and Abort stops the optimisation (empty output). Bad input
 * (missing or unreadable files, a target of the wrong size, a degenerate view, a constant
 * volume) gives one error message and an empty output.
 */
class DDGFILTERS_EXPORT vtkDDGReconstructTransferFunction : public vtkDDGAlgorithm
{
public:
  static vtkDDGReconstructTransferFunction* New();
  vtkTypeMacro(vtkDDGReconstructTransferFunction, vtkDDGAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Target image file (PNG, JPEG, TIFF, EXR; the view's size). (default: empty)
  vtkSetStdStringFromCharMacro(TargetImageFile);
  vtkGetCharFromStdStringMacro(TargetImageFile);
  ///@}

  ///@{
  /// View file the target was taken from. (default: empty)
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
  /// The target as a base64-encoded image file (PNG, JPEG or TIFF); when set, used instead of
  /// TargetImageFile. (default: empty)
  vtkSetStdStringFromCharMacro(TargetImageData);
  vtkGetCharFromStdStringMacro(TargetImageData);
  ///@}

  ///@{
  /// Where to write the TF (ParaView preset JSON, or DDG 2D TF JSON); empty: not written.
  /// (default: empty)
  vtkSetStdStringFromCharMacro(OutputFile);
  vtkGetCharFromStdStringMacro(OutputFile);
  ///@}

  ///@{
  /// Reconstruct a 2D (value x gradient magnitude) TF. (default: off)
  vtkSetMacro(TwoD, bool);
  vtkGetMacro(TwoD, bool);
  vtkBooleanMacro(TwoD, bool);
  ///@}

  ///@{
  /// TF bins along the value. (default: 128)
  vtkSetClampMacro(Bins, int, 2, 4096);
  vtkGetMacro(Bins, int);
  ///@}

  ///@{
  /// Maximum optimisation steps. (default: 500)
  vtkSetClampMacro(Iterations, int, 1, 100000);
  vtkGetMacro(Iterations, int);
  ///@}

  ///@{
  /// Weight of the smoothness prior. (default: 0.01)
  vtkSetClampMacro(Smoothness, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Smoothness, double);
  ///@}

  ///@{
  /// Adam step in logit space. (default: 0.2)
  vtkSetClampMacro(LearningRate, double, 1e-6, 100.0);
  vtkGetMacro(LearningRate, double);
  ///@}

protected:
  vtkDDGReconstructTransferFunction();
  ~vtkDDGReconstructTransferFunction() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) override;

private:
  vtkDDGReconstructTransferFunction(const vtkDDGReconstructTransferFunction&) = delete;
  void operator=(const vtkDDGReconstructTransferFunction&) = delete;

  std::string TargetImageFile;
  std::string ViewFile;
  std::string ViewJSON;
  std::string TargetImageData;
  std::string OutputFile;
  bool TwoD = false;
  int Bins = 128;
  int Iterations = 500;
  double Smoothness = 0.01;
  double LearningRate = 0.2;
};

#endif
