// Parallel.cxx: parallelFor on std::threads with dynamic scheduling.
#include "Common/Parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace ddg
{

int defaultThreadCount()
{
  unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

int resolveThreadCount(int threads, std::int64_t count)
{
  int n = threads > 0 ? threads : defaultThreadCount();
  if (count < n)
  {
    n = static_cast<int>(std::max<std::int64_t>(count, 1));
  }
  return n;
}

void parallelFor(std::int64_t count, int threads,
  const std::function<void(std::int64_t index, int threadId)>& body)
{
  parallelFor(count, threads, body,
    [](int n, const std::function<void(int)>& worker)
    {
      std::vector<std::thread> pool;
      pool.reserve(static_cast<size_t>(n - 1));
      for (int t = 1; t < n; ++t)
      {
        pool.emplace_back(worker, t);
      }
      worker(0);
      for (auto& t : pool)
      {
        t.join();
      }
    });
}

void parallelFor(std::int64_t count, int threads,
  const std::function<void(std::int64_t index, int threadId)>& body, const ThreadLauncher& launch)
{
  if (count <= 0)
  {
    return;
  }
  const int n = resolveThreadCount(threads, count);
  std::atomic<std::int64_t> next{ 0 };
  std::atomic<bool> failed{ false };
  std::exception_ptr firstError;
  std::mutex errorMutex;

  auto worker = [&](int threadId)
  {
    while (!failed.load(std::memory_order_relaxed))
    {
      const std::int64_t i = next.fetch_add(1, std::memory_order_relaxed);
      if (i >= count)
      {
        break;
      }
      try
      {
        body(i, threadId);
      }
      catch (...)
      {
        std::lock_guard<std::mutex> lock(errorMutex);
        if (!firstError)
        {
          firstError = std::current_exception();
        }
        failed = true;
      }
    }
  };

  launch(n, worker);
  if (firstError)
  {
    std::rethrow_exception(firstError);
  }
}

} // namespace ddg
