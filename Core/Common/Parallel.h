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

/// Runs worker(threadId) for every threadId in [0, n) at once, the calling thread being one of
/// them, and returns when all have returned (parallelFor's workers never throw).
using ThreadLauncher = std::function<void(int n, const std::function<void(int threadId)>& worker)>;

/// parallelFor with its workers run by `launch` instead of new std::threads: e.g. on a thread
/// pool that would otherwise spin beside them (libtorch's OpenMP threads, Neural/NeuralNetworks.h).
void parallelFor(std::int64_t count, int threads,
  const std::function<void(std::int64_t index, int threadId)>& body, const ThreadLauncher& launch);

/// The thread count parallelFor() will actually use for `threads` (resolves 0, clamps to count).
int resolveThreadCount(int threads, std::int64_t count);

} // namespace ddg
