// BenchBuildCancel.cxx: how fast a design-space build stops when asked, per stage — the panel's
// Cancel (issue 18: within 1 s). For each stage (exemplars, training, evaluation, outline) a
// build of the volume is started, a watcher thread asks it to stop `delay` seconds into that
// stage (an atomic flag the progress callback returns), and the time from the request to
// buildDesignSpace returning (ddg::Cancelled, staging folder removed) is printed with the
// longest gap between progress calls seen in the stage. Prints figures; asserts nothing.
//
//   BenchBuildCancel [VOLUME] [OUTDIR]   (default: Data/Volumes/neghip.vti, /tmp)
#include "DDGVolumeAdaptor.h"

#include "Gallery/BuildDesignSpace.h"
#include "Render/RayCaster.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>

using Clock = std::chrono::steady_clock;

int main(int argc, char** argv)
{
  const std::string path = argc > 1 ? argv[1] : std::string(DDG_DATA_DIR) + "/Volumes/neghip.vti";
  const std::string out =
    (std::filesystem::path(argc > 2 ? argv[2] : "/tmp") / "ddg-bench-build-cancel").string();
  const ddg::Volume volume = ddg::readVolumeFile(path);
  ddg::BuildOptions o;
  o.count = 2000;
  o.heldout = 200;
  o.minutes = 0.5;
  o.outlineCount = 4000;
  std::printf("volume %s (%dx%dx%d), %d exemplars, %.1f min training, %d outline designs\n",
    path.c_str(), volume.dims()[0], volume.dims()[1], volume.dims()[2], o.count, o.minutes,
    o.outlineCount);
  std::printf("%-11s %10s %16s %s\n", "stage", "latency s", "longest gap s", "folder left");
  for (const std::string target : { "exemplars", "training", "evaluation", "outline" })
  {
    std::filesystem::remove_all(out);
    std::mutex mutex;
    std::string stage;
    Clock::time_point stageStart, last;
    double longestGap = 0;
    std::atomic<bool> stop{ false }, finished{ false };
    Clock::time_point requested;
    const double delay = target == "evaluation" ? 0.3 : 1.0;
    std::thread watcher(
      [&]()
      {
        while (!finished)
        {
          {
            std::lock_guard<std::mutex> lock(mutex);
            if (stage == target &&
              std::chrono::duration<double>(Clock::now() - stageStart).count() > delay)
            {
              requested = Clock::now();
              stop = true;
              return;
            }
          }
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
      });
    double latency = -1;
    try
    {
      ddg::buildDesignSpace(volume, path, out, o,
        [&](const std::string& s, double)
        {
          std::lock_guard<std::mutex> lock(mutex);
          const auto now = Clock::now();
          if (s != stage)
          {
            stage = s;
            stageStart = now;
          }
          else if (s == target)
            longestGap = std::max(longestGap, std::chrono::duration<double>(now - last).count());
          last = now;
          return !stop;
        });
    }
    catch (const ddg::Cancelled&)
    {
      latency = std::chrono::duration<double>(Clock::now() - requested).count();
    }
    finished = true;
    watcher.join();
    std::printf("%-11s %10.3f %16.3f %s\n", target.c_str(), latency, longestGap,
      std::filesystem::exists(out) ? "yes" : "no");
    std::fflush(stdout);
  }
  return 0;
}
