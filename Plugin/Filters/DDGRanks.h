// DDGRanks.h: the ranks of `mpiexec -np N pvserver` working on one request together — collective
// steps that fail together instead of hanging, and the few collectives the distributed filters
// need (through VTK's multiprocess controller).
#pragma once

#include "DDGFiltersModule.h" // export macro

#include "Common/Error.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

class vtkInformation;
class vtkMultiProcessController;

namespace ddg
{

/// Thrown on the ranks other than the first when a collective step failed (on this rank or
/// another): the first rank reports the error, the others stay quiet.
class DDGFILTERS_EXPORT RankFailed : public Error
{
public:
  explicit RankFailed(const std::string& message)
    : Error(message)
  {
  }
};

/// The ranks that execute one pipeline request together: every rank of ParaView's global
/// controller, each asked for its own piece (UPDATE_PIECE_NUMBER = rank of
/// UPDATE_NUMBER_OF_PIECES = ranks). MPI collectives never time out and a rank that skips one
/// hangs the others, so every step that may throw runs through step(): its failure reaches every
/// rank and they all throw together. No call from worker threads (ParaView initialises MPI
/// without thread support).
class DDGFILTERS_EXPORT RankGroup
{
public:
  /// The group for a request whose output information is `outInfo`, or nullptr when the request
  /// is not collective (one process, or one piece asked of one rank: compute locally).
  static std::unique_ptr<RankGroup> forRequest(vtkInformation* outInfo);
  /// Every rank of ParaView's global controller, for a proxy command that every rank runs in the
  /// same order (pvserver runs a command on all of its ranks); nullptr in one process.
  static std::unique_ptr<RankGroup> global();

  int rank() const { return Rank; }
  int size() const { return Size; }

  /// Runs `work` on this rank, then agrees with the others. When any rank failed, every rank
  /// throws: the first rank a ddg::Error with the first failing rank's message ("rank r: ..."
  /// for another rank; a rank that stopped with ddg::PieceFailed, because another piece failed
  /// inside a collective pass, is not the one reported), ddg::Cancelled when the failure was a
  /// cancellation, the other ranks RankFailed.
  void step(const std::function<void()>& work) const;

  /// Element-wise minimum / maximum / sum over the ranks, in place.
  void allMin(double* values, int count) const;
  void allMax(double* values, int count) const;
  void allSum(double* values, int count) const;
  /// Every rank's `count` values, rank by rank, on every rank.
  std::vector<int> allGather(const int* values, int count) const;
  /// Every rank's `count` floats, rank by rank, into `all` (size() x count) on every rank.
  void allGather(const float* values, long long count, float* all) const;
  /// Every rank's floats, rank by rank, on the first rank (empty elsewhere); rank r sends
  /// counts[r] of them (the same counts on every rank, size() of them).
  std::vector<float> gatherToFirst(
    const std::vector<float>& values, const std::vector<long long>& counts) const;
  /// The first rank's text on every rank.
  std::string broadcast(const std::string& text) const;
  /// The first rank's floats on every rank (resized there).
  void broadcast(std::vector<float>& values) const;

private:
  RankGroup(vtkMultiProcessController* controller);
  vtkMultiProcessController* Controller;
  int Rank = 0;
  int Size = 1;
};

} // namespace ddg
