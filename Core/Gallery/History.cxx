// History.cxx: history files and their replay.
#include "Gallery/History.h"

#include "Reconstruct/Match.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Render/View.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace ddg
{

namespace
{
using json = nlohmann::json;

const char* const kActions[] = { "query", "pick", "latent", "blend", "edit", "axes", "match" };

void validateStep(const HistoryStep& s, size_t i, const std::string& origin)
{
  const std::string where = origin + ": step " + std::to_string(i + 1) + " (" + s.action + ")";
  if (std::find(std::begin(kActions), std::end(kActions), s.action) == std::end(kActions))
    throw Error(origin + ": step " + std::to_string(i + 1) + " has the unknown action '" +
      s.action + "' (query, pick, latent, blend, edit, axes or match)");
  if (s.action == "query" && s.image.empty())
    throw Error(where + " needs \"image\"");
  if (s.action == "pick" && s.row < 0)
    throw Error(where + " needs a \"row\" >= 0");
  if (s.action == "latent" && s.latent.empty())
    throw Error(where + " needs \"latent\"");
  const size_t anchors = s.rows.empty() ? s.latents.size() : s.rows.size();
  if (s.action == "blend" &&
    (anchors < 2 || anchors > 4 || (!s.rows.empty() && !s.latents.empty())))
    throw Error(where + " needs 2 to 4 \"rows\" or 2 to 4 \"latents\"");
  if (s.action == "edit")
  {
    if (s.viewJson.empty())
      throw Error(where + " needs the \"view\" it was made at");
    if (s.cluster < 0 && (s.pickX < 0 || s.pickY < 0))
      throw Error(where + " needs a \"cluster\" or a \"pick\" [x, y]");
  }
  if (s.action == "axes" && s.steps.empty())
    throw Error(where + " needs \"steps\"");
  if (s.action == "match")
  {
    if (s.viewJson.empty() || s.tfJson.empty())
      throw Error(where + " needs the \"view\" of the picture and the \"tf\" it gave");
    if (s.bins < 2 || s.iterations < 1)
      throw Error(where + " needs \"bins\" >= 2 and \"iterations\" >= 1");
  }
  const bool starts =
    s.action == "query" || s.action == "pick" || s.action == "latent" || s.action == "blend";
  if (i == 0 && !starts)
    throw Error(
      origin + ": a history starts with query, pick, latent or blend (not " + s.action + ")");
}
} // namespace

// --- steps as the front ends record them --------------------------------------------------

HistoryStep HistoryStep::query(const std::string& image)
{
  HistoryStep s;
  s.action = "query";
  s.image = image;
  return s;
}

HistoryStep HistoryStep::pick(int row)
{
  HistoryStep s;
  s.action = "pick";
  s.row = row;
  return s;
}

HistoryStep HistoryStep::latentDesign(const std::vector<float>& latent, const std::string& image)
{
  HistoryStep s;
  s.action = "latent";
  s.latent = latent;
  s.image = image;
  return s;
}

HistoryStep HistoryStep::blend(const std::vector<std::vector<float>>& latents, double u, double v)
{
  HistoryStep s;
  s.action = "blend";
  s.latents = latents;
  s.u = u;
  s.v = v;
  return s;
}

HistoryStep HistoryStep::edit(const std::string& viewJson, int cluster, int pickX, int pickY,
  int clusters, double hue, double saturation, double lightness, double visibility, bool white)
{
  HistoryStep s;
  s.action = "edit";
  s.viewJson = viewJson;
  s.cluster = cluster;
  s.pickX = pickX;
  s.pickY = pickY;
  s.clusters = clusters;
  s.hue = hue;
  s.saturation = saturation;
  s.lightness = lightness;
  s.visibility = visibility;
  s.white = white;
  return s;
}

HistoryStep HistoryStep::axes(const std::vector<double>& steps)
{
  HistoryStep s;
  s.action = "axes";
  s.steps = steps;
  return s;
}

HistoryStep HistoryStep::match(const std::string& image, const std::string& viewJson,
  bool cameraEstimated, const std::string& tfJson, bool twoD, int bins, int iterations)
{
  HistoryStep s;
  s.action = "match";
  s.image = image;
  s.viewJson = viewJson;
  s.cameraEstimated = cameraEstimated;
  s.tfJson = tfJson;
  s.twoD = twoD;
  s.bins = bins;
  s.iterations = iterations;
  return s;
}

void DesignHistory::checkMatchLast(const std::string& origin) const
{
  for (size_t i = 0; i + 1 < steps.size(); ++i)
    if (steps[i].action == "match")
      throw Error(origin + ": step " + std::to_string(i + 1) +
        " (match) is not the last: a match gives the TF and ends a history");
}

void DesignHistory::setAxes(const std::vector<double>& values)
{
  if (!steps.empty() && steps.back().action == "axes")
    steps.back() = HistoryStep::axes(values);
  else
    steps.push_back(HistoryStep::axes(values));
}

// --- JSON -----------------------------------------------------------------------------------

std::string DesignHistory::toJson() const
{
  json steps = json::array();
  for (const auto& s : this->steps)
  {
    json j = { { "action", s.action } };
    if (s.action == "query")
      j["image"] = s.image;
    else if (s.action == "pick")
      j["row"] = s.row;
    else if (s.action == "latent")
    {
      j["latent"] = s.latent;
      if (!s.image.empty())
        j["image"] = s.image;
    }
    else if (s.action == "blend")
    {
      if (s.latents.empty())
        j["rows"] = s.rows;
      else
        j["latents"] = s.latents;
      j.update({ { "u", s.u }, { "v", s.v } });
    }
    else if (s.action == "edit")
    {
      j["view"] = json::parse(s.viewJson);
      if (s.cluster >= 0)
        j["cluster"] = s.cluster;
      else
        j["pick"] = { s.pickX, s.pickY };
      j.update({ { "clusters", s.clusters }, { "hue", s.hue }, { "saturation", s.saturation },
        { "lightness", s.lightness }, { "visibility", s.visibility }, { "white", s.white } });
    }
    else if (s.action == "axes")
      j["steps"] = s.steps;
    else if (s.action == "match")
    {
      if (!s.image.empty())
        j["image"] = s.image;
      j["view"] = json::parse(s.viewJson);
      j.update({ { "camera", s.cameraEstimated ? "estimated" : "given" }, { "two_d", s.twoD },
        { "bins", s.bins }, { "iterations", s.iterations } });
      j["tf"] = json::parse(s.tfJson);
    }
    steps.push_back(j);
  }
  return json{ { "format", "ddg-history" }, { "version", 1 }, { "steps", steps } }.dump(2) + "\n";
}

DesignHistory DesignHistory::fromJson(const std::string& text, const std::string& origin)
{
  DesignHistory h;
  try
  {
    const auto j = json::parse(text);
    if (j.value("format", std::string()) != "ddg-history" || j.value("version", 0) != 1)
      throw Error(origin + " is not a version-1 ddg history (\"format\": \"ddg-history\")");
    for (const auto& e : j.at("steps"))
    {
      HistoryStep s;
      s.action = e.at("action").get<std::string>();
      s.image = e.value("image", std::string());
      s.row = e.value("row", -1);
      s.rows = e.value("rows", std::vector<int>());
      s.latent = e.value("latent", std::vector<float>());
      s.latents = e.value("latents", std::vector<std::vector<float>>());
      s.u = e.value("u", 0.0);
      s.v = e.value("v", 0.0);
      if (e.contains("view"))
        s.viewJson = e.at("view").dump();
      s.cluster = e.value("cluster", -1);
      if (e.contains("pick"))
      {
        const auto p = e.at("pick").get<std::vector<int>>();
        if (p.size() != 2)
          throw Error(origin + ": \"pick\" is [x, y]");
        s.pickX = p[0];
        s.pickY = p[1];
      }
      s.clusters = e.value("clusters", 4);
      s.hue = e.value("hue", 0.0);
      s.saturation = e.value("saturation", 1.0);
      s.lightness = e.value("lightness", 0.0);
      s.visibility = e.value("visibility", 1.0);
      s.white = e.value("white", false);
      s.steps = e.value("steps", std::vector<double>());
      s.cameraEstimated = e.value("camera", std::string("given")) == "estimated";
      s.twoD = e.value("two_d", false);
      s.bins = e.value("bins", 128);
      s.iterations = e.value("iterations", 500);
      if (e.contains("tf"))
        s.tfJson = e.at("tf").dump();
      h.steps.push_back(std::move(s));
    }
  }
  catch (const json::exception& e)
  {
    throw Error(origin + ": " + e.what());
  }
  if (h.steps.empty())
    throw Error(origin + " has no steps");
  for (size_t i = 0; i < h.steps.size(); ++i)
    validateStep(h.steps[i], i, origin);
  h.checkMatchLast(origin);
  return h;
}

DesignHistory DesignHistory::read(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw Error("cannot open the history " + path);
  std::stringstream text;
  text << in.rdbuf();
  return fromJson(text.str(), path);
}

void DesignHistory::write(const std::string& path) const
{
  for (size_t i = 0; i < steps.size(); ++i)
    validateStep(steps[i], i, path);
  checkMatchLast(path);
  writeFileAtomic(path, toJson(), "history");
}

std::vector<float> applyHistoryStep(
  const DesignGallery& gallery, const HistoryStep& s, const std::vector<float>& current)
{
  if (s.action == "query")
    return gallery.analyzeImage(readImage(s.image));
  if (s.action == "pick")
    return gallery.latent(s.row);
  const size_t size = static_cast<size_t>(gallery.outline().latents().dim);
  auto checked = [size](const std::vector<float>& z)
  {
    if (z.size() != size)
      throw Error("a history's latent has " + std::to_string(z.size()) +
        " values; this model's latents have " + std::to_string(size));
    return z;
  };
  if (s.action == "latent")
    return checked(s.latent);
  if (s.action == "blend")
  {
    std::vector<Latent> anchors = s.latents;
    for (const auto& z : anchors)
      checked(z);
    for (int r : s.rows)
      anchors.push_back(gallery.latent(r));
    return blendLatents(anchors, s.u, s.v);
  }
  if (current.empty())
    throw Error("a history's " + s.action + " step needs a design before it");
  if (s.action == "axes")
    return gallery.outline().moveAlongAxes(current, s.steps);
  if (s.action == "match")
    return current; // the design stays; the TF comes from replayMatch
  if (s.action == "edit")
    return editDesign(gallery, current, DesignEdit::fromStep(s)).latent;
  throw Error("unknown history action '" + s.action + "'");
}

DesignEdit DesignEdit::fromStep(const HistoryStep& s)
{
  DesignEdit e;
  e.view = parseView(s.viewJson, "history edit view");
  e.clusters = s.clusters;
  e.cluster = s.cluster;
  e.pickX = s.pickX;
  e.pickY = s.pickY;
  e.hue = s.hue;
  e.saturation = s.saturation;
  e.lightness = s.lightness;
  e.visibility = s.visibility;
  e.white = s.white;
  return e;
}

HistoryStep DesignEdit::toStep() const
{
  if (!mask.empty())
    throw Error("a history does not record brushed masks; edit a cluster or a picked pixel");
  return HistoryStep::edit(viewToJson(view), pickX >= 0 ? -1 : cluster, pickX, pickY, clusters, hue,
    saturation, lightness, visibility, white);
}

DesignEditResult editDesign(const DesignGallery& gallery, const std::vector<float>& latent,
  const DesignEdit& e, const FeatureLock* lock)
{
  DesignEditResult r;
  r.before = gallery.render(latent, e.view, lock);
  r.clusters = colorClusters(r.before, e.clusters);
  EditRegion region;
  if (!e.mask.empty())
  {
    region.mask = e.mask;
    if (region.mask.width != e.view.width || region.mask.height != e.view.height)
      region.mask = resizeImage(region.mask, e.view.width, e.view.height);
  }
  else if (e.pickX >= 0 && e.pickY >= 0)
  {
    region.cluster = r.clusters.at(e.pickX, e.pickY);
    if (region.cluster < 0)
      throw Error("the picked pixel shows no feature (it is background)");
  }
  else
    region.cluster = e.cluster;
  if (region.mask.empty() && region.cluster < 0)
    throw Error("an image edit needs what to edit: a cluster, a picked pixel or a mask");
  checkEditRegion(r.clusters, region, r.before); // also for an edit that changes nothing
  r.cluster = region.cluster;
  r.edited = r.before;
  if (e.hue != 0 || e.saturation != 1 || e.lightness != 0)
    r.edited = recolour(r.edited, r.clusters, region, e.hue, e.saturation, e.lightness);
  if (e.visibility != 1)
    r.edited = changeVisibility(r.edited, r.clusters, region, e.visibility);
  r.latent = gallery.analyzeEdit(
    r.edited, e.white ? std::array<double, 3>{ 1, 1, 1 } : std::array<double, 3>{ 0, 0, 0 });
  return r;
}

std::vector<float> replayHistory(const DesignGallery& gallery, const DesignHistory& history)
{
  std::vector<float> z;
  for (const auto& s : history.steps)
    z = applyHistoryStep(gallery, s, z);
  return z;
}

} // namespace ddg

