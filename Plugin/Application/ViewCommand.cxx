// ViewCommand.cxx: `ddg view` — write a view JSON for a volume: ParaView's reset camera.
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Render/View.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct ViewArgs
{
  std::string volume, out, array;
  std::vector<int> size{ 512, 512 };
  double azimuth = 0, elevation = 0, zoom = 1;
  bool parallel = false;
  std::vector<double> background;
};

int runView(const ViewArgs& a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  ddg::View v = ddg::defaultView(volume, a.size[0], a.size[1]);
  auto& cam = v.camera;
  // vtkCamera::Azimuth (about view up through the focal point), then Elevation (about the
  // right vector), then OrthogonalizeViewUp.
  const Eigen::Vector3d up = cam.viewUp.normalized();
  Eigen::Vector3d offset = cam.position - cam.focalPoint;
  offset = Eigen::AngleAxisd(a.azimuth * M_PI / 180.0, up) * offset;
  const Eigen::Vector3d right = (-offset).normalized().cross(up).normalized();
  offset = Eigen::AngleAxisd(-a.elevation * M_PI / 180.0, right) * offset;
  cam.position = cam.focalPoint + offset / (a.parallel ? 1.0 : a.zoom);
  const Eigen::Vector3d forward = (-offset).normalized();
  cam.viewUp = forward.cross(up).normalized().cross(forward).normalized();
  if (cam.viewUp.norm() < 0.5 || !std::isfinite(cam.viewUp[0]))
  {
    throw ddg::Error("elevation of +-90 degrees makes view_up parallel to the view direction");
  }
  cam.parallelProjection = a.parallel;
  cam.parallelScale /= a.zoom;
  if (!a.background.empty())
  {
    if (a.background.size() != 3)
    {
      throw ddg::Error("--background needs three numbers r g b");
    }
    v.background = { a.background[0], a.background[1], a.background[2] };
  }
  v.validate();
  ddg::writeView(v, a.out);
  std::printf("wrote %s\n", a.out.c_str());
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addViewCommand(CLI::App& app)
{
  auto va = std::make_shared<ViewArgs>();
  auto* viewCmd = app.add_subcommand("view",
    "Write a view JSON for a volume: ParaView's reset camera (looking down -z, +y up), then "
    "azimuth/elevation/zoom.");
  viewCmd->add_option("--volume", va->volume, "Volume file")->required();
  viewCmd->add_option("--out", va->out, "Output view JSON")->required();
  viewCmd->add_option("--array", va->array, "Point array (default: the active scalars)");
  viewCmd->add_option("--size", va->size, "Image width and height (default 512 512)")->expected(2);
  viewCmd->add_option("--azimuth", va->azimuth, "Degrees about the view up vector (default 0)");
  viewCmd->add_option("--elevation", va->elevation, "Degrees about the right vector (default 0)");
  viewCmd->add_option("--zoom", va->zoom, "Zoom factor > 0 (default 1)")
    ->check(CLI::PositiveNumber);
  viewCmd->add_flag("--parallel", va->parallel, "Parallel projection");
  viewCmd->add_option("--background", va->background, "Background r g b in [0, 1]")->expected(3);
  return { viewCmd, [va] { return runView(*va); } };
}
