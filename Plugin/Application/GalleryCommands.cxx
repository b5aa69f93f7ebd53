// GalleryCommands.cxx: `ddg outline`, `ddg gallery`, `ddg query` and `ddg export` — the design
// gallery (paper §5) over a model bundle, on the command line.
#include "GalleryCommands.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Gallery/Export.h"
#include "Image/Image.h"
#include "Render/RayCaster.h"
#include "Render/View.h"
#include "TransferFunction/ColorSpace.h"
#include "TransferFunction/TransferFunctionIO.h"
#ifdef DDG_WITH_TORCH
#include "Design/ExemplarGenerator.h"
#include "Gallery/BuildDesignSpace.h"
#include "Gallery/Gallery.h"
#include "Gallery/History.h"
#endif

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace
{

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// --- ddg export ------------------------------------------------------------------------------

struct ExportArgs
{
  std::string tf, volume, out, format = "paraview", view;
  int boxIterations = ddg::ParaViewBoxFitOptions().iterations;
};

int runExport(const ExportArgs& a)
{
  const auto tf = ddg::readTransferFunctionFile(a.tf);
  const ddg::Volume volume = ddg::readVolumeFile(a.volume);
  const ddg::RayCaster caster(volume);
  double unit = caster.defaultOpacityUnitDistance();
  if (!a.view.empty())
  {
    const auto view = ddg::readView(a.view);
    if (view.opacityUnitDistance)
      unit = *view.opacityUnitDistance;
  }
  if (a.format == "paraview-2d")
  {
    if (!tf.is2D)
      throw ddg::Error(
        "--format paraview-2d exports 2D TFs; a 1D TF is a ParaView preset (paraview)");
    ddg::View view;
    view.opacityUnitDistance = unit;
    ddg::ParaViewBoxFitReport report;
    ddg::ParaViewBoxFitOptions options;
    options.iterations = a.boxIterations;
    const auto pv =
      ddg::fitParaViewBoxes(tf.tf2D, caster.paraviewMapping2D(view), options, &report);
    ddg::writeFileAtomic(a.out, pv.toJson(&report), "ParaView 2D transfer function");
    std::printf("wrote %s (paraview-2d: %zu boxes; fit RMSE %.4f, alpha RMSE %.4f, from %.4f)\n",
      a.out.c_str(), pv.boxes.size(), report.rmse, report.alphaRmse, report.initialRmse);
    return 0;
  }
  ddg::exportTransferFunction(tf, a.out, a.format, volume.range(), unit);
  std::printf("wrote %s (%s)\n", a.out.c_str(), a.format.c_str());
  return 0;
}

#ifdef DDG_WITH_TORCH

/// The opacity unit distance a TF is exported with: the view's, or ParaView's default.
double unitDistance(const ddg::DesignGallery& gallery, const ddg::View& view)
{
  return view.opacityUnitDistance ? *view.opacityUnitDistance
                                  : gallery.caster().defaultOpacityUnitDistance();
}

std::vector<double> parseNumbers(const std::string& text, size_t count, const char* what);

ddg::OutlineBox parseBox(const std::string& text)
{
  const auto v = parseNumbers(text, 4, "--box");
  ddg::OutlineBox b{ v[0], v[1], v[2], v[3] };
  if (!b.valid())
    throw ddg::Error("--box needs x0 < x1 and y0 < y1");
  return b;
}

ddg::DesignHistory historyOf(const std::string& ref);
std::unique_ptr<ddg::FeatureLock> makeLock(
  const ddg::DesignGallery& g, const std::string& regions, const std::string& from);

/// The bundle, its volume and its outline, loaded and checked together.
struct LoadedGallery
{
  ddg::Volume volume;
  ddg::NeuralDesignModel model;
  std::unique_ptr<ddg::DesignGallery> gallery;
  double loadMs = 0, pcaMs = 0;

  LoadedGallery(const std::string& modelDir, const std::string& volumePath)
    : volume(ddg::readVolumeFile(volumePath))
    , model(ddg::NeuralDesignModel::loadBundle(modelDir, ddg::volumeFingerprint(volume)))
  {
    const auto t0 = Clock::now();
    ddg::LatentSet latents;
    try
    {
      latents = ddg::readLatentSet(ddg::outlineFile(modelDir));
    }
    catch (const ddg::Error& e)
    {
      throw ddg::Error(std::string(e.what()) + " (build the outline with: ddg outline --model " +
        modelDir + " --volume " + volumePath + ")");
    }
    loadMs = msSince(t0);
    const auto t1 = Clock::now();
    gallery = std::make_unique<ddg::DesignGallery>(model, volume, std::move(latents));
    pcaMs = msSince(t1);
  }
};

// --- ddg outline -----------------------------------------------------------------------------

struct OutlineArgs
{
  std::string model, volume, out;
  int count = 50000, threads = 0;
  std::uint64_t seed = 1, firstIndex = 0;
  bool quiet = false;
};

int runOutline(const OutlineArgs& a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume);
  const auto model = ddg::NeuralDesignModel::loadBundle(a.model, ddg::volumeFingerprint(volume));
  const auto t0 = Clock::now();
  int lastPercent = -1;
  const auto set = ddg::buildOutlineLatents(model, volume, a.count, a.seed, a.firstIndex, a.threads,
    [&](double f)
    {
      const int p = static_cast<int>(f * 100);
      if (!a.quiet && p / 10 != lastPercent / 10)
      {
        std::printf("outline: %3d %%  %.0f s\n", p, msSince(t0) / 1000);
        std::fflush(stdout);
      }
      lastPercent = p;
      return true;
    });
  const double seconds = msSince(t0) / 1000;
  const std::string out = a.out.empty() ? ddg::outlineFile(a.model) : a.out;
  ddg::writeLatentSet(set, out);
  const auto t1 = Clock::now();
  const ddg::DesignOutline outline(set);
  std::printf("outline: %d designs in %.1f s (%.0f designs/s); PCA %.0f ms, the plane explains "
              "%.1f %% + %.1f %% of the variance; wrote %s\n",
    set.count(), seconds, set.count() / seconds, msSince(t1), 100 * outline.explainedVariance(0),
    100 * outline.explainedVariance(1), out.c_str());
  return 0;
}

