// VolumeIO.cxx: raw(.gz) + JSON volume reader.
#include "Volume/VolumeIO.h"

#include "Common/Error.h"

#include <nlohmann/json.hpp>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <sstream>

namespace ddg
{
namespace
{

bool endsWith(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() &&
    s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string directoryOf(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

bool fileExists(const std::string& path)
{
  std::ifstream f(path, std::ios::binary);
  return static_cast<bool>(f);
}

// Reads exactly `expected` bytes of the (gzipped or plain) file into `out`; refuses a file that
// holds fewer or more.
void readExactly(const std::string& path, unsigned char* out, size_t expected)
{
  gzFile f = gzopen(path.c_str(), "rb"); // reads plain files too
  if (!f)
  {
    throw Error("cannot open raw volume file '" + path + "'");
  }
  size_t total = 0;
  unsigned char extra = 0;
  while (total <= expected)
  {
    unsigned char* at = total < expected ? out + total : &extra;
    const unsigned chunk =
      total < expected ? static_cast<unsigned>(std::min<size_t>(expected - total, 1u << 30)) : 1u;
    const int got = gzread(f, at, chunk);
    if (got < 0)
    {
      int err = 0;
      std::string msg = gzerror(f, &err);
      gzclose(f);
      throw Error("cannot read raw volume file '" + path + "': " + msg);
    }
    if (got == 0)
    {
      break;
    }
    total += static_cast<size_t>(got);
  }
  gzclose(f);
  if (total != expected)
  {
    std::ostringstream msg;
    msg << "raw volume file '" << path << "' holds " << (total > expected ? "more than " : "")
        << (total > expected ? expected : total) << " bytes but its JSON describes " << expected;
    throw Error(msg.str());
  }
}

// The file's scalars read straight into the volume's buffer (no second copy when T is the type
// the volume keeps).
template <typename T>
Volume readAs(const std::string& path, const std::array<int, 3>& dims,
  const std::array<double, 3>& origin, const std::array<double, 3>& spacing, bool swap,
  ScalarType type)
{
  const size_t n = static_cast<size_t>(dims[0]) * dims[1] * dims[2];
  std::vector<T> data(n);
  readExactly(path, reinterpret_cast<unsigned char*>(data.data()), n * sizeof(T));
  if (swap && sizeof(T) > 1)
  {
    for (T& v : data)
    {
      auto* p = reinterpret_cast<unsigned char*>(&v);
      for (size_t a = 0, b = sizeof(T) - 1; a < b; ++a, --b)
      {
        std::swap(p[a], p[b]);
      }
    }
  }
  return Volume::fromVector(dims, origin, spacing, std::move(data), type);
}

} // namespace

bool isRawVolumePath(const std::string& path)
{
  return endsWith(path, ".json") || endsWith(path, ".raw") || endsWith(path, ".raw.gz");
}

Volume readRawVolume(const std::string& path)
{
  std::string jsonPath = path;
  if (endsWith(path, ".raw.gz"))
  {
    jsonPath = path.substr(0, path.size() - 7) + ".json";
  }
  else if (endsWith(path, ".raw"))
  {
    jsonPath = path.substr(0, path.size() - 4) + ".json";
  }
  std::ifstream in(jsonPath);
  if (!in)
  {
    throw Error("cannot open volume description '" + jsonPath + "'");
  }
  nlohmann::json j;
  try
  {
    in >> j;
  }
  catch (const std::exception& e)
  {
    throw Error("volume description '" + jsonPath + "' is not valid JSON: " + e.what());
  }
  auto fail = [&](const std::string& what)
  { throw Error("volume description '" + jsonPath + "': " + what); };
  if (!j.is_object() || !j.contains("dims") || !j.contains("dtype"))
  {
    fail("needs \"dims\" and \"dtype\"");
  }
  std::array<int, 3> dims{};
  std::array<double, 3> spacing{ 1, 1, 1 };
  std::array<double, 3> origin{ 0, 0, 0 };
  ScalarType type{};
  bool swap = false;
  std::string rawName;
  try
  {
    if (!j["dims"].is_array() || j["dims"].size() != 3)
      fail("\"dims\" must be [nx, ny, nz]");
    for (int a = 0; a < 3; ++a)
      dims[a] = j["dims"][a].get<int>();
    if (j.contains("spacing"))
    {
      if (!j["spacing"].is_array() || j["spacing"].size() != 3)
        fail("\"spacing\" must be [sx, sy, sz]");
      for (int a = 0; a < 3; ++a)
        spacing[a] = j["spacing"][a].get<double>();
    }
    if (j.contains("origin"))
    {
      if (!j["origin"].is_array() || j["origin"].size() != 3)
        fail("\"origin\" must be [ox, oy, oz]");
      for (int a = 0; a < 3; ++a)
        origin[a] = j["origin"][a].get<double>();
    }
    type = parseScalarType(j["dtype"].get<std::string>());
    const std::string endian = j.value("endian", std::string("little"));
    if (endian != "little" && endian != "big")
      fail("\"endian\" must be \"little\" or \"big\"");
    swap = endian == "big";
    rawName = j.value("file", std::string());
  }
  catch (const nlohmann::json::exception& e)
  {
    fail(std::string("wrong type of value: ") + e.what());
  }
  for (int a = 0; a < 3; ++a)
  {
    if (dims[a] < 1)
      fail("dimensions must be positive");
  }
  std::string rawPath;
  if (!rawName.empty())
  {
    rawPath = rawName[0] == '/' ? rawName : directoryOf(jsonPath) + rawName;
  }
  else if (jsonPath != path)
  {
    rawPath = path;
  }
  else
  {
    const std::string stem = jsonPath.substr(0, jsonPath.size() - 5);
    rawPath = fileExists(stem + ".raw.gz") ? stem + ".raw.gz" : stem + ".raw";
  }
  switch (type)
  {
    case ScalarType::UInt8:
      return readAs<std::uint8_t>(rawPath, dims, origin, spacing, swap, type);
    case ScalarType::Int8:
      return readAs<std::int8_t>(rawPath, dims, origin, spacing, swap, type);
    case ScalarType::UInt16:
      return readAs<std::uint16_t>(rawPath, dims, origin, spacing, swap, type);
    case ScalarType::Int16:
      return readAs<std::int16_t>(rawPath, dims, origin, spacing, swap, type);
    case ScalarType::UInt32:
      return readAs<std::uint32_t>(rawPath, dims, origin, spacing, swap, type);
    case ScalarType::Int32:
      return readAs<std::int32_t>(rawPath, dims, origin, spacing, swap, type);
    case ScalarType::Float32:
      return readAs<float>(rawPath, dims, origin, spacing, swap, type);
    case ScalarType::Float64:
      return readAs<double>(rawPath, dims, origin, spacing, swap, type);
  }
  throw Error("unsupported scalar type");
}

} // namespace ddg
