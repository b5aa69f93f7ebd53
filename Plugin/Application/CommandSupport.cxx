// CommandSupport.cxx: timing, number lists, bundles and designs named on the command line.
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Render/View.h"
#ifdef DDG_WITH_TORCH
#include "Gallery/DesignReference.h"
#include "Neural/KindNetwork.h"
#endif

#include <cstdio>
#include <sstream>

namespace ddg::cli
{

double msSince(Clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::vector<int> parseInts(const std::string& text, const char* what)
{
  std::vector<int> v;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ','))
  {
    try
    {
      size_t used = 0;
      v.push_back(std::stoi(part, &used));
      if (used != part.size())
        throw std::invalid_argument(part);
    }
    catch (const std::logic_error&)
    {
      throw Error(std::string(what) + ": '" + part + "' is not an integer");
    }
  }
  return v;
}

std::vector<double> parseNumbers(const std::string& text, size_t count, const char* what)
{
  std::vector<double> v;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ','))
  {
    try
    {
      v.push_back(std::stod(part));
    }
    catch (const std::logic_error&)
    {
      throw Error(std::string(what) + ": '" + part + "' is not a number");
    }
  }
  if (count > 0 && v.size() != count)
    throw Error(std::string(what) + " takes " + std::to_string(count) + " numbers");
  return v;
}

#ifdef DDG_WITH_TORCH
OutlineBox parseBox(const std::string& text)
{
  const auto v = parseNumbers(text, 4, "--box");
  OutlineBox b{ v[0], v[1], v[2], v[3] };
  if (!b.valid())
    throw Error("--box needs x0 < x1 and y0 < y1");
  return b;
}

View thumbnailView(
  const Volume& volume, const DesignSpaceSpec& spec, const std::string& path, int size)
{
  View v = path.empty() ? designDefaultView(volume, spec, size) : readView(path);
  v.width = v.height = size;
  return v;
}

std::unique_ptr<BundleSession> openBundle(const std::string& modelDir, const std::string& volume)
{
  return std::make_unique<BundleSession>(modelDir, readVolumeFile(volume), volume);
}

std::vector<float> resolveDesign(const DesignGallery& g, const std::string& reference)
{
  return DesignReference::parse(reference).resolve(g);
}

std::unique_ptr<FeatureLock> makeLock(
  const DesignGallery& g, const std::string& regions, const std::string& from)
{
  if (regions.empty())
    return nullptr;
  if (from.empty())
    throw Error("--lock needs --lock-from: the design whose regions stay fixed");
  return std::make_unique<FeatureLock>(
    g.lockRegions(resolveDesign(g, from), parseInts(regions, "--lock")));
}

void printEvaluation(const EvaluationReport& e)
{
  std::printf("held-out %d exemplars: PSNR %.2f dB  SSIM %.4f  EMD %.3f  invariance %.3f  analyzer "
              "%.2f ms  renderer %.2f ms\n",
    e.count, e.psnr, e.ssim, e.emd, e.invariance, e.analyzerMs, e.rendererMs);
}
#endif

#ifdef DDG_WITH_TORCH
namespace
{
// The command's kind network: loaded once by kindNetworkOption, used by printKindCheck.
KindChecker& commandKindChecker()
{
  static KindChecker checker;
  return checker;
}
} // namespace
#endif

std::string kindNetworkOption(const std::string& option)
{
  if (option.empty() || option == "none")
    return "";
#ifdef DDG_WITH_TORCH
  commandKindChecker().load(option);
  return option;
#else
  throw Error("--kind-network needs a build with libtorch");
#endif
}

void printKindCheck(const std::string& dir, int threads, const Image& picture, const Volume& volume)
{
  if (dir.empty())
    return;
#ifdef DDG_WITH_TORCH
  try
  {
    std::printf(
      "%s\n", describeKindCheck(commandKindChecker().check(dir, picture, volume, threads)).c_str());
  }
  catch (const Error& e)
  {
    std::fprintf(stderr, "warning: the kind of the picture was not checked: %s\n", e.what());
  }
#else
  (void)threads;
  (void)picture;
  (void)volume;
#endif
}

} // namespace ddg::cli
