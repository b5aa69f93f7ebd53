// Error.h: the one exception type Core throws for bad input (files, JSON, parameters).
#pragma once

#include <stdexcept>
#include <string>

namespace ddg
{

/// Thrown by Core for invalid input: unreadable files, malformed JSON, degenerate cameras,
/// out-of-range parameters. The message is meant for the user as-is (no "Error:" prefix).
class Error : public std::runtime_error
{
public:
  explicit Error(const std::string& message)
    : std::runtime_error(message)
  {
  }
};

/// A library's reason on one line: its first (libpng, say, adds "PNG read error: IDAT: ..." and
/// "PNG library error" after the reason itself; libtorch adds a C++ stack).
inline std::string firstLine(const std::string& reason)
{
  const size_t start = reason.find_first_not_of(" \n");
  if (start == std::string::npos)
    return "";
  return reason.substr(start, reason.find('\n', start) - start);
}

} // namespace ddg
