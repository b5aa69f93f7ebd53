// ddg.cxx: the command-line program — the project's public interface for rendering,
// reconstruction, design-space generation, training and gallery operations. Each subcommand
// lives in its own <Name>Command.cxx (CommandSupport.h); this file lists them. See `ddg --help`.
#include "CommandSupport.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv)
{
  CLI::App app{
    "ddg — Differentiable Design Gallery: volume rendering and transfer functions.\n"
    "Files shared by every command (see README.md):\n"
    "  TF file   ParaView preset JSON [{\"Name\", \"ColorSpace\", \"RGBPoints\": [x,r,g,b,...],\n"
    "            \"Points\": [x,alpha,midpoint,sharpness,...]}], the DDG 2D TF JSON\n"
    "            {\"Format\": \"ddg-transfer-function-2d\", ...}, or ParaView's 2D TF\n"
    "            {\"Boxes\": [x,y,w,h,r,g,b,a,...], \"Range\", \"OutputDimensions\"}\n"
    "  view file {\"camera\": {\"position\", \"focal_point\", \"view_up\", \"view_angle\",\n"
    "            \"parallel_projection\", \"parallel_scale\"}, \"size\": [w,h],\n"
    "            \"background\": [r,g,b], \"opacity_unit_distance\": d (optional),\n"
    "            \"lighting\": {\"shade\", \"ambient\", \"diffuse\", \"specular\",\n"
    "            \"specular_power\"} (optional; ParaView's Shade and coefficients)}\n"
    "  volumes   .vti .vtk .nrrd .nhdr .mha .mhd .nii .nii.gz, or raw(.gz) + JSON sidecar",
    "ddg"
  };
  app.require_subcommand(1);
  app.set_version_flag("--version", "ddg 0.1.0");

  using namespace ddg::cli;
  std::vector<Command> commands{ addRenderCommand(app), addCompareCommand(app), addViewCommand(app),
    addReconstructCommand(app), addGenerateCommand(app) };
#ifdef DDG_WITH_TORCH
  for (auto add : { addTrainCommand, addEvalCommand, addValidityCommand })
    commands.push_back(add(app));
#endif
  commands.push_back(addInfoCommand(app));
  commands.push_back(addExportCommand(app));
#ifdef DDG_WITH_TORCH
  for (auto add : { addOutlineCommand, addGalleryCommand, addQueryCommand, addNavigateCommand,
         addEditCommand, addAnimateCommand, addFidelityCommand, addBuildCommand, addReplayCommand,
         addRecallCommand, addQueryKeyCommand, addTrainKindCommand, addKindCommand })
    commands.push_back(add(app));
#endif

  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::ParseError& e)
  {
    return app.exit(e);
  }

  const std::string name = app.get_subcommands().front()->get_name();
  try
  {
    for (const auto& c : commands)
      if (*c.app)
        return c.run();
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "ddg %s: error: %s\n", name.c_str(), e.what());
    return 1;
  }
  return 0;
}
