// AnimateCommand.cxx: `ddg animate` — animate between two designs.
#ifdef DDG_WITH_TORCH
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/BuildDesignSpace.h"
#include "Gallery/BundleSession.h"
#include "Gallery/DesignReference.h"
#include "Gallery/Export.h"
#include "Gallery/Gallery.h"
#include "Gallery/History.h"
#include "Image/Image.h"
#include "Render/View.h"
#include "TransferFunction/ColorSpace.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct AnimateArgs
{
  std::string model, volume, from, to, out, view, easing = "smoothstep", lock, lockFrom;
  int frames = 24, keyEvery = 6, size = 128;
  double fps = 12;
};

int runAnimate(const AnimateArgs& a)
{
  const auto session = openBundle(a.model, a.volume);
  ddg::DesignGallery& g = session->gallery();
  const auto lock = makeLock(g, a.lock, a.lockFrom);
  const auto view =
    thumbnailView(session->volume(), session->gallery().model().spec(), a.view, a.size);
  const auto za = resolveDesign(g, a.from), zb = resolveDesign(g, a.to);
  const auto t0 = Clock::now();
  const auto anim = g.animate(za, zb, view, a.frames, a.easing, a.keyEvery, lock.get());
  std::filesystem::create_directories(a.out);
  char name[64];
  for (int f = 0; f < a.frames; ++f)
  {
    std::snprintf(name, sizeof(name), "/frame_%04d.png", f);
    ddg::writeImage(anim.real[f], a.out + name);
    std::snprintf(name, sizeof(name), "/neural_%04d.png", f);
    ddg::writeImage(anim.neural[f], a.out + name);
  }
  ddg::writeAnimation(anim.real, a.out + "/preview.gif", a.fps);
  for (int k : anim.keyframes)
  {
    std::snprintf(name, sizeof(name), "/key_%04d.json", k);
    ddg::exportTransferFunction(
      ddg::renamed(g.explicitTransferFunction(anim.latents[k], view, lock.get()),
        ddg::exportName(a.volume, "animation keyframe", a.out + name)),
      a.out + name, "paraview", g.caster(), view);
  }
  std::printf("animation: %d frames (%zu keyframes with explicit TFs, %s easing) in %.1f s; wrote "
              "%s/frame_*.png (ray casts), neural_*.png, key_*.json, preview.gif\n",
    a.frames, anim.keyframes.size(), a.easing.c_str(), msSince(t0) / 1000, a.out.c_str());
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addAnimateCommand(CLI::App& app)
{
  auto aa = std::make_shared<AnimateArgs>();
  auto* animate = app.add_subcommand("animate",
    "Animate between two designs (paper 1): an eased latent path, neural frames, explicit TFs at "
    "keyframes interpolated so the final frames are real ray casts; writes numbered PNG frames, "
    "the keyframe TFs and an animated GIF preview.");
  animate->add_option("--model", aa->model, "Model bundle directory (with outline.bin)")
    ->required();
  animate->add_option("--volume", aa->volume, "The bundle's volume")->required();
  animate
    ->add_option("--from", aa->from, "First design: row:N, image:PATH, latent:PATH or history:PATH")
    ->required();
  animate->add_option("--to", aa->to, "Last design")->required();
  animate->add_option("--frames", aa->frames, "Frames (default 24)")->check(CLI::Range(2, 10000));
  animate->add_option("--out", aa->out, "Output directory")->required();
  animate->add_option("--view", aa->view, "View JSON (default: the volume's default view)");
  animate->add_option("--size", aa->size, "Frame side without --view (default 128)")
    ->check(CLI::Range(8, 4096));
  animate->add_option("--easing", aa->easing, "linear, smoothstep (default) or cosine")
    ->check(CLI::IsMember({ "linear", "smoothstep", "cosine" }));
  animate->add_option("--key-every", aa->keyEvery, "Frames between keyframes (default 6)")
    ->check(CLI::Range(1, 10000));
  animate->add_option("--fps", aa->fps, "Preview frames per second (default 12)")
    ->check(CLI::Range(0.1, 100.0));
  animate->add_option("--lock", aa->lock, "Feature lock: regions kept from --lock-from");
  animate->add_option("--lock-from", aa->lockFrom, "The design the locked regions come from");
  return { animate, [aa] { return runAnimate(*aa); } };
}
#endif
