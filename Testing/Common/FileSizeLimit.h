// FileSizeLimit.h: a "full disk" for this process in tests — files cannot grow beyond a size
// (writes fail with EFBIG, as they would with ENOSPC) while the guard lives.
#pragma once

#include <csignal>
#include <sys/resource.h>

class FileSizeLimit
{
public:
  explicit FileSizeLimit(rlim_t bytes)
  {
    getrlimit(RLIMIT_FSIZE, &Old);
    Handler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit lim = Old;
    lim.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &lim);
  }
  ~FileSizeLimit()
  {
    setrlimit(RLIMIT_FSIZE, &Old);
    std::signal(SIGXFSZ, Handler);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

private:
  rlimit Old{};
  void (*Handler)(int) = nullptr;
};
