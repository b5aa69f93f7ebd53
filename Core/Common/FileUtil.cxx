// FileUtil.cxx: whole-file reads and atomic writes.
#include "Common/FileUtil.h"

#include "Common/Error.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <unistd.h>

namespace ddg
{

std::string readTextFile(const std::string& path, const std::string& what)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    throw Error("cannot read " + what + " '" + path + "': " + std::strerror(errno));
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad())
  {
    throw Error("cannot read " + what + " '" + path + "'");
  }
  return ss.str();
}

void writeFileAtomic(const std::string& path, const std::string& content, const std::string& what)
{
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
    {
      throw Error("cannot write " + what + " '" + path + "': " + std::strerror(errno));
    }
    out << content;
    out.flush();
    if (!out)
    {
      out.close();
      std::remove(tmp.c_str());
      throw Error("cannot write " + what + " '" + path + "' (disk full?)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    const std::string reason = std::strerror(errno);
    std::remove(tmp.c_str());
    throw Error("cannot write " + what + " '" + path + "': " + reason);
  }
}

std::string fileExtension(const std::string& path)
{
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const auto slash = lower.find_last_of('/');
  const std::string name = slash == std::string::npos ? lower : lower.substr(slash + 1);
  for (const char* dbl : { ".raw.gz", ".nii.gz", ".tar.gz" })
  {
    const std::string d = dbl;
    if (name.size() > d.size() && name.compare(name.size() - d.size(), d.size(), d) == 0)
    {
      return d;
    }
  }
  const auto dot = name.find_last_of('.');
  return dot == std::string::npos ? std::string() : name.substr(dot);
}

} // namespace ddg
