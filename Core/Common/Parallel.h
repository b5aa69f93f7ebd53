// Parallel.h: a minimal parallel-for over an index range on std::threads.
#pragma once

#include <cstdint>
#include <functional>

namespace ddg
{

/// Number of worker threads used when a caller asks for 0 ("all cores"):
/// std::thread::hardware_concurrency(), at least 1.
int defaultThreadCount();

/// Calls body(index, threadId) for every index in [0, count), distributing indices
/// dynamically (an atomic counter) over `threads` workers (0 = defaultThreadCount()).
/// threadId is in [0, threads). The calling thread is one of the workers.
/// If a body throws, the remaining indices are skipped and the first exception is rethrown.
void parallelFor(std::int64_t count, int threads,
  const std::function<void(std::int64_t index, int threadId)>& body);

/// The thread count parallelFor() will actually use for `threads` (resolves 0, clamps to count).
int resolveThreadCount(int threads, std::int64_t count);

} // namespace ddg
