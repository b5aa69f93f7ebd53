// ReconstructCommand.cxx: `ddg reconstruct` — find a transfer function whose rendering matches
// target image(s).
#include "ReconstructSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Gallery/Export.h"
#include "Image/Image.h"
#include "Image/ImageMetrics.h"
#include "Reconstruct/CarryLook.h"
#include "Reconstruct/Match.h"
#include "Reconstruct/Reconstruction.h"
#include "Render/DifferentiableRenderer.h"
#include "Render/RayCaster.h"
#include "Render/View.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

namespace ddg::cli::reconstruct
{

// Prints a warning (when there is one) on stderr.
void warn(const std::string& text)
{
  if (!text.empty())
  {
    std::fprintf(stderr, "ddg reconstruct: warning: %s\n", text.c_str());
  }
}

// Reads a target image for reconstruction and checks what the reconstruction can use; the size
// against `view`'s when there is one (a match without a view takes any size).
ddg::Image readTarget(const std::string& path, const ddg::View* view, bool resample)
{
  ddg::ImageFileInfo info;
  ddg::Image img = ddg::inColour(ddg::readImage(path, &info)); // a grey figure as the filter
  if (img.channels != 3 && img.channels != 4)
  {
    throw ddg::Error("target '" + path + "' has " + std::to_string(img.channels) +
      " channels; an RGB screenshot, an RGBA image (straight alpha) or a grey picture is needed");
  }
  if (info.format != "uint8")
  {
    for (float v : img.pixels)
    {
      if (!std::isfinite(v) || v < 0.0f || v > 1.0f)
      {
        throw ddg::Error("target '" + path + "' is a " + info.format +
          " image with values outside [0, 1] (or NaN): tone-map it to [0, 1] first");
      }
    }
    std::fprintf(stderr,
      "ddg reconstruct: note: target '%s' is %s per channel; using its values in [0, 1]\n",
      path.c_str(), info.format.c_str());
  }
  if (view && (img.width != view->width || img.height != view->height))
  {
    if (!resample)
    {
      throw ddg::Error("target '" + path + "' is " + std::to_string(img.width) + " x " +
        std::to_string(img.height) + " but its view is " + std::to_string(view->width) + " x " +
        std::to_string(view->height) + " (pass --resample to resize the target to the view)");
    }
    img = ddg::resizeImage(img, view->width, view->height);
  }
  return img;
}

// The options given, over `defaults` (the match's or the reconstruction's).
ddg::ReconstructionOptions reconstructionOptions(
  const ReconstructArgs& a, const ddg::Volume& volume, ddg::ReconstructionOptions opt = {})
{
  opt.twoD = a.twoD;
  opt.bins = a.bins;
  opt.gradientBins = a.gradientBins;
  opt.primitives = a.primitives;
  opt.loss = a.loss == "l2" ? ddg::ReconstructionLoss::L2 : ddg::ReconstructionLoss::L1;
  opt.smoothness = a.smoothness;
  opt.ssimWeight = a.ssimWeight;
  opt.iterations = a.iterations;
  opt.learningRate = a.learningRate;
  if (a.rays >= 0)
  {
    opt.raysPerIteration = a.rays;
  }
  opt.seed = a.seed;
  opt.render.threads = a.threads;
  if (!a.init.empty())
  {
    const ddg::TransferFunction1D init = ddg::readPreset(a.init);
    opt.initial1D = ddg::bakeTable(init, volume.range()[0], volume.range()[1], 1024);
  }
  return opt;
}

// The TF file, named for the volume, what made it and the file (Core's export).
void writeResult(const ddg::ReconstructionResult& result, const ReconstructArgs& a,
  const std::string& origin, const ddg::RayCaster& caster, const ddg::View& view)
{
  const auto tf = ddg::resultTransferFunction(result, ddg::exportName(a.volume, origin, a.out));
  ddg::exportTransferFunction(tf, a.out, "paraview", caster, view);
}

} // namespace ddg::cli::reconstruct

