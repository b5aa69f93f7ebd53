// InfoCommand.cxx: `ddg info` — print a volume's dimensions, spacing, type, range and ParaView's
// defaults.
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Render/RayCaster.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct InfoArgs
{
  std::string volume, array;
};

int runInfo(const std::string& path, const std::string& array)
{
  const ddg::Volume v = ddg::readVolumeFile(path, array);
  const auto& d = v.dims();
  const auto& s = v.spacing();
  const auto& o = v.origin();
  std::printf("volume       %s\n", path.c_str());
  std::printf("dimensions   %d x %d x %d (%lld voxels)\n", d[0], d[1], d[2],
    static_cast<long long>(v.voxelCount()));
  std::printf("scalar type  %s\n", ddg::scalarTypeName(v.originalType()));
  std::printf("origin       %g %g %g\n", o[0], o[1], o[2]);
  std::printf("spacing      %g %g %g\n", s[0], s[1], s[2]);
  std::printf("range        %g .. %g\n", v.range()[0], v.range()[1]);
  if (v.nonFiniteCount() > 0)
  {
    std::printf("non-finite   %lld voxels (rendered as the minimum)\n",
      static_cast<long long>(v.nonFiniteCount()));
  }
  try
  {
    const ddg::RayCaster caster(v);
    std::printf("sample distance (ParaView default)        %.7g\n", caster.defaultSampleDistance());
    std::printf(
      "opacity unit distance (ParaView default)  %.7g\n", caster.defaultOpacityUnitDistance());
  }
  catch (const ddg::Error& e)
  {
    std::printf("not renderable: %s\n", e.what());
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addInfoCommand(CLI::App& app)
{
  auto a = std::make_shared<InfoArgs>();
  auto* info = app.add_subcommand(
    "info", "Print a volume's dimensions, spacing, type, range and ParaView's defaults.");
  info->add_option("--volume", a->volume, "Volume file")->required();
  info->add_option("--array", a->array, "Point array (default: the active scalars)");
  return { info, [a] { return runInfo(a->volume, a->array); } };
}