// --- ddg gallery -----------------------------------------------------------------------------

struct GalleryArgs
{
  std::string model, volume, out, view, box, state, saveState, list, lock, lockFrom;
  int count = 64, thumb = 96, side = 1024;
  std::uint64_t seed = 1;
};

ddg::View thumbnailView(const ddg::Volume& volume, const std::string& path, int size)
{
  ddg::View v = path.empty() ? ddg::defaultView(volume, size, size) : ddg::readView(path);
  v.width = v.height = size;
  return v;
}

int runGallery(const GalleryArgs& a)
{
  LoadedGallery g(a.model, a.volume);
  ddg::OutlineViewState state;
  if (!a.state.empty())
  {
    std::ifstream in(a.state);
    if (!in)
      throw ddg::Error("cannot open the view state " + a.state);
    std::stringstream text;
    text << in.rdbuf();
    state = ddg::OutlineViewState::fromJson(text.str());
  }
  else
  {
    state.boxes = { g.gallery->outline().bounds() };
    state.count = a.count;
    state.seed = a.seed;
  }
  if (!a.box.empty())
    state.drillIn(parseBox(a.box));
  const auto view = thumbnailView(g.volume, a.view, a.thumb);
  const auto t0 = Clock::now();
  const auto rows =
    ddg::selectThumbnails(g.gallery->outline(), state.current(), state.count, state.seed);
  const double selectMs = msSince(t0);
  const auto t1 = Clock::now();
  const auto lock = makeLock(*g.gallery, a.lock, a.lockFrom);
  const ddg::Image sheet = g.gallery->sheet(state, view, a.side, lock.get());
  const double sheetMs = msSince(t1);
  ddg::writeImage(sheet, a.out);
  const auto& b = state.current();
  std::printf("outline of %d designs, box [%.3g, %.3g] x [%.3g, %.3g] holds %zu; %zu thumbnails "
              "(dispersion %.3f of the box)\n",
    g.gallery->outline().count(), b.x0, b.x1, b.y0, b.y1, g.gallery->outline().inside(b).size(),
    rows.size(), ddg::dispersion(g.gallery->outline(), b, rows));
  std::printf("times: load %.0f ms, PCA + layout %.0f ms, thumbnail choice %.1f ms, renders + "
              "sheet %.0f ms; wrote %s\n",
    g.loadMs, g.pcaMs, selectMs, sheetMs, a.out.c_str());
  if (!a.saveState.empty())
    ddg::writeFileAtomic(a.saveState, state.toJson(), "outline view state");
  if (!a.list.empty())
  {
    std::string csv = "row,design_index,x,y\n";
    char line[128];
    for (int r : rows)
    {
      const auto p = g.gallery->outline().point(r);
      std::snprintf(line, sizeof(line), "%d,%llu,%.5f,%.5f\n", r,
        static_cast<unsigned long long>(g.gallery->outline().latents().indices[r]), p[0], p[1]);
      csv += line;
    }
    ddg::writeFileAtomic(a.list, csv, "thumbnail list");
  }
  return 0;
}

// --- ddg query -------------------------------------------------------------------------------

struct QueryArgs
{
  std::string model, volume, image, view, outPreview, outTF, outInput, format = "paraview", history;
  int neighbours = 5;
};

