// PieceExchange.h: how the pieces of one volume, each in its own process (ParaView's ranks under
// `mpiexec -np N pvserver`), exchange what the differentiable renderer's sort-last passes need.
// Core has no MPI: the plugin implements this over VTK's multiprocess controller
// (Plugin/Filters/DDGPieces), the tests over threads.
#pragma once

#include "Common/Error.h"

#include <cstdint>
#include <string>

namespace ddg
{

/// The pieces of one volume working together. Every call is collective: every piece makes the
/// same calls in the same order, with the same counts.
class PieceExchange
{
public:
  virtual ~PieceExchange() = default;
  /// This piece's index, 0 .. pieces() - 1.
  virtual int piece() const = 0;
  virtual int pieces() const = 0;
  /// Every piece's `count` floats, piece by piece, into `all` (pieces() x count floats).
  virtual void allGather(const float* local, std::int64_t count, float* all) const = 0;
};

/// Thrown on a piece when another piece's part of a collective pass failed: that piece throws
/// its own error and reports it; this one stops without a message of its own.
class PieceFailed : public Error
{
public:
  PieceFailed()
    : Error("another piece of the volume failed")
  {
  }
};

} // namespace ddg
