// DDGBuildRanks.h: the ranks of `mpiexec -np N pvserver` rendering a design-space build's
// exemplars with the first rank. Every rank gets the design-space volume once (through MPI); the
// first rank then sends each other rank its share of every batch of candidates over a TCP
// connection of their own (ParaView initialises MPI without thread support, and the panel's build
// runs on a thread: the ranks' build traffic never touches MPI).
#pragma once

#include "DDGFiltersModule.h" // export macro
#include "DDGRanks.h"

#include "Design/ExemplarGenerator.h"
#include "Gallery/BuildPlan.h"

#include <atomic>
#include <functional>
#include <memory>

namespace ddg
{

/// A build's exemplar renderers over the ranks.
struct DDGFILTERS_EXPORT BuildCrew
{
  /// The first rank's: the other ranks as ExemplarWorkers (ending it sends them "end" and closes
  /// their connections); null elsewhere.
  std::unique_ptr<ExemplarWorkers> workers;
  /// The other ranks': answers the first rank's messages (serveExemplars, every core) until it
  /// ends them, its connection closes or `stop` is set (checked every second); any thread.
  /// Throws ddg::Error when the connection broke. Empty on the first rank.
  std::function<void(const std::atomic<bool>& stop)> serve;
};

/// Collective (every rank, on the thread that runs ParaView's requests): hands the first rank's
/// design-space volume (`input`, empty elsewhere) to every rank and connects every other rank to
/// the first (a TCP port the first rank opens on its host name; 30 s to connect). Every rank
/// throws together when one fails.
DDGFILTERS_EXPORT BuildCrew buildCrewOnRanks(const RankGroup& ranks, const DesignSpaceInput& input);

} // namespace ddg