int runQuery(const QueryArgs& a)
{
  const auto t0 = Clock::now();
  LoadedGallery g(a.model, a.volume);
  const ddg::View view = ddg::readView(a.view);
  const ddg::Image image = ddg::readImage(a.image);
  const double loadMs = msSince(t0);
  const auto t1 = Clock::now();
  const auto r = g.gallery->query(image, view, a.neighbours);
  const double queryMs = msSince(t1);
  std::printf(
    "query %s: outline position (%.4f, %.4f)\n", a.image.c_str(), r.position[0], r.position[1]);
  for (size_t i = 0; i < r.neighbours.size(); ++i)
  {
    const auto& n = r.neighbours[i];
    std::printf("  neighbour %zu: design row %d (index %llu), latent distance %.4f\n", i + 1, n.row,
      static_cast<unsigned long long>(g.gallery->outline().latents().indices[n.row]), n.distance);
  }
  if (!a.outInput.empty())
    ddg::writeImage(r.input, a.outInput);
  if (!a.history.empty())
    historyOf("image:" + a.image).write(a.history);
  if (!a.outPreview.empty())
    ddg::writeImage(ddg::compositeOverBackground(r.preview, view.background), a.outPreview);
  double tfMs = 0;
  if (!a.outTF.empty())
  {
    const auto t2 = Clock::now();
    const auto tf = g.gallery->explicitTransferFunction(r.latent, view);
    ddg::exportTransferFunction(
      tf, a.outTF, a.format, g.volume.range(), unitDistance(*g.gallery, view));
    tfMs = msSince(t2);
  }
  std::printf("times: load %.0f ms (PCA %.0f ms), query (analyzer, neighbours, %dx%d preview) "
              "%.1f ms, TF file %.0f ms; screenshot -> TF file %.0f ms\n",
    loadMs, g.pcaMs, view.width, view.height, queryMs, tfMs, queryMs + tfMs);
  return 0;
}

// --- designs named on the command line ------------------------------------------------------

/// The latent of a latent JSON file {"latent": [...]} (written by --out-latent).
std::vector<float> readLatentFile(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw ddg::Error("cannot open the latent file " + path);
  std::stringstream text;
  text << in.rdbuf();
  try
  {
    return nlohmann::json::parse(text.str()).at("latent").get<std::vector<float>>();
  }
  catch (const nlohmann::json::exception& e)
  {
    throw ddg::Error(path + ": not a latent file (" + e.what() + ")");
  }
}

/// A design reference: "row:N" (row N of the outline), "image:PATH" (the analyzer's latent of an
/// image, framed as a query), "latent:PATH" (a latent JSON {"latent": [...]} written by
/// --out-latent) or "history:PATH" (where a history file's path ends).
std::vector<float> resolveDesign(const ddg::DesignGallery& g, const std::string& ref)
{
  const auto colon = ref.find(':');
  const std::string kind = ref.substr(0, colon),
                    arg = colon == std::string::npos ? "" : ref.substr(colon + 1);
  if (colon == std::string::npos || arg.empty())
    throw ddg::Error("design '" + ref + "': use row:N, image:PATH, latent:PATH or history:PATH");
  if (kind == "row")
  {
    try
    {
      size_t used = 0;
      const int row = std::stoi(arg, &used);
      if (used != arg.size())
        throw std::invalid_argument(arg);
      return g.latent(row);
    }
    catch (const std::logic_error&)
    {
      throw ddg::Error("design '" + ref + "': row must be an integer");
    }
  }
  if (kind == "image")
    return g.analyzeImage(ddg::readImage(arg));
  if (kind == "latent")
  {
    std::vector<float> z = readLatentFile(arg);
    if (static_cast<int>(z.size()) != g.outline().latents().dim)
      throw ddg::Error(arg + ": a latent of " + std::to_string(z.size()) +
        " values, the model's have " + std::to_string(g.outline().latents().dim) +
        ": it comes from another model");
    return z;
  }
  if (kind == "history")
    return ddg::replayHistory(g, ddg::DesignHistory::read(arg));
  throw ddg::Error(
    "design '" + ref + "': unknown kind '" + kind + "' (row, image, latent or history)");
}

/// The history that leads to a design reference (for --history): row -> [pick], image ->
/// [query], latent file -> [latent], history -> its steps.
ddg::DesignHistory historyOf(const std::string& ref)
{
  const auto colon = ref.find(':');
  const std::string kind = ref.substr(0, colon), arg = ref.substr(colon + 1);
  ddg::DesignHistory h;
  ddg::HistoryStep s;
  if (kind == "row")
  {
    s.action = "pick";
    s.row = std::stoi(arg);
    h.steps.push_back(s);
  }
  else if (kind == "image")
  {
    s.action = "query";
    s.image = arg;
    h.steps.push_back(s);
  }
  else if (kind == "latent")
  {
    s.action = "latent";
    s.latent = readLatentFile(arg);
    h.steps.push_back(s);
  }
  else if (kind == "history")
    h = ddg::DesignHistory::read(arg);
  else
    throw ddg::Error("--history: a design given as " + kind +
      ":... has no history to continue; "
      "start from row:N, image:PATH, latent:PATH or history:PATH");
  return h;
}

void writeLatent(const std::vector<float>& z, const std::string& path)
{
  ddg::writeFileAtomic(path, nlohmann::json{ { "latent", z } }.dump() + "\n", "latent");
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
      throw ddg::Error(std::string(what) + ": '" + part + "' is not an integer");
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
      throw ddg::Error(std::string(what) + ": '" + part + "' is not a number");
    }
  }
  if (count > 0 && v.size() != count)
    throw ddg::Error(std::string(what) + " takes " + std::to_string(count) + " numbers");
  return v;
}

