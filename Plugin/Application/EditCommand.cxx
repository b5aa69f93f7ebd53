// EditCommand.cxx: `ddg edit` — edit a design without TF widgets.
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

struct EditArgs
{
  std::string model, volume, design, view, pick, mask, axes, outImage, outDesign, outTF, outLatent,
    format = "paraview", lock, lockFrom, history;
  int cluster = -1, clusters = 4;
  double hue = 0, saturation = 1, lightness = 0, visibility = 1;
  bool white = false;
};

int runEdit(const EditArgs& a)
{
  const auto session = openBundle(a.model, a.volume);
  ddg::DesignGallery& g = session->gallery();
  const ddg::View view = ddg::readView(a.view);
  const auto lock = makeLock(g, a.lock, a.lockFrom);
  const auto reference = ddg::DesignReference::parse(a.design);
  std::vector<float> z = reference.resolve(g);
  const bool imageEdit = a.hue != 0 || a.saturation != 1 || a.lightness != 0 || a.visibility != 1;
  ddg::DesignHistory history;
  if (!a.history.empty())
  {
    if (lock)
      throw ddg::Error("--history does not record feature locks yet; edit without --lock");
    if (imageEdit && !a.mask.empty())
      throw ddg::Error("--history does not record brushed masks; edit a --cluster or --pick");
    history = reference.history();
  }
  if (imageEdit)
  {
    ddg::DesignEdit edit;
    edit.view = view;
    edit.clusters = a.clusters;
    edit.cluster = a.cluster;
    if (!a.mask.empty())
      edit.mask = ddg::toChannels(ddg::readImage(a.mask), 1);
    else if (!a.pick.empty())
    {
      const auto p = parseNumbers(a.pick, 2, "--pick");
      edit.pickX = static_cast<int>(p[0]);
      edit.pickY = static_cast<int>(p[1]);
    }
    if (edit.mask.empty() && edit.pickX < 0 && edit.cluster < 0)
      throw ddg::Error("an image edit needs what to edit: --pick x,y, --cluster N or --mask PNG");
    edit.hue = a.hue;
    edit.saturation = a.saturation;
    edit.lightness = a.lightness;
    edit.visibility = a.visibility;
    edit.white = a.white;
    const auto r = ddg::editDesign(g, z, edit, lock.get());
    for (int c = 0; c < r.clusters.count(); ++c)
    {
      const auto rgb = ddg::labToRgb(r.clusters.lab[c]);
      std::printf("colour cluster %d: %.0f %% of the visible pixels, rgb (%.2f, %.2f, %.2f)\n", c,
        100 * r.clusters.share[c], rgb[0], rgb[1], rgb[2]);
    }
    if (!a.outImage.empty())
      ddg::writeImage(
        ddg::compositeOverBackground(
          r.edited, a.white ? std::array<double, 3>{ 1, 1, 1 } : std::array<double, 3>{ 0, 0, 0 }),
        a.outImage);
    z = r.latent;
    if (!a.history.empty())
      history.steps.push_back(edit.toStep());
  }
  if (!a.axes.empty())
  {
    const auto steps = parseNumbers(a.axes, 0, "--axes");
    z = g.outline().moveAlongAxes(z, steps);
    history.steps.push_back(ddg::HistoryStep::axes(steps));
  }
  if (!a.history.empty())
    history.write(a.history);
  const auto p = g.outline().project(z.data());
  std::printf("edited design: outline position (%.4f, %.4f)\n", p[0], p[1]);
  if (!a.outDesign.empty())
    ddg::writeImage(
      ddg::compositeOverBackground(g.render(z, view, lock.get()), view.background), a.outDesign);
  if (!a.outLatent.empty())
    ddg::writeLatentFile(z, a.outLatent);
  if (!a.outTF.empty())
  {
    ddg::exportTransferFunction(ddg::renamed(g.explicitTransferFunction(z, view, lock.get()),
                                  ddg::exportName(a.volume, "edit", a.outTF)),
      a.outTF, a.format, g.caster(), view);
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addEditCommand(CLI::App& app)
{
  auto eda = std::make_shared<EditArgs>();
  auto* edit = app.add_subcommand("edit",
    "Edit a design without TF widgets (paper 1): recolour a feature or make it more/less visible "
    "in its image at the view (the feature: the colour cluster under --pick, --cluster N, or a "
    "brushed --mask), re-analyzed to a latent; and/or move along the principal axes (--axes).");
  edit->add_option("--model", eda->model, "Model bundle directory (with outline.bin)")->required();
  edit->add_option("--volume", eda->volume, "The bundle's volume")->required();
  edit
    ->add_option(
      "--design", eda->design, "The design: row:N, image:PATH, latent:PATH or history:PATH")
    ->required();
  edit->add_option("--view", eda->view, "View JSON the edit is made at")->required();
  edit->add_option("--pick", eda->pick, "x,y: edit the colour cluster under this pixel");
  edit->add_option("--cluster", eda->cluster, "Edit colour cluster N (largest first)");
  edit->add_option("--clusters", eda->clusters, "Colour clusters found (default 4)")
    ->check(CLI::Range(1, 16));
  edit->add_option("--mask", eda->mask, "Edit a brushed region: a gray PNG, white = edited");
  edit->add_option("--hue", eda->hue, "Rotate the hue by degrees");
  edit->add_option("--saturation", eda->saturation, "Scale the saturation (default 1)");
  edit->add_option("--lightness", eda->lightness, "Shift the lightness (CIELAB L*, -100..100)");
  edit->add_option(
    "--visibility", eda->visibility, "Scale the feature's opacity (> 1 more visible)");
  edit->add_option("--white", eda->white, "Analyze the edited image over white (default black)");
  edit->add_option(
    "--axes", eda->axes, "s0,s1,...: move along the principal axes by these standard deviations");
  edit->add_option("--out-image", eda->outImage, "Write the edited image (PNG)");
  edit->add_option("--out-design", eda->outDesign, "Write the edited design's render (PNG)");
  edit->add_option("--out-tf", eda->outTF, "Write the edited design's explicit TF");
  edit->add_option("--format", eda->format, "TF file format: paraview (default) or slicer")
    ->check(CLI::IsMember({ "paraview", "slicer" }));
  edit->add_option("--out-latent", eda->outLatent, "Write the edited latent (JSON)");
  edit->add_option("--history", eda->history,
    "Write the path to this design as a history file (continuing a history:PATH design)");
  edit->add_option("--lock", eda->lock, "Feature lock: regions kept from --lock-from");
  edit->add_option("--lock-from", eda->lockFrom, "The design the locked regions come from");
  return { edit, [eda] { return runEdit(*eda); } };
}
#endif
