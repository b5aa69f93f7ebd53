// CommandSupport.h: what the `ddg` subcommands share — one registration style (each subcommand's
// file adds its options and returns how to run it), timing, number lists on the command line,
// and opening a bundle for --model / --volume through Core's bundle session.
#pragma once

#include <CLI/CLI.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#ifdef DDG_WITH_TORCH
#include "Gallery/BundleSession.h"
#include "Neural/NeuralDesignModel.h"
#endif

namespace ddg
{
struct View;
struct Image;
class Volume;

namespace cli
{

/// A subcommand: its CLI11 app (registered on the program's) and how to run it once parsed
/// (returns the exit code; errors are thrown as ddg::Error and printed by main). `neural`, once
/// parsed, says whether this run needs libtorch after all (reconstruct's carried look, for its
/// kind check): the `ddg` program then hands the whole command line to its neural commands
/// (ddg.cxx); unset: never.
struct Command
{
  CLI::App* app = nullptr;
  std::function<int()> run;
  std::function<bool()> neural = {}; // (= {}: commands that never need libtorch leave it out)
};

using Clock = std::chrono::steady_clock;
/// Milliseconds since t0.
double msSince(Clock::time_point t0);

/// Comma-separated numbers (exactly `count` of them when count > 0); ddg::Error names `what`.
std::vector<double> parseNumbers(const std::string& text, size_t count, const char* what);
/// Comma-separated integers; ddg::Error names `what`.
std::vector<int> parseInts(const std::string& text, const char* what);

/// --kind-network of ddg query and ddg reconstruct --carry-look: "" or "none" is no check (""
/// returned), else the directory, its network loaded now so that a bad one fails before any
/// work is done (without libtorch a network given is an error).
std::string kindNetworkOption(const std::string& option);
/// The kind network `dir`'s check of a picture against a volume, printed as one line ("" prints
/// nothing); a failure is a warning on stderr (the command's outputs are written by then).
void printKindCheck(
  const std::string& dir, int threads, const Image& picture, const Volume& volume);

#ifdef DDG_WITH_TORCH
/// --box x0,y0,x1,y1 on the outline plane (x0 < x1, y0 < y1).
OutlineBox parseBox(const std::string& text);
/// The thumbnails' view: the view file's camera, else the design space's default view (lit as its
/// exemplars: designDefaultView), at size x size.
View thumbnailView(
  const Volume& volume, const DesignSpaceSpec& spec, const std::string& path, int size);
/// The bundle of --model opened for --volume (Core's BundleSession).
std::unique_ptr<BundleSession> openBundle(const std::string& modelDir, const std::string& volume);
/// A design reference's latent (row:N, image:PATH, latent:PATH, history:PATH).
std::vector<float> resolveDesign(const DesignGallery& g, const std::string& reference);
/// --lock REGIONS --lock-from DESIGN: the feature lock, or none.
std::unique_ptr<FeatureLock> makeLock(
  const DesignGallery& g, const std::string& regions, const std::string& from);
/// One line of held-out figures (train, eval).
void printEvaluation(const EvaluationReport& e);
#endif

// The subcommands, one file each (<Name>Command.cxx), in the order `ddg --help` lists them.
Command addRenderCommand(CLI::App& app);
Command addCompareCommand(CLI::App& app);
Command addViewCommand(CLI::App& app);
Command addReconstructCommand(CLI::App& app);
Command addGenerateCommand(CLI::App& app);
Command addInfoCommand(CLI::App& app);
Command addExportCommand(CLI::App& app);
#ifdef DDG_WITH_TORCH
Command addTrainCommand(CLI::App& app);
Command addEvalCommand(CLI::App& app);
Command addValidityCommand(CLI::App& app);
Command addOutlineCommand(CLI::App& app);
Command addGalleryCommand(CLI::App& app);
Command addQueryCommand(CLI::App& app);
Command addNavigateCommand(CLI::App& app);
Command addEditCommand(CLI::App& app);
Command addAnimateCommand(CLI::App& app);
Command addFidelityCommand(CLI::App& app);
Command addBuildCommand(CLI::App& app);
Command addReplayCommand(CLI::App& app);
Command addRecallCommand(CLI::App& app);
Command addQueryKeyCommand(CLI::App& app);
Command addTrainKindCommand(CLI::App& app);
Command addKindCommand(CLI::App& app);
#endif

} // namespace cli
} // namespace ddg