namespace
{
using namespace ddg::cli;
using namespace ddg::cli::reconstruct;

// One picture without a mask: Core's matchPicture (background estimated, overlays masked,
// empty space kept transparent; the camera estimated unless a --view is given as the answer).
int runMatch(const ReconstructArgs& a)
{
  const auto t0 = Clock::now();
  std::optional<ddg::View> view;
  if (!a.views.empty())
  {
    view = ddg::readView(a.views[0]);
  }
  const ddg::Image picture = readTarget(a.targets[0], view ? &*view : nullptr, a.resample);
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  const ddg::DifferentiableRenderer renderer(volume);
  ddg::MatchOptions opt;
  opt.reconstruction = reconstructionOptions(a, volume, ddg::matchReconstructionDefaults());
  opt.view = view;
  opt.refineGivenView = a.estimateView;
  if (!a.background.empty())
  {
    opt.background = std::array<double, 3>{ a.background[0], a.background[1], a.background[2] };
  }
  opt.cameraCandidates = a.cameraCandidates;
  if (a.shade != "auto" && !view)
  {
    opt.lighting = ddg::Lighting{};
    opt.lighting->shade = a.shade == "on";
  }
  if (opt.background && picture.channels == 3)
  {
    warn(ddg::targetBackground(picture, ddg::View(), opt.background).warning);
  }
  const double tLoad = msSince(t0);
  std::string lastStage;
  const auto m = ddg::matchPicture(renderer, picture, opt,
    [&](const std::string& stage, double fraction, const ddg::Image*)
    {
      if (!a.quiet && stage != lastStage)
      {
        std::printf("%s (%.0f %%)\n", stage.c_str(), 100 * fraction);
        std::fflush(stdout);
        lastStage = stage;
      }
      return true;
    });
  writeResult(m.tf, a, "match", renderer.caster(), m.view);
  if (!a.outView.empty())
  {
    ddg::writeView(m.view, a.outView);
  }
  if (!a.outOverlay.empty())
  {
    ddg::writeImage(m.masks.overlay, a.outOverlay);
  }
  const auto& bg = m.background;
  std::printf("background: %s (%.3f %.3f %.3f)", bg.gradient ? "gradient, bottom" : "uniform",
    bg.bottom[0], bg.bottom[1], bg.bottom[2]);
  if (bg.gradient)
  {
    std::printf(", top (%.3f %.3f %.3f)", bg.top[0], bg.top[1], bg.top[2]);
  }
  std::printf("\n");
  std::printf("lighting: Shade %s%s", m.view.lighting.shade ? "on" : "off",
    m.lightingEstimated ? " (estimated" : " (given");
  if (m.lightingEstimated)
  {
    std::printf(", specular %.2f: fit %.2f dB, the next best %.2f dB", m.view.lighting.specular,
      m.fitPSNR, m.otherLightingFitPSNR);
  }
  std::printf(")\n");
  if (m.cameraEstimated)
  {
    std::printf("camera: azimuth %.1f, elevation %.1f, roll %.1f, zoom %.3f, pan %+.3f %+.3f "
                "(from %s), %s projection; silhouette overlap %.3f\n",
      m.orbit[0], m.orbit[1], m.orbit[2], m.zoom, m.pan[0], m.pan[1],
      a.views.empty() ? "ParaView's reset camera" : "the given view",
      m.view.camera.parallelProjection ? "parallel" : "perspective", m.overlap);
  }
  else
  {
    std::printf("camera: the given view; silhouette overlap %.3f\n", m.overlap);
  }
  double overlay = 0;
  for (float v : m.masks.overlay.pixels)
  {
    overlay += v > 0.5f;
  }
  std::printf("overlays masked: %.2f %% of the picture\n",
    100.0 * overlay / static_cast<double>(m.masks.overlay.pixels.size()));
  const auto& cs = m.cameraStages;
  std::printf("%s after %d steps; fit PSNR %.2f dB; %.2f s (background %.2f, camera %.2f "
              "[silhouettes %.2f, colours %.2f, candidates %.2f, polish %.2f], fit %.2f; load "
              "%.0f ms); wrote %s\n",
    m.tf.converged ? "converged" : "did NOT converge (iteration limit)", m.tf.iterations, m.fitPSNR,
    m.seconds, m.backgroundSeconds, m.cameraSeconds, cs.silhouettes, cs.colours, cs.candidates,
    cs.polish, m.fitSeconds, tLoad, a.out.c_str());
  if (!a.outImage.empty())
  {
    const ddg::Image render = ddg::renderResult(renderer.caster(), m.tf, m.view, {});
    ddg::writeImage(m.view.background2
        ? ddg::compositeOverBackground(render, m.view.background, *m.view.background2)
        : ddg::compositeOverBackground(render, m.view.background),
      a.outImage);
  }
  return 0;
}

int runReconstruct(const ReconstructArgs& a)
{
  if (a.otherVolume)
    return runCarry(a);
  if (!a.kindNetwork.empty())
    throw ddg::Error("--kind-network is for --carry-look");
  if (a.targets.size() == 1 && a.masks.empty())
  {
    if (a.views.size() > 1)
    {
      throw ddg::Error(
        "give one --view per --target (1 target, " + std::to_string(a.views.size()) + " views)");
    }
    return runMatch(a);
  }
  if (a.estimateView || !a.outView.empty() || !a.outOverlay.empty())
  {
    throw ddg::Error("--estimate-view, --out-view and --out-overlay are for one target without "
                     "--mask");
  }
  const auto t0 = Clock::now();

  if (a.views.size() != a.targets.size())
  {
    throw ddg::Error("give one --view per --target (" + std::to_string(a.targets.size()) +
      " targets, " + std::to_string(a.views.size()) + " views)");
  }
  if (!a.masks.empty() && a.masks.size() != a.targets.size())
  {
    throw ddg::Error("give one --mask per --target, or none");
  }
  std::vector<ddg::ReconstructionTarget> targets(a.targets.size());
  for (size_t i = 0; i < a.targets.size(); ++i)
  {
    targets[i].view = ddg::readView(a.views[i]);
    targets[i].image = readTarget(a.targets[i], &targets[i].view, a.resample);
    if (targets[i].image.channels == 3)
    {
      // the picture's background: the one given, else the view's unless the border disagrees
      std::optional<std::array<double, 3>> given;
      if (!a.background.empty())
      {
        given = std::array<double, 3>{ a.background[0], a.background[1], a.background[2] };
      }
      const auto bg = ddg::targetBackground(targets[i].image, targets[i].view, given);
      bg.background.applyTo(targets[i].view);
      warn(bg.warning.empty() ? "" : "target '" + a.targets[i] + "': " + bg.warning);
    }
    if (!a.masks.empty())
    {
      targets[i].mask = readTarget(a.masks[i], &targets[i].view, a.resample);
    }
  }
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  const ddg::DifferentiableRenderer renderer(volume);
  const ddg::ReconstructionOptions opt = reconstructionOptions(a, volume);
  const double tLoad = msSince(t0);
  const auto result = ddg::reconstructTransferFunction(renderer, targets, opt,
    [&](int step, double loss, const ddg::ReconstructionResult*)
    {
      if (!a.quiet && (step % 50 == 0))
      {
        std::printf("step %4d  loss %.6f\n", step, loss);
        std::fflush(stdout);
      }
      return true;
    });
  writeResult(result, a, "reconstruction", renderer.caster(), targets[0].view);
  std::printf("%s after %d steps (%.2f s, load %.0f ms); wrote %s\n",
    result.converged ? "converged" : "did NOT converge (iteration limit)", result.iterations,
    result.seconds, tLoad, a.out.c_str());
  for (size_t i = 0; i < targets.size(); ++i)
  {
    const auto& t = targets[i];
    const ddg::Image render = ddg::renderResult(renderer.caster(), result, t.view, {});
    ddg::Image ours, target;
    if (t.image.channels == 4)
    {
      // compare over the view's background, as a person sees them
      target = ddg::compositeOverBackground(ddg::premultiplyAlpha(t.image), t.view.background);
    }
    else
    {
      target = t.image;
    }
    ours = t.view.background2
      ? ddg::compositeOverBackground(render, t.view.background, *t.view.background2)
      : ddg::compositeOverBackground(render, t.view.background);
    std::printf("target %zu (%s): PSNR %.2f dB  SSIM %.4f  EMD %.3f\n", i, a.targets[i].c_str(),
      ddg::psnr(ours, target), ddg::ssim(ours, target), ddg::colorHistogramEMD(ours, target));
    if (i == 0 && !a.outImage.empty())
    {
      ddg::writeImage(ours, a.outImage);
    }
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addReconstructCommand(CLI::App& app)
{
  auto rc = std::make_shared<ddg::cli::reconstruct::ReconstructArgs>();
  auto* reconstruct = app.add_subcommand("reconstruct",
    "Find a transfer function whose rendering matches target image(s) (differentiable ray caster + "
    "Adam).");
  reconstruct->add_option("--volume", rc->volume, "Volume file")->required();
  reconstruct
    ->add_option("--target", rc->targets,
      "Target image: RGB screenshot over the view's background, or RGBA with straight alpha "
      "(repeat for multi-view); one target: a letterbox is cut away, and a screenshot of "
      "ParaView's whole window (toolbars, panels) is matched at its render view, and a figure (a "
      "render pasted on a page of one colour, with a colour bar and a caption) inside the render")
    ->required();
  reconstruct->add_option("--view", rc->views,
    "View JSON of each target, in the same order. One target: optional — without it the camera "
    "(azimuth, elevation, roll, distance, pan from ParaView's reset camera; perspective or "
    "parallel projection) is estimated; with "
    "it the view's camera is used as is (or searched near it with --estimate-view). Several "
    "targets, or --mask: required, exact");
  reconstruct
    ->add_option("--out", rc->out, "Output TF: ParaView preset JSON (1D) or DDG 2D JSON (--2d)")
    ->required();
  reconstruct->add_option(
    "--mask", rc->masks, "Per-target mask image (first channel = weight in [0, 1])");
  reconstruct
    ->add_option("--background", rc->background,
      "Background r g b in [0, 1] of opaque (RGB) targets; a warning when a picture's border "
      "disagrees with it (default: estimated from the picture's border: one target without "
      "--mask: uniform or ParaView's vertical gradient; otherwise the view's background when the "
      "border agrees with it or has no one colour, else the border's, with a warning)")
    ->expected(3)
    ->check(CLI::Range(0.0, 1.0));
  reconstruct->add_flag("--2d", rc->twoD, "Reconstruct a 2D TF (value x gradient magnitude)");
  reconstruct->add_flag("--carry-look,--other-volume", rc->otherVolume,
    "The --target is a picture of another volume of the same kind: carry its look over (Core's "
    "carryLook, the filter's CarryLook, ddg.carry_look in pvpython; its "
    "colours matched to this volume's feature regions by rank, refined by colour distribution; "
    "no camera; --out-image renders it at azimuth 30, elevation 20; takes --iterations, --init, "
    "--seed, --shade on, --threads, --kind-network and refuses the match's fit options)");
  reconstruct->add_option("--kind-network", rc->kindNetwork,
    "--carry-look: the kind network that checks whether the picture shows a volume of this "
    "volume's kind (`ddg kind`; about 10 s; default: the project's Data/Models/kind when the "
    "program was built from the source tree; none: no check)");
  reconstruct->add_option("--bins", rc->bins, "TF resolution along the value (default 128)")
    ->check(CLI::Range(2, 4096));
  reconstruct
    ->add_option(
      "--gradient-bins", rc->gradientBins, "2D: bins along gradient magnitude (default 32)")
    ->check(CLI::Range(2, 1024));
  reconstruct
    ->add_option("--primitives", rc->primitives,
      "Fit K Gaussian primitives (mean, width, colour, opacity each) instead of free bins; "
      "rasterized at --bins, no smoothness prior (default 0: bins)")
    ->check(CLI::Range(0, 64));
  reconstruct->add_option("--loss", rc->loss, "l1 (default) or l2")
    ->check(CLI::IsMember({ "l1", "l2" }));
  reconstruct->add_option(
    "--smoothness", rc->smoothness, "Weight of the smoothness prior (default 0.01)");
  reconstruct
    ->add_option("--iterations", rc->iterations,
      "Maximum Adam steps, 1 to 100000 as the filter's Iterations (default 500; --carry-look: 150)")
    ->check(CLI::Range(1, 100000));
  reconstruct
    ->add_option("--lr", rc->learningRate, "Adam learning rate in logit space (default 0.2)")
    ->check(CLI::PositiveNumber);
  reconstruct
    ->add_option("--rays", rc->rays,
      "Random pixels per target and step, 0 = all (default 2048; one target without --mask: 512, "
      "and convergence judged over 100 steps)")
    ->check(CLI::NonNegativeNumber);
  reconstruct->add_option("--init", rc->init, "Initial TF (ParaView preset JSON; 1D only)");
  reconstruct->add_flag("--resample", rc->resample,
    "Resize targets to their view's size instead of refusing a size mismatch");
  reconstruct->add_option(
    "--out-image", rc->outImage, "Also write our render of the result at the first view");
  reconstruct->add_option("--seed", rc->seed,
    "Seed of the pixel sampling (default 1); --carry-look: of the colour distance's directions");
  reconstruct->add_option("--threads", rc->threads, "Worker threads (default 0: all cores)")
    ->check(CLI::Range(0, 256));
  reconstruct->add_option("--array", rc->array, "Point array (default: the active scalars)");
  reconstruct->add_flag("--quiet", rc->quiet, "Do not print progress");
  reconstruct
    ->add_option("--ssim-weight", rc->ssimWeight,
      "Weight of an extra (1 - SSIM) loss on a random 32x32 patch per view and step (default 0: "
      "off)")
    ->check(CLI::NonNegativeNumber);
  reconstruct->add_flag("--estimate-view", rc->estimateView,
    "One target with --view: the view's camera is a hint; search the camera near it (azimuth, "
    "elevation, roll, distance, pan)");
  reconstruct->add_option("--out-view", rc->outView,
    "One target: write the picture's view JSON (the camera found or given, the picture's size "
    "and background)");
  reconstruct
    ->add_option("--camera-candidates", rc->cameraCandidates,
      "One target, camera searched: distinct cameras whose silhouettes fit best that get a short "
      "reconstruction each (a multi-start; more is slower and finds more; default 6)")
    ->check(CLI::Range(1, 64));
  reconstruct
    ->add_option("--shade", rc->shade,
      "One target without --view: whether the picture is lit (ParaView's Shade, default\n"
      "coefficients): on, off, or auto (default: matched unlit and lit, refitted lit with\n"
      "Specular 0.5 / power 30, the best fit kept; about 3.5 times off's time). With --view, its\n"
      "\"lighting\"")
    ->check(CLI::IsMember({ "auto", "on", "off" }));
  reconstruct->add_option("--out-overlay", rc->outOverlay,
    "One target: write the mask of what was ignored as an overlay (orientation axes, text, a "
    "scalar bar): white = ignored");
  using ddg::cli::reconstruct::noteCarryOptions;
  return { reconstruct,
    [rc, reconstruct]
    {
      noteCarryOptions(*reconstruct, *rc);
      return runReconstruct(*rc);
    },
    // the carried look checks the picture's kind (the kind network: libtorch) unless told not to
    [rc] { return rc->otherVolume && rc->kindNetwork != "none"; } };
}
