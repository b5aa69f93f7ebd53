// Hash.h: 64-bit FNV-1a over bytes fed in parts (cache keys: a volume's version, a bundle's files).
#pragma once

#include <cstddef>
#include <cstdint>

namespace ddg
{

class Fnv1a
{
public:
  void add(const void* data, std::size_t bytes)
  {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i)
      Hash = (Hash ^ p[i]) * 1099511628211ull;
  }
  std::uint64_t value() const { return Hash; }

private:
  std::uint64_t Hash = 1469598103934665603ull;
};

} // namespace ddg
