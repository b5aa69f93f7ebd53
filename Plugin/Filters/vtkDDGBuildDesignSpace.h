// vtkDDGBuildDesignSpace.h: builds a model bundle for the input volume (ddg::buildDesignSpace).
#ifndef vtkDDGBuildDesignSpace_h
#define vtkDDGBuildDesignSpace_h

#include "DDGFiltersModule.h" // export macro
#include "vtkDDGAlgorithm.h"

#include "Gallery/BuildDesignSpace.h" // ddg::BuildOptions

#include <memory> // for std::unique_ptr

namespace ddg
{
class RankGroup;
}
#include <string> // for std::string

/**
 * @class vtkDDGBuildDesignSpace
 * @brief Volume -> design exemplars -> trained decoder model -> bundle with its outline.
 *
 * Input: a volume. OutputDirectory: where the bundle is written (a directory; its
 * bundle.json appears only when everything, outline included, is done). SpecFile: a design-space
 * spec JSON (empty: defaults, regions found from the histogram). Count, Minutes, Iterations,
 * OutlineCount, Seed: see ddg::BuildOptions.
 *
 * Output: a one-row vtkTable of the bundle's figures on its held-out exemplars ("PSNR",
 * "SSIM", "EMD", "Invariance", "TrainingSeconds", "Iterations"); field data "ModelDirectory"
 * and "OtherRanksCandidates" (under MPI: the exemplar candidates the other ranks rendered).
 * Progress covers the stages; Abort cancels (no bundle.json written). Bad input gives one
 * error and an empty output.
 *
 * In the background (the panel's way; the GUI or a remote client stays responsive): StartBuild()
 * copies the input volume (updating it first) and runs the same build on a thread of its own;
 * the Build* getters report on it (information properties a client polls), CancelBuild() asks
 * it to stop (it does within ~0.5 s: no bundle left). PlanBuild() fills BuildPlan with what a
 * BudgetMinutes build of the input would cost. Deleting the filter cancels and joins the
 * thread.
 *
 * Under MPI (`mpiexec -np N pvserver`), in the pipeline and in the background alike: every rank
 * takes its own piece (no ghost level) and streams its points to the first rank slab by slab,
 * which assembles the design-space volume (downsampled above DesignVoxels) and the whole's
 * fingerprint: no rank holds the whole volume. Every rank then gets the design-space volume, and
 * the other ranks render their shares of every batch of exemplar candidates (DDGBuildRanks.h)
 * while the first rank renders its own, trains, evaluates and writes the outline alone. The
 * bundle is the one a single process builds (the same exemplars, bit for bit).
 */
