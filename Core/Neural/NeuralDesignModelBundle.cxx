// NeuralDesignModelBundle.cxx: model bundles on disk — saveBundle writes model.pt (weights),
// latents.bin, exemplars.json and bundle.json (last); loadBundle reads and checks them.
#include "Neural/NeuralDesignModel.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Design/DesignJson.h"
#include "Gallery/Outline.h"
#include "Gallery/QueryKey.h"
#include "Neural/NeuralDesignModelInternals.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace ddg
{
namespace
{
using namespace neural;
namespace fs = std::filesystem;

// Why a bundle does not fit this volume, in words (no hashes).
std::string otherVolumeMessage(
  const std::string& dir, const std::string& theirs, const std::string& ours)
{
  const std::string a = describeFingerprint(theirs), b = describeFingerprint(ours);
  return "model bundle '" + dir + "' was trained on another volume (" +
    (a == b ? "one of the same size and range with other values" : a) + "), not this one (" + b +
    "): build a design space for this volume, or load the model made for it";
}
} // namespace

// --- saving ------------------------------------------------------------------------------

void NeuralDesignModel::saveBundle(const std::string& dir, const ExemplarDataset& training,
  const std::string& metricsJson, const std::function<bool(double)>& progress) const
{
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw Error("cannot create bundle directory '" + dir + "': " + ec.message());
  // bundle.json is written last and removed first: a failed save never leaves an index that
  // describes files of another save
  fs::remove(fs::path(dir) / "bundle.json", ec);
  // a query key fitted to other weights (Gallery/QueryKey.h) no longer holds
  fs::remove(fs::path(dir) / kQueryKeyFileName, ec);
  // weights
  {
    torch::serialize::OutputArchive ar, a, r;
    In->A->save(a);
    In->generator().save(r);
    ar.write("analyzer", a);
    ar.write(In->decoder() ? "decoder" : "renderer", r);
    writeFileAtomic((fs::path(dir) / "model.pt").string(), serialized(ar), "bundle weights");
  }
  // latents of the training exemplars (half floats) and their TF parameters (for the gallery)
  {
    LatentSet set;
    set.dim = In->Config.latent;
    set.seed = training.exemplars().empty() ? 0 : training.exemplars()[0].seed;
    const int chunk = 128; // a progress call per chunk (cancel within ~0.5 s)
    for (int first = 0; first < training.count(); first += chunk)
    {
      std::vector<Image> images;
      for (int i = first; i < std::min(training.count(), first + chunk); ++i)
      {
        images.push_back(training.images(i).rgbExp);
        set.indices.push_back(static_cast<std::uint64_t>(i));
      }
      const auto z = analyzeBatch(images);
      set.values.insert(set.values.end(), z.begin(), z.end());
      if (progress &&
        !progress(
          static_cast<double>(std::min(training.count(), first + chunk)) / training.count()))
        throw Cancelled();
    }
    writeLatentSet(set, (fs::path(dir) / "latents.bin").string());
  }
  nlohmann::json ex = nlohmann::json::array();
  for (int i = 0; i < training.count(); ++i)
  {
    nlohmann::json p = nlohmann::json::array();
    for (const auto& g : training.exemplars()[static_cast<size_t>(i)].primitives)
      p.push_back(primitiveToJson(g, training.spec().dimensions == 2, true));
    ex.push_back(p);
  }
  writeFileAtomic(
    (fs::path(dir) / "exemplars.json").string(), ex.dump() + "\n", "bundle exemplars");
  nlohmann::json j;
  j["format"] = "ddg-model-bundle";
  j["version"] = 2; // 2: latents.bin is a half-float latent set (Gallery/Outline.h)
  j["architecture"] = { { "kind", In->Config.kind }, { "regions", In->Config.regions },
    { "image_size", In->Config.imageSize }, { "width", In->Config.width },
    { "latent", In->Config.latent }, { "dropout", In->Config.dropout },
    { "dimensions", In->Config.dimensions } };
  j["parameters"] = parameterCount();
  j["volume"] = training.fingerprint();
  j["spec"] = nlohmann::json::parse(designSpaceSpecToJson(training.spec()));
  j["regions"] = nlohmann::json::array();
  for (const auto& r : training.regions())
    j["regions"].push_back(regionToJson(r));
  j["training_exemplars"] = training.count();
  j["metrics"] =
    metricsJson.empty() ? nlohmann::json::object() : nlohmann::json::parse(metricsJson);
  writeFileAtomic((fs::path(dir) / "bundle.json").string(), j.dump(2) + "\n", "bundle index");
}

// --- loading -----------------------------------------------------------------------------

NeuralDesignModel NeuralDesignModel::loadBundle(
  const std::string& dir, const std::string& expectedFingerprint)
{
  const std::string indexPath = (fs::path(dir) / "bundle.json").string();
  nlohmann::json j;
  try
  {
    j = nlohmann::json::parse(readTextFile(indexPath, "model bundle"));
  }
  catch (const nlohmann::json::parse_error& e)
  {
    throw Error("model bundle '" + indexPath + "' is corrupt: " + e.what());
  }
  NetworkConfig c;
  try
  {
    if (j.value("format", std::string()) != "ddg-model-bundle" || j.value("version", 0) != 2)
      throw Error("'" + indexPath + "' is not a version-2 ddg model bundle");
    const auto& a = j.at("architecture");
    c.kind = a.value("kind", std::string());
    if (c.kind != "unet" && c.kind != "decoder")
      throw Error("model bundle '" + dir + "' has an unknown architecture '" + c.kind + "'");
    c.regions = a.value("regions", 0);
    c.dimensions = a.value("dimensions", 1);
    c.imageSize = a.at("image_size").get<int>();
    c.width = a.at("width").get<int>();
    c.latent = a.at("latent").get<int>();
    c.dropout = a.at("dropout").get<double>();
    if (!expectedFingerprint.empty() && j.at("volume").get<std::string>() != expectedFingerprint)
      throw Error(otherVolumeMessage(dir, j.at("volume").get<std::string>(), expectedFingerprint));
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error("model bundle '" + indexPath + "' is corrupt: " + e.what());
  }
  NeuralDesignModel m(c);
  try
  {
    m.In->Fingerprint = j.at("volume").get<std::string>();
    m.In->Layout.spec = parseDesignSpaceSpec(j.at("spec").dump(), indexPath);
    for (const auto& r : j.at("regions"))
      m.In->Layout.regions.push_back(regionFromJson(r));
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error("model bundle '" + indexPath + "' is corrupt: " + e.what());
  }
  if (c.kind == "decoder" && static_cast<int>(m.In->Layout.regions.size()) != c.regions)
    throw Error("model bundle '" + indexPath + "' is inconsistent: " + std::to_string(c.regions) +
      " regions in the architecture, " + std::to_string(m.In->Layout.regions.size()) + " listed");
  // Module::load replaces tensors whatever their shape: compare them with the architecture's.
  const auto expectA = shapes(*m.In->A), expectR = shapes(m.In->generator());
  const std::string broken = "model bundle '" + dir +
    "': model.pt is missing, truncated or does not match the architecture in bundle.json";
  try
  {
    torch::serialize::InputArchive ar, a, r;
    ar.load_from((fs::path(dir) / "model.pt").string());
    ar.read("analyzer", a);
    ar.read(c.kind == "decoder" ? "decoder" : "renderer", r);
    m.In->A->load(a);
    m.In->generator().load(r);
  }
  catch (const c10::Error&)
  {
    throw Error(broken);
  }
  if (shapes(*m.In->A) != expectA || shapes(m.In->generator()) != expectR)
  {
    throw Error(broken);
  }
  // the training designs: latents.bin (a half-float latent set) and exemplars.json
  auto& d = m.In->Designs;
  d.latent = c.latent;
  const std::string latentsPath = (fs::path(dir) / "latents.bin").string();
  const std::string designsPath = (fs::path(dir) / "exemplars.json").string();
  try
  {
    const auto count = j.at("training_exemplars").get<std::int64_t>();
    for (const auto& tf : nlohmann::json::parse(readTextFile(designsPath, "model bundle designs")))
    {
      std::vector<GaussianPrimitive> prims;
      for (const auto& p : tf)
        prims.push_back(primitiveFromJson(p));
      validatePrimitives(prims, c.dimensions == 2);
      d.tfs.push_back(std::move(prims));
    }
    LatentSet set;
    try
    {
      set = readLatentSet(latentsPath);
    }
    catch (const Error& e)
    {
      throw Error("model bundle '" + dir + "': " + e.what());
    }
    if (static_cast<std::int64_t>(d.tfs.size()) != count || set.count() != count ||
      set.dim != c.latent)
      throw Error("model bundle '" + dir + "': latents.bin or exemplars.json is truncated (" +
        std::to_string(count) + " training exemplars of latent " + std::to_string(c.latent) +
        " expected)");
    d.latents = std::move(set.values);
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error("model bundle '" + designsPath + "' is corrupt: " + e.what());
  }
  return m;
}

} // namespace ddg
