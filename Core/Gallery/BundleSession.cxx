// BundleSession.cxx: opening a bundle for a volume; the one-session cache of the filters.
#include "Gallery/BundleSession.h"

#include "Common/Error.h"

#include <chrono>

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

BundleSession::BundleSession(
  const std::string& bundleDir, Volume volume, const std::string& volumeHint)
  : Directory(bundleDir)
  , Vol(std::make_unique<Volume>(std::move(volume)))
{
  Model = std::make_unique<NeuralDesignModel>(
    NeuralDesignModel::loadBundle(bundleDir, volumeFingerprint(*Vol)));
  const auto t0 = Clock::now();
  LatentSet latents;
  try
  {
    latents = readLatentSet(outlineFile(bundleDir));
  }
  catch (const Error& e)
  {
    throw Error(std::string(e.what()) + " (build the outline with: ddg outline --model " +
      bundleDir + " --volume " + volumeHint + ")");
  }
  ReadMs = msSince(t0);
  const auto t1 = Clock::now();
  Gallery = std::make_unique<DesignGallery>(*Model, *Vol, std::move(latents));
  PcaMs = msSince(t1);
}

BundleSession::~BundleSession() = default;

BundleSession& BundleSessionCache::get(const std::string& bundleDir, std::uint64_t volumeVersion,
  const std::function<Volume()>& loadVolume)
{
  if (bundleDir.empty())
    throw Error("no ModelDirectory set");
  if (!Session || Session->directory() != bundleDir || Version != volumeVersion)
  {
    Session.reset();
    Session = std::make_unique<BundleSession>(bundleDir, loadVolume());
    Version = volumeVersion;
  }
  return *Session;
}

} // namespace ddg
