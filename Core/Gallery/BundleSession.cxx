// BundleSession.cxx: opening a bundle for a volume; the one-session cache of the filters.
#include "Gallery/BundleSession.h"

#include "Common/Error.h"
#include "Common/Hash.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <vector>

namespace ddg
{

namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
} // namespace

std::uint64_t bundleStamp(const std::string& bundleDir)
{
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<std::string> entries;
  for (fs::directory_iterator it(bundleDir, ec), end; !ec && it != end; it.increment(ec))
  {
    std::error_code e;
    if (!it->is_regular_file(e))
      continue;
    const auto size = it->file_size(e);
    const auto written = it->last_write_time(e).time_since_epoch().count();
    entries.push_back(it->path().filename().string() + "|" + std::to_string(size) + "|" +
      std::to_string(static_cast<long long>(written)));
  }
  if (ec)
    return 0;
  std::sort(entries.begin(), entries.end()); // the listing's order is the file system's
  Fnv1a hash;
  for (const std::string& entry : entries)
    hash.add(entry.c_str(), entry.size() + 1); // with its terminating zero between entries
  return hash.value();
}

BundleSession::BundleSession(
  const std::string& bundleDir, Volume volume, const std::string& volumeHint)
  : Directory(bundleDir)
  , Vol(std::make_unique<Volume>(std::move(volume)))
  , Stamp(bundleStamp(bundleDir))
{
  Fingerprint = volumeFingerprint(*Vol);
  LatentSet latents = openBundle(volumeHint);
  const auto t1 = Clock::now();
  Gallery = std::make_unique<DesignGallery>(*Model, *Vol, std::move(latents));
  attachQueryKey();
  PcaMs = msSince(t1);
}

BundleSession::BundleSession(const std::string& bundleDir, const std::string& fingerprint,
  std::shared_ptr<const DesignVolume> volume, const std::string& volumeHint)
  : Directory(bundleDir)
  , Fingerprint(fingerprint)
  , Space(std::move(volume))
  , Stamp(bundleStamp(bundleDir))
{
  LatentSet latents = openBundle(volumeHint);
  const auto t1 = Clock::now();
  Gallery = std::make_unique<DesignGallery>(*Model, Space, std::move(latents));
  attachQueryKey();
  PcaMs = msSince(t1);
}

void BundleSession::attachQueryKey()
{
  // the query's nearest designs by the bundle's key, when it has one (older bundles do not)
  if (std::filesystem::exists(queryKeyFile(Directory)))
    Gallery->setQueryKey(readQueryKey(queryKeyFile(Directory)));
}

LatentSet BundleSession::openBundle(const std::string& volumeHint)
{
  Model =
    std::make_unique<NeuralDesignModel>(NeuralDesignModel::loadBundle(Directory, Fingerprint));
  const auto t0 = Clock::now();
  LatentSet latents;
  try
  {
    latents = readLatentSet(outlineFile(Directory));
  }
  catch (const Error& e)
  {
    throw Error(std::string(e.what()) + " (build the outline with: ddg outline --model " +
      Directory + " --volume " + volumeHint + ")");
  }
  ReadMs = msSince(t0);
  return latents;
}

const Volume& BundleSession::volume() const
{
  if (!Vol)
    throw Error("the bundle was opened for a volume known by its fingerprint only");
  return *Vol;
}

BundleSession::~BundleSession() = default;

BundleSession& BundleSessionCache::get(const std::string& bundleDir, std::uint64_t volumeVersion,
  const std::function<Volume()>& loadVolume)
{
  if (bundleDir.empty())
    throw Error("no ModelDirectory set");
  if (!Session || Session->directory() != bundleDir || Version != volumeVersion ||
    !Session->hasVolume() || Session->stamp() != bundleStamp(bundleDir))
  {
    Session.reset();
    Session = std::make_unique<BundleSession>(bundleDir, loadVolume());
    Version = volumeVersion;
  }
  return *Session;
}

BundleSession& BundleSessionCache::get(const std::string& bundleDir, const std::string& fingerprint,
  const std::shared_ptr<const DesignVolume>& volume)
{
  if (bundleDir.empty())
    throw Error("no ModelDirectory set");
  if (!Session || Session->directory() != bundleDir || Session->hasVolume() ||
    Session->fingerprint() != fingerprint || &Session->gallery().space() != volume.get() ||
    Session->stamp() != bundleStamp(bundleDir))
  {
    Session.reset();
    Session = std::make_unique<BundleSession>(bundleDir, fingerprint, volume);
  }
  return *Session;
}

} // namespace ddg
