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

} // namespace ddg