class DDGFILTERS_EXPORT vtkDDGBuildDesignSpace : public vtkDDGAlgorithm
{
public:
  static vtkDDGBuildDesignSpace* New();
  vtkTypeMacro(vtkDDGBuildDesignSpace, vtkDDGAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Bundle directory to write. (default: empty)
  vtkSetStdStringFromCharMacro(OutputDirectory);
  vtkGetCharFromStdStringMacro(OutputDirectory);
  ///@}

  ///@{
  /// Design-space spec JSON; empty: the defaults. (default: empty)
  vtkSetStdStringFromCharMacro(SpecFile);
  vtkGetCharFromStdStringMacro(SpecFile);
  ///@}

  ///@{
  /// Training exemplars. (default: 2000)
  vtkSetClampMacro(Count, int, 8, 1000000);
  vtkGetMacro(Count, int);
  ///@}

  ///@{
  /// Exemplar image side. (default: 64)
  vtkSetClampMacro(Size, int, 16, 512);
  vtkGetMacro(Size, int);
  ///@}

  ///@{
  /// Training budget in minutes. (default: 5)
  vtkSetClampMacro(Minutes, double, 0.01, 10000.0);
  vtkGetMacro(Minutes, double);
  ///@}

  ///@{
  /// Training iterations; 0 = until the budget. (default: 0)
  vtkSetClampMacro(Iterations, int, 0, 10000000);
  vtkGetMacro(Iterations, int);
  ///@}

  ///@{
  /// Designs in the outline. (default: 10000)
  vtkSetClampMacro(OutlineCount, int, 3, 1000000);
  vtkGetMacro(OutlineCount, int);
  ///@}

  ///@{
  /// Whole-build budget in minutes: > 0 sizes Count, Minutes and OutlineCount for it
  /// (ddg::planBuild; they are ignored then); 0: those as set. (default: 0)
  vtkSetClampMacro(BudgetMinutes, double, 0.0, 100000.0);
  vtkGetMacro(BudgetMinutes, double);
  ///@}

  ///@{
  /// Volumes above this many voxels are downsampled (box average) for the design space
  /// (ddg::BuildOptions::maxDesignVoxels). (default: 16 Mi)
  vtkSetClampMacro(DesignVoxels, vtkIdType, 4096, vtkIdType(1) << 40);
  vtkGetMacro(DesignVoxels, vtkIdType);
  ///@}

  ///@{
  /// Replace a bundle already in OutputDirectory (else the build refuses). (default: false)
  vtkSetMacro(Overwrite, bool);
  vtkGetMacro(Overwrite, bool);
  ///@}

  ///@{
  /// Seed of exemplars and training. (default: 1)
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  // --- the build in the background ----------------------------------------------------------
  /// Starts building (the properties as set now) on a background thread; the input is updated
  /// and copied first. A build already running: ignored. Bad input fails the build at once
  /// (BuildState "failed", BuildError says why).
  void StartBuild();
  /// Asks the running build to stop (BuildState becomes "cancelled").
  void CancelBuild();
  /// "idle", "running", "done", "failed" or "cancelled".
  const char* GetBuildState();
  /// The running stage: "exemplars", "training", "evaluation", "outline" ("" before).
  const char* GetBuildStage();
  /// The fraction done, in [0, 1].
  double GetBuildProgress();
  /// Seconds since StartBuild (until the end).
  double GetBuildSecondsElapsed();
  /// Estimated seconds left (-1: not known yet).
  double GetBuildSecondsLeft();
  /// Why the build failed ("" otherwise).
  const char* GetBuildError();
  /// After a build that finished: held-out PSNR, SSIM, EMD, invariance, training seconds,
  /// iterations (else zeros).
  double* GetBuildFigures() VTK_SIZEHINT(6);
  /// Computes BuildPlan for the input and BudgetMinutes (a short timed probe).
  void PlanBuild();
  /// The plan (ddg::BuildPlan::toJson) of the last PlanBuild(), with "describe" (text for
  /// people) or "error"; "" before.
  const char* GetBuildPlan();

protected:
  vtkDDGBuildDesignSpace();
  ~vtkDDGBuildDesignSpace() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) override;
  /// Under MPI every rank gets its own piece (no ghost level: the points stream to the first rank,
  /// which builds with the others rendering shares of the exemplars).
  int PieceGhostLevels() override { return 0; }

private:
  vtkDDGBuildDesignSpace(const vtkDDGBuildDesignSpace&) = delete;
  void operator=(const vtkDDGBuildDesignSpace&) = delete;

  /// The build's options from the properties.
  ddg::BuildOptions Options() const;
  /// The input volume, updated and converted (a copy).
  ddg::Volume InputVolume();
  /// Collective, under MPI (every rank runs the command): every rank updates its own piece of the
  /// input, and the first rank gets the design space's input (ddg::designSpaceInputOnRanks; empty
  /// elsewhere). The last one is used again while no rank's piece changed.
  ddg::DesignSpaceInput InputOnRanks(const ddg::RankGroup& ranks);
  /// The build's options and the output folder's check (under MPI, `ranks`: the first rank's,
  /// failing on every rank together: the spec file and the folder are the first rank's).
  ddg::BuildOptions CheckedOptions(const ddg::RankGroup* ranks);

  std::string OutputDirectory;
  std::string SpecFile;
  int Count = 2000;
  int Size = 64;
  double Minutes = 5;
  int Iterations = 0;
  int OutlineCount = 10000;
  vtkIdType DesignVoxels = ddg::kMaxDesignSpaceVoxels;
  int Seed = 1;
  double BudgetMinutes = 0;
  bool Overwrite = false;

  struct Background;
  std::unique_ptr<Background> Worker;
};

#endif
