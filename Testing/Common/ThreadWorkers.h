// ThreadWorkers.h: exemplar workers (ddg::ExemplarWorkers) on threads of the test's process, each
// serving over a pair of message queues as another process serves over its connection
// (ddg::serveExemplars).
#pragma once

#include "Design/CandidateRenderer.h"

#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ddg
{
namespace testing
{

class ThreadWorkers : public ExemplarWorkers
{
public:
  ThreadWorkers(const Volume& volume, int n)
    : Links(static_cast<size_t>(n))
  {
    for (auto& link : Links)
      Threads.emplace_back(
        [&volume, &link]
        {
          serveExemplars(
            volume, [&link] { return link.in.pop(); },
            [&link](const std::string& m) { link.out.push(m); }, 1);
        });
  }
  ~ThreadWorkers() override
  {
    for (auto& link : Links)
      link.in.push("end");
    for (auto& t : Threads)
      t.join();
  }
  int size() const override { return static_cast<int>(Links.size()); }
  void send(int w, const std::string& m) override
  {
    Links[static_cast<size_t>(w)].in.push(m);
    ++Messages;
    OutlineRequests += m.rfind("outline ", 0) == 0;
  }
  std::string receive(int w) override { return Links[static_cast<size_t>(w)].out.pop(); }
  int Messages = 0;
  int OutlineRequests = 0; ///< of them, requests to render outline designs

private:
  struct Queue
  {
    std::mutex m;
    std::condition_variable c;
    std::deque<std::string> q;
    void push(const std::string& s)
    {
      std::lock_guard<std::mutex> lock(m);
      q.push_back(s);
      c.notify_one();
    }
    std::string pop()
    {
      std::unique_lock<std::mutex> lock(m);
      c.wait(lock, [this] { return !q.empty(); });
      std::string s = q.front();
      q.pop_front();
      return s;
    }
  };
  struct Link
  {
    Queue in, out;
  };
  std::deque<Link> Links;
  std::vector<std::thread> Threads;
};

} // namespace testing
} // namespace ddg
