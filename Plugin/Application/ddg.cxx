// ddg.cxx: the command-line program — the project's public interface for rendering,
// reconstruction, design-space generation, training and gallery operations. Each subcommand
// lives in its own <Name>Command.cxx (CommandSupport.h); this file lists them. See `ddg --help`.
//
// Built twice (Application/CMakeLists.txt): the program `ddg` without libtorch (the commands that
// need none: render, compare, view, reconstruct, generate, info, export) and, with libtorch, the
// module of every command (DDG_COMMANDS_MODULE), which the program loads only when the command
// line is not one of its own (a neural command, --help, a carried look with its kind check), so
// that its own commands start without libtorch's 0.7 s.
#include "CommandSupport.h"

#include <cstdio>
#include <exception>
#include <string>

#ifdef DDG_NEURAL_COMMANDS
#include <dlfcn.h>
#include <filesystem>
#endif

namespace
{

#ifdef DDG_NEURAL_COMMANDS
/// The whole command line run by the module of every command (DDG_NEURAL_COMMANDS, relative to
/// this program's folder).
int runNeuralCommands(int argc, char** argv)
{
  std::error_code error;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", error);
  const std::string path =
    (error ? std::filesystem::path(argv[0]) : self).parent_path() / DDG_NEURAL_COMMANDS;
  void* module = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
  if (!module)
  {
    std::fprintf(stderr, "ddg: error: cannot load its neural commands: %s\n", dlerror());
    return 1;
  }
  using Main = int (*)(int, char**);
  const auto commandsMain = reinterpret_cast<Main>(dlsym(module, "ddgCommandsMain"));
  if (!commandsMain)
  {
    std::fprintf(stderr, "ddg: error: %s has no ddgCommandsMain: %s\n", path.c_str(), dlerror());
    return 1;
  }
  return commandsMain(argc, argv);
}
#endif

int runCommands(int argc, char** argv)
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

#ifdef DDG_NEURAL_COMMANDS
  // a command line that names none of this program's commands (a neural command, --help, none)
  // is the module's
  bool own = argc > 1 && std::string(argv[1]) == "--version";
  for (const auto& c : commands)
    own = own || (argc > 1 && c.app->get_name() == argv[1]);
  if (!own)
    return runNeuralCommands(argc, argv);
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
      {
#ifdef DDG_NEURAL_COMMANDS
        if (c.neural && c.neural())
          return runNeuralCommands(argc, argv);
#endif
        return c.run();
      }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "ddg %s: error: %s\n", name.c_str(), e.what());
    return 1;
  }
  return 0;
}

} // namespace

#ifdef DDG_COMMANDS_MODULE
/// The module's entry: the whole command line, as `ddg` gets it.
extern "C" __attribute__((visibility("default"))) int ddgCommandsMain(int argc, char** argv)
{
  return runCommands(argc, argv);
}
#else
int main(int argc, char** argv)
{
  return runCommands(argc, argv);
}
#endif
