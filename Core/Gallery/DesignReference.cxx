// DesignReference.cxx: parsing and resolving design references; latent files.
#include "Gallery/DesignReference.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Image/Image.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace ddg
{

DesignReference DesignReference::parse(const std::string& reference)
{
  const auto colon = reference.find(':');
  const std::string kind = reference.substr(0, colon),
                    arg = colon == std::string::npos ? "" : reference.substr(colon + 1);
  if (colon == std::string::npos || arg.empty())
    throw Error("design '" + reference + "': use row:N, image:PATH, latent:PATH or history:PATH");
  DesignReference r;
  r.text = reference;
  r.path = arg;
  if (kind == "row")
  {
    r.kind = Kind::Row;
    r.path.clear();
    try
    {
      size_t used = 0;
      r.row = std::stoi(arg, &used);
      if (used != arg.size())
        throw std::invalid_argument(arg);
    }
    catch (const std::logic_error&)
    {
      throw Error("design '" + reference + "': row must be an integer");
    }
  }
  else if (kind == "image")
    r.kind = Kind::Image;
  else if (kind == "latent")
    r.kind = Kind::Latent;
  else if (kind == "history")
    r.kind = Kind::History;
  else
    throw Error(
      "design '" + reference + "': unknown kind '" + kind + "' (row, image, latent or history)");
  return r;
}

std::vector<float> DesignReference::resolve(const DesignGallery& gallery) const
{
  switch (kind)
  {
    case Kind::Row:
      return gallery.latent(row);
    case Kind::Image:
      return gallery.analyzeImage(readImage(path));
    case Kind::Latent:
    {
      std::vector<float> z = readLatentFile(path);
      const int dim = gallery.outline().latents().dim;
      if (static_cast<int>(z.size()) != dim)
        throw Error(path + ": a latent of " + std::to_string(z.size()) +
          " values, the model's have " + std::to_string(dim) + ": it comes from another model");
      return z;
    }
    case Kind::History:
      return replayHistory(gallery, DesignHistory::read(path));
  }
  throw Error("design '" + text + "': unknown kind");
}

DesignHistory DesignReference::history() const
{
  DesignHistory h;
  switch (kind)
  {
    case Kind::Row:
      h.steps.push_back(HistoryStep::pick(row));
      break;
    case Kind::Image:
      h.steps.push_back(HistoryStep::query(path));
      break;
    case Kind::Latent:
      h.steps.push_back(HistoryStep::latentDesign(readLatentFile(path)));
      break;
    case Kind::History:
      h = DesignHistory::read(path);
      break;
  }
  return h;
}

std::vector<float> readLatentFile(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw Error("cannot open the latent file " + path);
  std::stringstream text;
  text << in.rdbuf();
  try
  {
    return nlohmann::json::parse(text.str()).at("latent").get<std::vector<float>>();
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error(path + ": not a latent file (" + e.what() + ")");
  }
}

void writeLatentFile(const std::vector<float>& latent, const std::string& path)
{
  writeFileAtomic(path, nlohmann::json{ { "latent", latent } }.dump() + "\n", "latent");
}

} // namespace ddg