/// --lock REGIONS --lock-from DESIGN: the feature lock, or none.
std::unique_ptr<ddg::FeatureLock> makeLock(
  const ddg::DesignGallery& g, const std::string& regions, const std::string& from)
{
  if (regions.empty())
    return nullptr;
  if (from.empty())
    throw ddg::Error("--lock needs --lock-from: the design whose regions stay fixed");
  return std::make_unique<ddg::FeatureLock>(
    g.lockRegions(resolveDesign(g, from), parseInts(regions, "--lock")));
}

// --- ddg navigate ----------------------------------------------------------------------------

struct NavigateArgs
{
  std::string model, volume, out, view, window, lock, lockFrom;
  std::vector<std::string> designs;
  int rows = 5, cols = 5, thumb = 96;
};

int runNavigate(const NavigateArgs& a)
{
  LoadedGallery g(a.model, a.volume);
  std::vector<ddg::Latent> anchors;
  for (const auto& d : a.designs)
    anchors.push_back(resolveDesign(*g.gallery, d));
  ddg::NavigationWindow w;
  if (!a.window.empty())
  {
    const auto v = parseNumbers(a.window, 4, "--window");
    w = { v[0], v[1], v[2], v[3] };
  }
  const int rows = anchors.size() == 2 ? 1 : a.rows;
  const auto cells = ddg::navigationGrid(anchors, rows, a.cols, w);
  const auto lock = makeLock(*g.gallery, a.lock, a.lockFrom);
  const auto view = thumbnailView(g.volume, a.view, a.thumb);
  const auto t0 = Clock::now();
  std::vector<ddg::Image> images;
  for (const auto& c : cells)
    images.push_back(c.latent.empty()
        ? ddg::Image(view.width, view.height, 3, 1.0f)
        : ddg::compositeOverBackground(
            g.gallery->render(c.latent, view, lock.get()), view.background));
  ddg::writeImage(ddg::tileImages(images, a.cols), a.out);
  std::printf("navigation grid %d x %d between %zu designs, window u [%g, %g] v [%g, %g]%s: %zu "
              "renders in %.0f ms; wrote %s\n",
    rows, a.cols, anchors.size(), w.u0, w.u1, w.v0, w.v1, lock ? " (feature lock)" : "",
    cells.size(), msSince(t0), a.out.c_str());
  return 0;
}

// --- ddg edit --------------------------------------------------------------------------------

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
  LoadedGallery g(a.model, a.volume);
  const ddg::View view = ddg::readView(a.view);
  const auto lock = makeLock(*g.gallery, a.lock, a.lockFrom);
  std::vector<float> z = resolveDesign(*g.gallery, a.design);
  const bool imageEdit = a.hue != 0 || a.saturation != 1 || a.lightness != 0 || a.visibility != 1;
  ddg::DesignHistory history;
  if (!a.history.empty())
  {
    if (lock)
      throw ddg::Error("--history does not record feature locks yet; edit without --lock");
    if (imageEdit && !a.mask.empty())
      throw ddg::Error("--history does not record brushed masks; edit a --cluster or --pick");
    history = historyOf(a.design);
  }
  if (imageEdit)
  {
    const ddg::Image before = g.gallery->render(z, view, lock.get());
    const auto clusters = ddg::colorClusters(before, a.clusters);
    for (int c = 0; c < clusters.count(); ++c)
    {
      const auto rgb = ddg::labToRgb(clusters.lab[c]);
      std::printf("colour cluster %d: %.0f %% of the visible pixels, rgb (%.2f, %.2f, %.2f)\n", c,
        100 * clusters.share[c], rgb[0], rgb[1], rgb[2]);
    }
    ddg::EditRegion region;
    if (!a.mask.empty())
    {
      region.mask = ddg::toChannels(ddg::readImage(a.mask), 1);
      if (region.mask.width != view.width || region.mask.height != view.height)
        region.mask = ddg::resizeImage(region.mask, view.width, view.height);
    }
    else if (!a.pick.empty())
    {
      const auto p = parseNumbers(a.pick, 2, "--pick");
      region.cluster = clusters.at(static_cast<int>(p[0]), static_cast<int>(p[1]));
      if (region.cluster < 0)
        throw ddg::Error("--pick: the pixel shows no feature (it is background)");
    }
    else
      region.cluster = a.cluster;
    if (region.mask.empty() && region.cluster < 0)
      throw ddg::Error("an image edit needs what to edit: --pick x,y, --cluster N or --mask PNG");
    ddg::Image edited = before;
    if (a.hue != 0 || a.saturation != 1 || a.lightness != 0)
      edited = ddg::recolour(edited, clusters, region, a.hue, a.saturation, a.lightness);
    if (a.visibility != 1)
      edited = ddg::changeVisibility(edited, clusters, region, a.visibility);
    const std::array<double, 3> bg =
      a.white ? std::array<double, 3>{ 1, 1, 1 } : std::array<double, 3>{ 0, 0, 0 };
    if (!a.outImage.empty())
      ddg::writeImage(ddg::compositeOverBackground(edited, bg), a.outImage);
    z = g.gallery->analyzeEdit(edited, bg);
    ddg::HistoryStep step;
    step.action = "edit";
    step.viewJson = ddg::viewToJson(view);
    step.clusters = a.clusters;
    step.cluster = a.pick.empty() ? region.cluster : -1;
    if (!a.pick.empty())
    {
      const auto p = parseNumbers(a.pick, 2, "--pick");
      step.pickX = static_cast<int>(p[0]);
      step.pickY = static_cast<int>(p[1]);
    }
    step.hue = a.hue;
    step.saturation = a.saturation;
    step.lightness = a.lightness;
    step.visibility = a.visibility;
    step.white = a.white;
    history.steps.push_back(step);
  }
  if (!a.axes.empty())
  {
    ddg::HistoryStep step;
    step.action = "axes";
    step.steps = parseNumbers(a.axes, 0, "--axes");
    z = g.gallery->outline().moveAlongAxes(z, step.steps);
    history.steps.push_back(step);
  }
  if (!a.history.empty())
    history.write(a.history);
  const auto p = g.gallery->outline().project(z.data());
  std::printf("edited design: outline position (%.4f, %.4f)\n", p[0], p[1]);
  if (!a.outDesign.empty())
    ddg::writeImage(
      ddg::compositeOverBackground(g.gallery->render(z, view, lock.get()), view.background),
      a.outDesign);
  if (!a.outLatent.empty())
    writeLatent(z, a.outLatent);
  if (!a.outTF.empty())
  {
    ddg::exportTransferFunction(g.gallery->explicitTransferFunction(z, view, lock.get()), a.outTF,
      a.format, g.volume.range(), unitDistance(*g.gallery, view));
  }
  return 0;
}