namespace ddg
{

TransferFunctionFile replayMatch(const DesignGallery& gallery, const std::vector<float>& latent,
  const HistoryStep& step, bool* rematched, double* fitPSNR)
{
  if (step.action != "match")
    throw Error("replayMatch needs a match step, not " + step.action);
  if (rematched)
    *rematched = false;
  if (fitPSNR)
    *fitPSNR = 0;
  Image picture;
  try
  {
    if (!step.image.empty())
      picture = readImage(step.image);
  }
  catch (const Error&)
  {
    picture = Image();
  }
  if (picture.empty())
    return parseTransferFunctionFile(step.tfJson, "the history's match step");
  const View view = parseView(step.viewJson, "the history's match view");
  MatchOptions opt;
  opt.view = view;
  opt.reconstruction.twoD = step.twoD;
  opt.reconstruction.bins = step.bins;
  opt.reconstruction.iterations = step.iterations;
  const auto range = gallery.caster().dataRange();
  const TransferFunctionFile design = gallery.explicitTransferFunction(latent, view);
  if (!design.is2D && !step.twoD)
    opt.reconstruction.initial1D = bakeTable(design.tf1D, range[0], range[1], 1024);
  const DifferentiableRenderer renderer(gallery.caster().volume());
  const MatchResult m = matchPicture(renderer, picture, opt);
  if (rematched)
    *rematched = true;
  if (fitPSNR)
    *fitPSNR = m.fitPSNR;
  return resultTransferFunction(m.tf, "ddg match");
}

} // namespace ddg
