// KindChecker.cxx: the kind check's references, kept in memory and between sessions on disk
// (KindChecker and kindCacheDirectory in KindNetwork.h).
#include "Neural/KindNetwork.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Common/Hash.h"
#include "Design/DesignSpace.h"
#include "Volume/Volume.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace ddg
{
namespace fs = std::filesystem;
using json = nlohmann::json;

void KindChecker::load(const std::string& dir)
{
  if (Network && dir == Dir)
    return;
  Network = std::make_unique<KindNetwork>(KindNetwork::load(dir));
  Dir = dir;
  References.clear();
  DiskKey = 0;
}

std::string kindCacheDirectory()
{
  if (const char* d = std::getenv("DDG_CACHE_DIR"); d && *d)
    return std::string(d) == "none" ? std::string() : std::string(d);
  // the XDG base directories: a relative XDG_CACHE_HOME is ignored
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x && fs::path(x).is_absolute())
    return (fs::path(x) / "ddg").string();
  if (const char* h = std::getenv("HOME"); h && *h)
    return (fs::path(h) / ".cache" / "ddg").string();
  return std::string();
}

namespace
{
// The file a reference is kept in: kind-references/<hash of network and volume>.json.
std::string keptReferencePath(std::uint64_t network, const std::string& fingerprint)
{
  const std::string dir = kindCacheDirectory();
  if (dir.empty() || network == 0)
    return std::string();
  Fnv1a key;
  key.add(&network, sizeof network);
  key.add(fingerprint.data(), fingerprint.size());
  char name[40];
  std::snprintf(name, sizeof name, "%016llx.json", static_cast<unsigned long long>(key.value()));
  return (fs::path(dir) / "kind-references" / name).string();
}

std::string networkId(std::uint64_t network)
{
  char id[20];
  std::snprintf(id, sizeof id, "%016llx", static_cast<unsigned long long>(network));
  return id;
}
} // namespace

std::uint64_t KindChecker::diskKey()
{
  if (Network->identity() == 0)
    return 0;
  if (DiskKey == 0)
  {
    // 4 exemplars of a fixed small volume (a ball in a shell, 24^3) drawn and read as every
    // reference is: a change in how exemplars are drawn or read (generator, ray caster, framing,
    // libtorch) changes their probabilities, and with them every file's key
    std::vector<float> v;
    for (int k = 0; k < 24; ++k)
      for (int j = 0; j < 24; ++j)
        for (int i = 0; i < 24; ++i)
        {
          const double r =
            std::sqrt((i - 11.5) * (i - 11.5) + (j - 11.5) * (j - 11.5) + (k - 11.5) * (k - 11.5));
          v.push_back(r < 5 ? 200.0f : (r < 9 ? 100.0f : 10.0f));
        }
    const Volume probe({ 24, 24, 24 }, { 0, 0, 0 }, { 1, 1, 1 }, v, ScalarType::Float32);
    const std::vector<double> p = kindReference(*Network, probe, 0, {}, 4);
    Fnv1a key;
    const std::uint64_t id = Network->identity();
    key.add(&id, sizeof id);
    for (const double x : p) // to 1e-9: the last bits may follow the thread count
    {
      const long long q = std::llround(x * 1e9);
      key.add(&q, sizeof q);
    }
    DiskKey = key.value() == 0 ? 1 : key.value();
  }
  return DiskKey;
}

bool KindChecker::hasReference(const std::string& dir, const std::string& fingerprint)
{
  load(dir);
  if (std::any_of(References.begin(), References.end(),
        [&](const auto& r) { return r.first == fingerprint; }))
    return true;
  // drawn in an earlier session by this network for this volume: read back
  const std::string kept = keptReferencePath(diskKey(), fingerprint);
  if (kept.empty())
    return false;
  try // missing, unreachable or unreadable: drawn again (and written over)
  {
    const json j = json::parse(readTextFile(kept, "kept kind reference"));
    auto r = j.at("reference").get<std::vector<double>>();
    if (j.at("network").get<std::string>() != networkId(diskKey()) ||
      j.at("fingerprint").get<std::string>() != fingerprint || r.size() != Network->kinds().size())
      return false;
    References.emplace_back(fingerprint, std::move(r));
    return true;
  }
  catch (const std::exception&)
  {
    return false;
  }
}

void KindChecker::addReference(const std::string& dir, const std::string& fingerprint,
  const Volume& volume, int threads, const std::function<bool(double)>& progress)
{
  if (hasReference(dir, fingerprint))
    return;
  References.emplace_back(fingerprint, kindReference(*Network, volume, threads, progress));
  const std::string kept = keptReferencePath(diskKey(), fingerprint);
  if (kept.empty())
    return;
  try
  {
    std::error_code ec;
    fs::create_directories(fs::path(kept).parent_path(), ec);
    writeFileAtomic(kept,
      json{ { "network", networkId(diskKey()) }, { "fingerprint", fingerprint },
        { "reference", References.back().second } }
        .dump(),
      "kept kind reference");
  }
  catch (const std::exception&) // a read-only cache: the reference is still kept in memory
  {
  }
}

KindCheck KindChecker::check(
  const std::string& dir, const Image& picture, const std::string& fingerprint)
{
  load(dir);
  const auto it = std::find_if(
    References.begin(), References.end(), [&](const auto& r) { return r.first == fingerprint; });
  if (it == References.end())
    throw Error("the kind check has no reference of this volume");
  return checkKind(*Network, picture, it->second);
}

KindCheck KindChecker::check(const std::string& dir, const Image& picture, const Volume& volume,
  int threads, const std::function<bool(double)>& progress)
{
  return check(dir, picture, volume, std::string(), threads, progress);
}

KindCheck KindChecker::check(const std::string& dir, const Image& picture, const Volume& volume,
  const std::string& fingerprint, int threads, const std::function<bool(double)>& progress)
{
  const std::string key = fingerprint.empty() ? volumeFingerprint(volume) : fingerprint;
  addReference(dir, key, volume, threads, progress);
  return check(dir, picture, key);
}

} // namespace ddg
