// ExportCommand.cxx: `ddg export` — convert a TF file for another tool: a ParaView preset.
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Gallery/Export.h"
#include "Render/RayCaster.h"
#include "Render/View.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct ExportArgs
{
  std::string tf, volume, out, format = "paraview", view;
  int boxIterations = ddg::ParaViewBoxFitOptions().iterations;
};

int runExport(const ExportArgs& a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume);
  const ddg::RayCaster caster(volume);
  const ddg::View view = a.view.empty() ? ddg::View() : ddg::readView(a.view);
  const auto tf = caster.resolve(ddg::readTransferFunctionFile(a.tf), view);
  // named for the volume, the TF it came from and the file: each export imports into ParaView
  const std::string origin = std::filesystem::path(a.tf).stem().string();
  const std::string what =
    ddg::exportTransferFunction(ddg::renamed(tf, ddg::exportName(a.volume, origin, a.out)), a.out,
      a.format, caster, view, a.boxIterations);
  std::printf("wrote %s (%s)\n", a.out.c_str(), what.c_str());
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addExportCommand(CLI::App& app)
{
  auto ea = std::make_shared<ExportArgs>();
  auto* exportCmd = app.add_subcommand("export",
    "Convert a TF file for another tool: a ParaView preset (as is) or 3D Slicer's volume "
    "property JSON (.vp.json, schema volume-property-schema-v1.0.0).");
  exportCmd->add_option("--tf", ea->tf, "TF file (ParaView preset JSON or DDG 2D TF JSON)")
    ->required();
  exportCmd
    ->add_option("--volume", ea->volume, "The volume (its range is Slicer's effective range)")
    ->required();
  exportCmd->add_option("--out", ea->out, "Output file")->required();
  exportCmd
    ->add_option("--format", ea->format,
      "paraview (default: preset JSON, or the DDG 2D JSON), slicer (1D), or paraview-2d: a 2D\n"
      "TF as ParaView 5.11's TransferFunction2D properties {\"Boxes\", \"Range\",\n"
      "\"OutputDimensions\", \"Fit\"}, Gaussian boxes fitted for this volume (UseTransfer2D)")
    ->check(CLI::IsMember({ "paraview", "slicer", "paraview-2d" }));
  exportCmd
    ->add_option("--box-iterations", ea->boxIterations,
      "paraview-2d: Adam steps refining the boxes (default 400; 0 = one box per primitive as "
      "placed)")
    ->check(CLI::Range(0, 100000));
  exportCmd->add_option("--view", ea->view,
    "View JSON whose opacity_unit_distance the TF was designed with (default: ParaView's)");
  return { exportCmd, [ea] { return runExport(*ea); } };
}
