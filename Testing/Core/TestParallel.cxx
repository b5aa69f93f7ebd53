// TestParallel.cxx: parallelFor, on new threads and through a caller's launcher.
#include "Common/Parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

TEST(Parallel, EveryIndexOnceOnEachLauncher)
{
  const std::int64_t count = 1000;
  // a launcher of its own: the workers on threads it starts, recording their ids
  std::vector<int> launched;
  std::mutex m;
  const ddg::ThreadLauncher own = [&](int n, const std::function<void(int)>& worker)
  {
    std::vector<std::thread> pool;
    for (int t = 0; t < n; ++t)
    {
      launched.push_back(t);
      pool.emplace_back(worker, t);
    }
    for (auto& t : pool)
      t.join();
  };
  for (const bool custom : { false, true })
  {
    std::vector<std::atomic<int>> seen(count);
    std::set<int> ids;
    const auto body = [&](std::int64_t i, int id)
    {
      seen[static_cast<size_t>(i)]++;
      std::lock_guard<std::mutex> lock(m);
      ids.insert(id);
    };
    if (custom)
      ddg::parallelFor(count, 3, body, own);
    else
      ddg::parallelFor(count, 3, body);
    for (const auto& s : seen)
      ASSERT_EQ(s.load(), 1);
    for (const int id : ids)
      EXPECT_TRUE(id >= 0 && id < 3) << id;
  }
  EXPECT_EQ(launched, (std::vector<int>{ 0, 1, 2 }));
  // fewer indices than threads: as many workers as indices
  launched.clear();
  ddg::parallelFor(
    2, 8, [](std::int64_t, int) {}, own);
  EXPECT_EQ(launched.size(), 2u);
  // nothing to do: the launcher is not called
  launched.clear();
  ddg::parallelFor(
    0, 2, [](std::int64_t, int) {}, own);
  EXPECT_TRUE(launched.empty());
}

TEST(Parallel, ABodysExceptionReachesTheCallerThroughALauncher)
{
  const ddg::ThreadLauncher inline1 = [](int n, const std::function<void(int)>& worker)
  {
    for (int t = 0; t < n; ++t)
      worker(t); // one after another: the workers must not throw out of the launcher
  };
  std::atomic<int> ran{ 0 };
  EXPECT_THROW(ddg::parallelFor(
                 100, 2,
                 [&](std::int64_t i, int)
                 {
                   ran++;
                   if (i == 10)
                     throw std::runtime_error("index 10");
                 },
                 inline1),
    std::runtime_error);
  EXPECT_LT(ran.load(), 100); // the indices after the failure are skipped
}
