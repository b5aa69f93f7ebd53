// DDGFilterSupport.h: pipeline chores shared by the Design Gallery filters.
#pragma once

#include "DDGFiltersModule.h" // export macro

#include <vtkType.h>

#include <string>

class vtkAlgorithm;
class vtkInformation;
class vtkInformationVector;

namespace ddg
{

/// Asks for the input's whole extent (the filters need the whole volume, whatever image extent
/// is requested downstream). Distributed runs (pvserver under MPI): piece 0 asks for the whole
/// volume and computes; every other piece asks for nothing (an empty extent) and outputs empty
/// data (see skipPiece), so the result exists once, on the first rank.
DDGFILTERS_EXPORT void requestWholeInputExtent(vtkInformationVector** inputVector);

/// Asks for this rank's piece of the input (the piece and number of pieces asked of the output)
/// with `ghostLevels` ghost levels more than asked downstream, over the whole extent: for the
/// filters that work on pieces under MPI (vtkDDGAlgorithm::PieceGhostLevels).
DDGFILTERS_EXPORT void requestInputPiece(
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, int ghostLevels);

/// True for the pieces that do not compute (update piece > 0 of a distributed run); their
/// outputs are then initialized empty. Call first in RequestData and return 1 when true.
DDGFILTERS_EXPORT bool skipPiece(vtkInformationVector* outputVector);

/// Sets a 2D image output's whole extent (width x height; empty when either is < 1), origin 0
/// and spacing 1.
DDGFILTERS_EXPORT void setImageInformation(vtkInformation* outInfo, int width, int height);

/// Reports each failure once: the pipeline may re-run a failed request (an empty image never
/// satisfies the update extent), so the same error for the same state (the filter's and its
/// producer's parameters, not the data's MTime, which moves whenever the producer re-executes)
/// is not repeated.
class DDGFILTERS_EXPORT ErrorOnce
{
public:
  /// True when `message` should be reported now for `filter`'s current state.
  bool report(vtkAlgorithm* filter, const std::string& message);
  void clear() { Last.clear(); }

private:
  std::string Last;
  vtkMTimeType LastState = 0;
};

} // namespace ddg
