// TempDir.h: a temporary directory of this test process. ctest runs each gtest case as its own
// process, two at a time: files under one shared /tmp name (a dataset one test regenerates while
// another reads it) made tests fail at random. Each process gets /tmp/ddg-test-<pid>/, removed
// when the process exits.
#pragma once

#include <filesystem>
#include <string>
#include <unistd.h>

namespace ddg::testing
{
inline std::string tempDir()
{
  struct Dir
  {
    std::string path;
    Dir()
      : path((std::filesystem::temp_directory_path() / ("ddg-test-" + std::to_string(::getpid())))
               .string())
    {
      std::filesystem::create_directories(path);
    }
    ~Dir()
    {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}
} // namespace ddg::testing
