// vtkDDGBuildDesignSpace.h: builds a model bundle for the input volume (ddg::buildDesignSpace).
#ifndef vtkDDGBuildDesignSpace_h
#define vtkDDGBuildDesignSpace_h

#include "DDGFiltersModule.h" // export macro
#include "vtkDDGAlgorithm.h"

#include <string>

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
 * "SSIM", "EMD", "Invariance", "TrainingSeconds", "Iterations"); field data "ModelDirectory".
 * Progress covers the three stages; Abort cancels (no bundle.json written). Bad input gives one
 * error and an empty output.
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
  /// Seed of exemplars and training. (default: 1)
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

protected:
  vtkDDGBuildDesignSpace();
  ~vtkDDGBuildDesignSpace() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) override;

private:
  vtkDDGBuildDesignSpace(const vtkDDGBuildDesignSpace&) = delete;
  void operator=(const vtkDDGBuildDesignSpace&) = delete;

  std::string OutputDirectory;
  std::string SpecFile;
  int Count = 2000;
  int Size = 64;
  double Minutes = 5;
  int Iterations = 0;
  int OutlineCount = 10000;
  int Seed = 1;
};

#endif