// --- ddg animate -----------------------------------------------------------------------------

struct AnimateArgs
{
  std::string model, volume, from, to, out, view, easing = "smoothstep", lock, lockFrom;
  int frames = 24, keyEvery = 6, size = 128;
  double fps = 12;
};

int runAnimate(const AnimateArgs& a)
{
  LoadedGallery g(a.model, a.volume);
  const auto lock = makeLock(*g.gallery, a.lock, a.lockFrom);
  const auto view = thumbnailView(g.volume, a.view, a.size);
  const auto za = resolveDesign(*g.gallery, a.from), zb = resolveDesign(*g.gallery, a.to);
  const auto t0 = Clock::now();
  const auto anim = g.gallery->animate(za, zb, view, a.frames, a.easing, a.keyEvery, lock.get());
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
      g.gallery->explicitTransferFunction(anim.latents[k], view, lock.get()), a.out + name,
      "paraview", g.volume.range(), unitDistance(*g.gallery, view));
  }
  std::printf("animation: %d frames (%zu keyframes with explicit TFs, %s easing) in %.1f s; wrote "
              "%s/frame_*.png (ray casts), neural_*.png, key_*.json, preview.gif\n",
    a.frames, anim.keyframes.size(), a.easing.c_str(), msSince(t0) / 1000, a.out.c_str());
  return 0;
}

// --- ddg fidelity ----------------------------------------------------------------------------

struct FidelityArgs
{
  std::string model, volume, design, view, outHeat, outPair;
};

int runFidelity(const FidelityArgs& a)
{
  LoadedGallery g(a.model, a.volume);
  const ddg::View view = ddg::readView(a.view);
  const auto f = g.gallery->fidelity(resolveDesign(*g.gallery, a.design), view);
  std::printf(
    "fidelity of %s at %dx%d: neural image vs. ray cast of its exported TF: PSNR %.2f dB, "
    "SSIM %.4f, largest pixel error %.3f\n",
    a.design.c_str(), view.width, view.height, f.psnr, f.ssim, f.maxError);
  if (!a.outHeat.empty())
    ddg::writeImage(f.heat, a.outHeat);
  if (!a.outPair.empty())
    ddg::writeImage(ddg::tileImages({ f.neural, f.real, f.heat }, 3), a.outPair);
  return 0;
}

// --- ddg replay ------------------------------------------------------------------------------

struct ReplayArgs
{
  std::string model, volume, history, view, outTF, outDesign, outLatent, format = "paraview";
};

int runReplay(const ReplayArgs& a)
{
  LoadedGallery g(a.model, a.volume);
  const auto history = ddg::DesignHistory::read(a.history);
  std::vector<float> z;
  for (size_t i = 0; i < history.steps.size(); ++i)
  {
    z = ddg::applyHistoryStep(*g.gallery, history.steps[i], z);
    const auto p = g.gallery->outline().project(z.data());
    std::printf("step %zu (%s): outline position (%.4f, %.4f)\n", i + 1,
      history.steps[i].action.c_str(), p[0], p[1]);
  }
  const ddg::View view =
    a.view.empty() ? ddg::defaultView(g.volume, 256, 256) : ddg::readView(a.view);
  if (!a.outLatent.empty())
    writeLatent(z, a.outLatent);
  if (!a.outDesign.empty())
    ddg::writeImage(
      ddg::compositeOverBackground(g.gallery->render(z, view), view.background), a.outDesign);
  if (!a.outTF.empty())
  {
    ddg::exportTransferFunction(g.gallery->explicitTransferFunction(z, view), a.outTF, a.format,
      g.volume.range(), unitDistance(*g.gallery, view));
  }
  return 0;
}

