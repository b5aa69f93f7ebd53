// vtkDDGAlgorithm.h: the base of every Design Gallery filter — the pipeline chores they share,
// so that a filter's file holds only what is its own (in the manner of TTK's ttkAlgorithm).
#ifndef vtkDDGAlgorithm_h
#define vtkDDGAlgorithm_h

#include "DDGFiltersModule.h" // export macro
#include "vtkAlgorithm.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

class vtkDataArray;
class vtkImageData;
namespace ddg
{
class RankGroup;
}

/**
 * @class vtkDDGAlgorithm
 * @brief Base of the DDG filters: one vtkImageData input (the volume), outputs declared by the
 * subclass (FillOutputPortInformation: "vtkImageData" or "vtkTable" per port).
 *
 * It owns, for every filter:
 * - `LastError`: the message of the last failed run, empty after a run without error (an
 *   information property of every filter's XML; the panel and pvpython read it);
 * - reporting each failure once (the pipeline may re-run a failed request: the same message
 *   for the same state is not repeated, see ddg::ErrorOnce);
 * - the request of the input's whole extent (the filters need the whole volume);
 * - under MPI: piece 0 computes on the whole volume and the other pieces output empty data,
 *   unless the filter works on pieces (PieceGhostLevels >= 0: every rank gets its own piece
 *   with that many ghost levels, Execute runs on every rank with Ranks() set; the other
 *   ranks' failures reach the first rank, which reports them);
 * - the output reset before a run and after a failure or a cancellation (ddg::Cancelled:
 *   LastError "cancelled", no error message); AbortExecute cleared before each run (VTK 9.2
 *   keeps it set after an abort);
 * - the image information of its image outputs (port 0: PreviewSize; other ports an empty
 *   extent, filled when they run: so that an empty image does not re-run the filter).
 *
 * A subclass implements Execute (throwing ddg::Error, or any std::exception, for bad input)
 * and, if port 0 is an image, PreviewSize.
 */
class DDGFILTERS_EXPORT vtkDDGAlgorithm : public vtkAlgorithm
{
public:
  vtkTypeMacro(vtkDDGAlgorithm, vtkAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The last error message (empty after a run without error; "cancelled" after a cancelled
  /// run).
  vtkGetCharFromStdStringMacro(LastError);

  vtkTypeBool ProcessRequest(vtkInformation* request, vtkInformationVector** inputVector,
    vtkInformationVector* outputVector) override;

protected:
  vtkDDGAlgorithm();
  ~vtkDDGAlgorithm() override;

  /// The filter's own work: read `input`'s `array` (the input array to process: point scalars
  /// by default) and fill the outputs (already reset to empty). Throws for bad input.
  virtual void Execute(
    vtkImageData* input, vtkDataArray* array, vtkInformationVector* outputVector) = 0;

  /// The (width, height) of output port 0 when it is an image, from the filter's properties
  /// ((0, 0) when they do not say yet: the error comes from Execute). Default: (0, 0).
  virtual void PreviewSize(int& width, int& height);

  /// Ghost levels the filter needs on its own piece when it works distributed under MPI; -1
  /// (default): it needs the whole volume, on the first rank.
  virtual int PieceGhostLevels();
  /// The ranks computing the current request together (during Execute), or nullptr when it is
  /// computed by one process on the whole volume.
  const ddg::RankGroup* Ranks() const;
  /// The input's whole extent (during Execute).
  const int* InputWholeExtent() const;

  int FillInputPortInformation(int port, vtkInformation* info) override;

private:
  vtkDDGAlgorithm(const vtkDDGAlgorithm&) = delete;
  void operator=(const vtkDDGAlgorithm&) = delete;

  int RequestDataObject(vtkInformationVector* outputVector);
  void ResetOutputs(vtkInformationVector* outputVector);

  std::string LastError;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
