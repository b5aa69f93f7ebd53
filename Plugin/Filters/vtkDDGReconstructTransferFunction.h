// vtkDDGReconstructTransferFunction.h: finds the TF whose rendering of the input volume matches a
// target image (ddg::reconstructTransferFunction: the differentiable ray caster and Adam), or,
// with MatchPicture on, a TF and the camera for a picture as users have it (ddg::matchPicture).
#ifndef vtkDDGReconstructTransferFunction_h
#define vtkDDGReconstructTransferFunction_h

#include "DDGFiltersModule.h" // export macro
#include "vtkDDGAlgorithm.h"
#include "vtkSmartPointer.h" // for Preview

#include <memory>
#include <string>

class vtkImageData;
namespace ddg
{
struct ReconstructionOptions;
class KindChecker;
class RanksFingerprint;
}

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
 * LookupTable.RGBPoints / ScalarOpacityFunction.Points; its "Name" is "DDG reconstruction" or
 * "DDG match", and with OutputFile the volume's array, that origin, the file's stem and the time,
 * so that each file imports into ParaView), "Converged", "Iterations" and "Background" (bottom RGB,
 * top RGB: what the target was compared over, see EstimateBackground). With TwoD on, the rows are
 * the 2D table (value fastest, plus "GradientMagnitude") and the field data holds
 * "TransferFunction2D" (the DDG 2D TF JSON) instead of "Preset". OutputFile, when set, receives the
 * same JSON (written atomically).
 *
 * MatchPicture on (ddg::matchPicture, the `ddg reconstruct` of pictures whose camera, framing
 * and background nobody wrote down): the target may have any size; its background is estimated
 * and overlays are masked; the camera is the given view (ViewJSON / ViewFile, its size replaced
 * by the picture's) or, without one or with EstimateCamera on, found from ParaView's reset
 * camera. InitialTransferFunction (a preset's JSON text, e.g. a queried design's) is where the
 * fit starts. The table's field data then also holds "View" (the picture's camera as view JSON,
 * with the estimated background), "CameraEstimated", "Overlap" (silhouette IoU of the camera),
 * "FitPSNR" (Core's PSNR of the fit over the compared pixels), "PicturePSNR" (before, after: the
 * initial preset's and the output preset's render, as ParaView gets them, at the found view over
 * the estimated background against the picture, overlay pixels left out; before is NaN without
 * InitialTransferFunction), "Background" (bottom RGB, top RGB),
 * "GradientBackground", "Orbit" (azimuth, elevation, roll from the reset camera, degrees),
 * "Zoom", "Pan" (right, up in view heights), "Timings" (background, camera, fit, total, s) and
 * "Crop" (x, y, width, height: the part of the picture matched, inside a letterbox; the view is
 * its size). Output port 1 is then an image of that part's size: "Image" (the found TF rendered
 * at the found view over the background, RGB 8-bit), "Foreground" and "Overlay" (the masks,
 * 0/255).
 * Progress text is the stage ("background", "camera", "fit"); GetPreview returns the latest
 * preview render (every PreviewEvery fit steps).
 *
 * Progress is reported per step and Abort stops the optimisation (LastError "cancelled", empty
 * outputs). Bad input (missing or unreadable files, a target of the wrong size without
 * MatchPicture, a degenerate view, a constant volume; with MatchPicture: a uniform picture, one
 * no camera explains, a picture under 16 pixels a side) gives one error message and empty
 * outputs.
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
  /// The target as a base64-encoded image file (PNG, JPEG, TIFF, BMP, GIF or WebP); when set, used
  /// instead of TargetImageFile. (default: empty)
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
  /// The picture's background colour is estimated from its border: without MatchPicture the
  /// view's background is kept when the border agrees with it (within 6 levels of 255, or 3x
  /// the border's noise) or has no one colour, else the border's colour is used and a warning
  /// says so; with MatchPicture the estimate (uniform or ParaView's gradient) is used. Off: the
  /// picture's background is Background, with a warning when the border disagrees. RGBA
  /// targets have no background. (default: on)
  vtkSetMacro(EstimateBackground, bool);
  vtkGetMacro(EstimateBackground, bool);
  vtkBooleanMacro(EstimateBackground, bool);
  ///@}

  ///@{
  /// The picture's background colour (RGB in [0, 1]) when EstimateBackground is off.
  /// (default: 0.329, 0.349, 0.427, ParaView's)
  vtkSetVector3Macro(Background, double);
  vtkGetVector3Macro(Background, double);
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
  /// Seed of the fit's random draws (the pixels sampled; Carry Look: the colour distance's
  /// directions), as `ddg reconstruct --seed`. (default: 1)
  vtkSetClampMacro(Seed, int, 0, VTK_INT_MAX);
  vtkGetMacro(Seed, int);
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

  ///@{
  /// Match a picture as users have it (ddg::matchPicture: any size, background estimated,
  /// overlays masked, the camera given or estimated) instead of reconstructing from a
  /// screenshot at a known view of its size. (default: off)
  vtkSetMacro(MatchPicture, bool);
  vtkGetMacro(MatchPicture, bool);
  vtkBooleanMacro(MatchPicture, bool);
  ///@}

  ///@{
  /// The target is a picture of another volume of the same kind (ddg::carryLook): its look is
  /// carried over to the input (its colours matched to the input's feature regions by rank,
  /// refined by colour distribution; no camera). Takes precedence over MatchPicture. A view
  /// (ViewJSON or ViewFile) gives only the lighting the look is fitted and shown under (its
  /// camera is not used); without one the look is unlit.
  /// The table's field data then holds "Preset", "View" (where the look is shown: azimuth 30,
  /// elevation 20 from ParaView's reset camera, 256 x 256, over the picture's background),
  /// "Background", "Regions" (per feature region of the input: value from, value to, the
  /// picture's red, green, blue it was matched with, that colour's share of the picture's
  /// object), "ColourDistance" (start, end: CIELAB sliced Wasserstein), "ShapeAgreement" (the
  /// input's best silhouette IoU against the picture's object, and 1 when it reaches 0.6, else
  /// 0: the shapes disagree, the picture may show a volume of another kind), "OverlayShare",
  /// "Timings" (total, s), "Iterations" and "Converged", and with KindNetwork "Kind" (below);
  /// output port 1 the render at View. Progress text is "carry" (then "kind"); GetPreview shows
  /// the fit every PreviewEvery steps. (default: off)
  vtkSetMacro(CarryLook, bool);
  vtkGetMacro(CarryLook, bool);
  vtkBooleanMacro(CarryLook, bool);
  ///@}

  ///@{
  /// CarryLook: the kind network (a directory such as Data/Models/kind; ddg::KindNetwork) that
  /// checks whether the picture shows a volume of the input's kind. The field "Kind" then holds
  /// its JSON {"agreement", "threshold", "differs", "picture_like", "volume_like"}, and a warning
  /// goes to the Output Messages when it differs. The input's reference (its own exemplars, about
  /// 10 s) is kept for the next run. Not checked under MPI (the exemplars need the whole volume)
  /// or in a build without libtorch; a network that cannot be read is a warning, not an error.
  /// (default: empty, no check)
  vtkSetStdStringFromCharMacro(KindNetwork);
  vtkGetCharFromStdStringMacro(KindNetwork);
  ///@}

  ///@{
  /// MatchPicture: search the camera even when a view is given (the view is then a hint the
  /// search starts from); without a view the camera is always estimated. (default: off)
  vtkSetMacro(EstimateCamera, bool);
  vtkGetMacro(EstimateCamera, bool);
  vtkBooleanMacro(EstimateCamera, bool);
  ///@}

  ///@{
  /// MatchPicture: the TF the fit starts from, as a ParaView preset's JSON text (1D); empty:
  /// grey at opacity 0.02. (default: empty)
  vtkSetStdStringFromCharMacro(InitialTransferFunction);
  vtkGetCharFromStdStringMacro(InitialTransferFunction);
  ///@}

  ///@{
  /// MatchPicture: opacity unit distance of the views; 0: ParaView's default for the volume (or
  /// the given view's). (default: 0)
  vtkSetClampMacro(OpacityUnitDistance, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(OpacityUnitDistance, double);
  ///@}

  ///@{
  /// MatchPicture: camera candidates scored by a short fit. (default: 6)
  vtkSetClampMacro(CameraCandidates, int, 1, 64);
  vtkGetMacro(CameraCandidates, int);
  ///@}

  ///@{
  /// MatchPicture: below this silhouette overlap (IoU) of the best camera the match fails with
  /// "no camera explains the picture". (default: 0.6)
  vtkSetClampMacro(MinimumOverlap, double, 0.0, 1.0);
  vtkGetMacro(MinimumOverlap, double);
  ///@}

  ///@{
  /// MatchPicture: weight of the empty-space term (background pixels pull the render to
  /// transparent). (default: 1)
  vtkSetClampMacro(EmptySpaceWeight, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(EmptySpaceWeight, double);
  ///@}

  ///@{
  /// MatchPicture: mask overlays (parts of the picture the object does not explain).
  /// (default: on)
  vtkSetMacro(MaskOverlays, bool);
  vtkGetMacro(MaskOverlays, bool);
  vtkBooleanMacro(MaskOverlays, bool);
  ///@}

  ///@{
  /// MatchPicture: render a preview every this many fit steps (GetPreview); 0: none.
  /// (default: 0)
  vtkSetClampMacro(PreviewEvery, int, 0, 100000);
  vtkGetMacro(PreviewEvery, int);
  ///@}

  /// The latest preview of a running match: the current TF at the found view over the
  /// background, RGB 8-bit array "Image" at a quarter of the picture's size (empty before the
  /// first preview). Read it from a ProgressEvent observer; it is the filter's own object.
  vtkImageData* GetPreview();

protected:
  vtkDDGReconstructTransferFunction();
  ~vtkDDGReconstructTransferFunction() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  /// Under `mpiexec -np N pvserver` the reconstruction runs on pieces (one ghost level: each
  /// rank renders its own, ExecuteOnRanks); MatchPicture and CarryLook gather the volume on the
  /// first rank.
  int PieceGhostLevels() override;
  void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) override;
  void ExecuteOnRanks(const ddg::RankGroup& ranks, vtkImageData* input, vtkDataArray* array,
    vtkInformationVector* outputVector);
  void ExecuteMatch(vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector);
  void ExecuteCarryLook(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector);

private:
  vtkDDGReconstructTransferFunction(const vtkDDGReconstructTransferFunction&) = delete;
  /// The fit's options from the properties.
  ddg::ReconstructionOptions Options() const;
  void operator=(const vtkDDGReconstructTransferFunction&) = delete;

  std::string TargetImageFile;
  std::string ViewFile;
  std::string ViewJSON;
  std::string TargetImageData;
  std::string OutputFile;
  bool EstimateBackground = true;
  double Background[3] = { 0.329, 0.349, 0.427 };
  bool TwoD = false;
  int Bins = 128;
  int Iterations = 500;
  int Seed = 1;
  double Smoothness = 0.01;
  double LearningRate = 0.2;
  bool MatchPicture = false;
  bool CarryLook = false;
  bool EstimateCamera = false;
  std::string InitialTransferFunction;
  std::string KindNetwork;
  std::shared_ptr<ddg::KindChecker> KindReferences;       // the loaded network and what it keeps
  std::shared_ptr<ddg::RanksFingerprint> KindFingerprint; // under MPI: the input's, kept
  double OpacityUnitDistance = 0.0;
  int CameraCandidates = 6;
  double MinimumOverlap = 0.6;
  double EmptySpaceWeight = 1.0;
  bool MaskOverlays = true;
  int PreviewEvery = 0;
  vtkSmartPointer<vtkImageData> Preview;
};

#endif