// --- ddg build -------------------------------------------------------------------------------

struct BuildArgs
{
  std::string volume, out, spec;
  ddg::BuildOptions o;
  bool quiet = false;
};

int runBuild(BuildArgs a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume);
  if (!a.spec.empty())
    a.o.spec = ddg::readDesignSpaceSpec(a.spec);
  std::string lastStage;
  int lastPercent = -1;
  const auto r = ddg::buildDesignSpace(volume, a.volume, a.out, a.o,
    [&](const std::string& stage, double f)
    {
      const int p = static_cast<int>(100 * f);
      if (!a.quiet && (stage != lastStage || p / 10 != lastPercent / 10))
      {
        std::printf("build: %-9s %3d %%\n", stage.c_str(), p);
        std::fflush(stdout);
        lastStage = stage;
        lastPercent = p;
      }
      return true;
    });
  std::printf("built %s: exemplars %.0f s, training %d iterations in %.0f s, outline %.0f s; "
              "held-out %d: PSNR %.2f dB, SSIM %.4f, EMD %.3f, invariance %.3f\n",
    a.out.c_str(), r.generateSeconds, r.training.iterations, r.training.seconds, r.outlineSeconds,
    r.evaluation.count, r.evaluation.psnr, r.evaluation.ssim, r.evaluation.emd,
    r.evaluation.invariance);
  return 0;
}

// --- ddg recall ------------------------------------------------------------------------------

struct RecallArgs
{
  std::string model, data;
  int count = 200, k = 5;
};

int runRecall(const RecallArgs& a)
{
  const ddg::ExemplarDataset data(a.data);
  const auto model = ddg::NeuralDesignModel::loadBundle(a.model, data.fingerprint());
  const auto latents = ddg::readLatentSet(ddg::outlineFile(a.model));
  const auto t0 = Clock::now();
  const auto r = ddg::queryRecall(model, latents, data, a.count, a.k);
  std::printf("query recall@%d over %d held-out designs joined to the %d-design outline: own "
              "image %.1f %%, other view %.1f %% (%.1f s)\n",
    r.k, r.count, latents.count(), 100 * r.ownImage, 100 * r.otherView, msSince(t0) / 1000);
  return 0;
}

#endif

} // namespace

std::function<int()> addGalleryCommands(CLI::App& app)
{
  std::vector<std::pair<CLI::App*, std::function<int()>>> commands;

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
  commands.push_back({ exportCmd, [ea] { return runExport(*ea); } });

#ifdef DDG_WITH_TORCH
  auto oa = std::make_shared<OutlineArgs>();
  auto* outline = app.add_subcommand("outline",
    "Build a bundle's design-space outline (paper 5.1): latents of many generated designs "
    "(each rendered at its own view and analyzed), stored as outline.bin in the bundle.");
  outline->add_option("--model", oa->model, "Model bundle directory")->required();
  outline->add_option("--volume", oa->volume, "The bundle's volume")->required();
  outline->add_option("--count", oa->count, "Designs (default 50000)")
    ->check(CLI::Range(3, 10000000));
  outline->add_option("--seed", oa->seed,
    "Design-space seed (default 1: designs 0..N-1 include the training exemplars)");
  outline->add_option("--first-index", oa->firstIndex, "Index of the first design (default 0)");
  outline->add_option("--threads", oa->threads, "Render threads (default 0: all cores)");
  outline->add_option("--out", oa->out, "Output file (default MODEL/outline.bin)");
  outline->add_flag("--quiet", oa->quiet, "Do not print progress");
  commands.push_back({ outline, [oa] { return runOutline(*oa); } });

  auto ga = std::make_shared<GalleryArgs>();
  auto* gallery = app.add_subcommand("gallery",
    "Write the outline sheet (paper 5.1): every design of the bundle's outline as a dot on the "
    "PCA plane and K thumbnails chosen to cover the box shown (farthest-point sampling), "
    "rendered by the model at the view.");
  gallery->add_option("--model", ga->model, "Model bundle directory (with outline.bin)")
    ->required();
  gallery->add_option("--volume", ga->volume, "The bundle's volume")->required();
  gallery->add_option("--out", ga->out, "Output sheet (PNG)")->required();
  gallery->add_option(
    "--view", ga->view, "View JSON of the thumbnails (default: the volume's default view)");
  gallery->add_option("--box", ga->box, "Drill into x0,y0,x1,y1 on the PCA plane");
  gallery->add_option("--count", ga->count, "Thumbnails K (default 64)")
    ->check(CLI::Range(1, 1024));
  gallery->add_option(
    "--seed", ga->seed, "Thumbnail sampling seed; another seed resamples (default 1)");
  gallery->add_option("--thumb", ga->thumb, "Thumbnail side in pixels (default 96)")
    ->check(CLI::Range(8, 512));
  gallery->add_option("--side", ga->side, "Sheet side in pixels (default 1024)")
    ->check(CLI::Range(64, 8192));
  gallery->add_option("--state", ga->state,
    "Start from a saved view state JSON ({\"boxes\": [[x0,y0,x1,y1], ...], \"count\", \"seed\"})");
  gallery->add_option("--save-state", ga->saveState, "Write the view state JSON shown");
  gallery->add_option("--lock", ga->lock,
    "Feature lock: regions (e.g. 0,2) kept from --lock-from in every thumbnail");
  gallery->add_option("--lock-from", ga->lockFrom, "The design the locked regions come from");
  gallery->add_option(
    "--list", ga->list, "Write the thumbnails' rows, design indices and positions (CSV)");
  commands.push_back({ gallery, [ga] { return runGallery(*ga); } });

  auto qa = std::make_shared<QueryArgs>();
  auto* query = app.add_subcommand("query",
    "Query the design space with an image (paper 5.2): a screenshot of this volume, another "
    "volume or a figure; any size and aspect, RGB or RGBA, white or black background (framed "
    "around its content, see README). Prints its outline position and nearest designs, writes "
    "the model's render at the view and the explicit TF.");
  query->add_option("--model", qa->model, "Model bundle directory (with outline.bin)")->required();
  query->add_option("--volume", qa->volume, "The bundle's volume")->required();
  query->add_option("--image", qa->image, "Query image")->required();
  query->add_option("--view", qa->view, "View JSON of the preview and the TF (the current camera)")
    ->required();
  query->add_option(
    "--out-preview", qa->outPreview, "Write the preview (PNG, over the view's background)");
  query->add_option("--out-tf", qa->outTF,
    "Write the explicit TF (decoder: its output; U-Net: reconstructed from its render)");
  query->add_option("--format", qa->format, "TF file format: paraview (default) or slicer")
    ->check(CLI::IsMember({ "paraview", "slicer" }));
  query->add_option("--out-input", qa->outInput, "Write what the analyzer saw (PNG)");
  query->add_option("--history", qa->history,
    "Start a history file that replays this path (ddg edit --history, ddg replay)");
  query->add_option("--neighbours", qa->neighbours, "Nearest designs listed (default 5)")
    ->check(CLI::Range(0, 1000));
  commands.push_back({ query, [qa] { return runQuery(*qa); } });

  auto na = std::make_shared<NavigateArgs>();
  auto* navigate = app.add_subcommand("navigate",
    "Navigate between 2-4 designs (paper 1): a grid of the sub-space they span (2: a line, 3: "
    "barycentric triangle, 4: bilinear), each cell rendered by the model; --window pans and "
    "zooms inside it. Designs: row:N (outline row), image:PATH, latent:PATH.");
  navigate->add_option("--model", na->model, "Model bundle directory (with outline.bin)")
    ->required();
  navigate->add_option("--volume", na->volume, "The bundle's volume")->required();
  navigate->add_option("--design", na->designs, "A design (2 to 4 times)")
    ->required()
    ->expected(2, 4);
  navigate->add_option("--out", na->out, "Output grid (PNG)")->required();
  navigate->add_option("--rows", na->rows, "Grid rows (default 5; 1 for two designs)")
    ->check(CLI::Range(1, 64));
  navigate->add_option("--cols", na->cols, "Grid columns (default 5)")->check(CLI::Range(1, 64));
  navigate->add_option("--window", na->window, "u0,v0,u1,v1 shown (default 0,0,1,1)");
  navigate->add_option("--view", na->view, "View JSON (default: the volume's default view)");
  navigate->add_option("--thumb", na->thumb, "Cell side in pixels (default 96)")
    ->check(CLI::Range(8, 512));
  navigate->add_option(
    "--lock", na->lock, "Feature lock: regions (e.g. 0,2) kept from --lock-from");
  navigate->add_option("--lock-from", na->lockFrom, "The design the locked regions come from");
  commands.push_back({ navigate, [na] { return runNavigate(*na); } });

  auto eda = std::make_shared<EditArgs>();
  auto* edit = app.add_subcommand("edit",
    "Edit a design without TF widgets (paper 1): recolour a feature or make it more/less visible "
    "in its image at the view (the feature: the colour cluster under --pick, --cluster N, or a "
    "brushed --mask), re-analyzed to a latent; and/or move along the principal axes (--axes).");
  edit->add_option("--model", eda->model, "Model bundle directory (with outline.bin)")->required();
  edit->add_option("--volume", eda->volume, "The bundle's volume")->required();
  edit->add_option("--design", eda->design, "The design: row:N, image:PATH or latent:PATH")
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
  commands.push_back({ edit, [eda] { return runEdit(*eda); } });

  auto aa = std::make_shared<AnimateArgs>();
  auto* animate = app.add_subcommand("animate",
    "Animate between two designs (paper 1): an eased latent path, neural frames, explicit TFs at "
    "keyframes interpolated so the final frames are real ray casts; writes numbered PNG frames, "
    "the keyframe TFs and an animated GIF preview.");
  animate->add_option("--model", aa->model, "Model bundle directory (with outline.bin)")
    ->required();
  animate->add_option("--volume", aa->volume, "The bundle's volume")->required();
  animate->add_option("--from", aa->from, "First design: row:N, image:PATH or latent:PATH")
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
  commands.push_back({ animate, [aa] { return runAnimate(*aa); } });

  auto fa = std::make_shared<FidelityArgs>();
  auto* fidelity = app.add_subcommand("fidelity",
    "How far a design's neural image is from what ParaView will show with its explicit TF: "
    "PSNR, SSIM and a heat map (black: equal, white: 0.25 or more).");
  fidelity->add_option("--model", fa->model, "Model bundle directory (with outline.bin)")
    ->required();
  fidelity->add_option("--volume", fa->volume, "The bundle's volume")->required();
  fidelity->add_option("--design", fa->design, "The design: row:N, image:PATH or latent:PATH")
    ->required();
  fidelity->add_option("--view", fa->view, "View JSON")->required();
  fidelity->add_option("--out-heat", fa->outHeat, "Write the heat map (PNG)");
  fidelity->add_option(
    "--out-pair", fa->outPair, "Write neural | ray cast | heat map side by side (PNG)");
  commands.push_back({ fidelity, [fa] { return runFidelity(*fa); } });

  auto ba = std::make_shared<BuildArgs>();
  auto* build = app.add_subcommand("build",
    "Build a design space for a volume in one command: exemplars, the decoder model trained "
    "within --minutes, its held-out figures, the bundle and its outline (the steps of "
    "scripts/train_model.sh, sized for your own volume).");
  build->add_option("--volume", ba->volume, "Volume file")->required();
  build->add_option("--out", ba->out, "Bundle directory to write")->required();
  build->add_option(
    "--spec", ba->spec, "Design-space spec JSON (default: found from the histogram)");
  build->add_option("--count", ba->o.count, "Training exemplars (default 2000)")
    ->check(CLI::Range(8, 10000000));
  build->add_option("--heldout", ba->o.heldout, "Held-out exemplars (default 200)")
    ->check(CLI::Range(1, 100000));
  build->add_option("--size", ba->o.size, "Image side (default 64)")->check(CLI::Range(16, 512));
  build->add_option("--minutes", ba->o.minutes, "Training budget (default 5)")
    ->check(CLI::PositiveNumber);
  build
    ->add_option(
      "--iterations", ba->o.iterations, "Training iterations (default 0: the budget decides)")
    ->check(CLI::NonNegativeNumber);
  build->add_option("--outline", ba->o.outlineCount, "Outline designs (default 10000)")
    ->check(CLI::Range(3, 10000000));
  build->add_option("--width", ba->o.width, "Analyzer width (default 16)")
    ->check(CLI::Range(2, 256));
  build->add_option("--seed", ba->o.seed, "Seed (default 1)");
  build->add_option("--threads", ba->o.threads, "Threads (default 0: all cores)");
  build->add_flag("--quiet", ba->quiet, "Do not print progress");
  commands.push_back({ build, [ba] { return runBuild(*ba); } });

  auto pa = std::make_shared<ReplayArgs>();
  auto* replay = app.add_subcommand("replay",
    "Replay a history file (query -> picks -> edits -> TF; written by query/edit --history): "
    "prints each step's outline position and writes the design it ends on.");
  replay->add_option("--model", pa->model, "Model bundle directory (with outline.bin)")->required();
  replay->add_option("--volume", pa->volume, "The bundle's volume")->required();
  replay->add_option("--history", pa->history, "History file")->required();
  replay->add_option(
    "--view", pa->view, "View JSON of the outputs (default: the volume's default view)");
  replay->add_option("--out-tf", pa->outTF, "Write the final design's explicit TF");
  replay->add_option("--format", pa->format, "TF file format: paraview (default) or slicer")
    ->check(CLI::IsMember({ "paraview", "slicer" }));
  replay->add_option("--out-design", pa->outDesign, "Write the final design's render (PNG)");
  replay->add_option("--out-latent", pa->outLatent, "Write the final latent (JSON)");
  commands.push_back({ replay, [pa] { return runReplay(*pa); } });

  auto ra = std::make_shared<RecallArgs>();
  auto* recall = app.add_subcommand("recall",
    "How often a query finds the design it shows: held-out designs join the bundle's outline, "
    "then each is queried with its own image and with its image from another view; prints the "
    "fraction found among the k nearest.");
  recall->add_option("--model", ra->model, "Model bundle directory (with outline.bin)")->required();
  recall->add_option("--data", ra->data, "Held-out exemplars (ddg generate, same volume)")
    ->required();
  recall->add_option("--count", ra->count, "Held-out designs (default 200)")
    ->check(CLI::Range(1, 100000));
  recall->add_option("--k", ra->k, "Nearest designs that count as found (default 5)")
    ->check(CLI::Range(1, 1000));
  commands.push_back({ recall, [ra] { return runRecall(*ra); } });
#endif

  return [commands]() -> int
  {
    for (const auto& c : commands)
      if (*c.first)
        return c.second();
    return -1;
  };
}
