// TransferFunctionIO.cxx: ParaView preset and 2D TF JSON reading and writing.
#include "TransferFunction/TransferFunctionIO.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

namespace ddg
{
namespace
{
using nlohmann::json;

json parseJson(const std::string& text, const std::string& origin)
{
  try
  {
    return json::parse(text);
  }
  catch (const json::parse_error& e)
  {
    throw Error(origin + " is not valid JSON: " + e.what());
  }
}

std::vector<double> numbers(const json& j, const char* key, size_t group, const std::string& origin)
{
  const json& a = j.at(key);
  if (!a.is_array())
  {
    throw Error(origin + ": \"" + key + "\" must be a list of numbers");
  }
  std::vector<double> out;
  out.reserve(a.size());
  for (const auto& v : a)
  {
    if (!v.is_number())
    {
      throw Error(origin + ": \"" + key + "\" must hold only numbers");
    }
    out.push_back(v.get<double>());
  }
  if (group > 0 && out.size() % group != 0)
  {
    std::ostringstream msg;
    msg << origin << ": \"" << key << "\" has " << out.size() << " numbers, not a multiple of "
        << group;
    throw Error(msg.str());
  }
  return out;
}

std::array<double, 2> pair(const json& j, const char* key, const std::string& origin)
{
  if (!j.contains(key))
  {
    throw Error(origin + ": missing \"" + key + "\"");
  }
  auto v = numbers(j, key, 0, origin);
  if (v.size() != 2)
  {
    throw Error(origin + ": \"" + key + "\" must be [min, max]");
  }
  return { v[0], v[1] };
}

template <size_t N>
std::array<double, N> fixed(const json& j, const char* key, const std::string& origin)
{
  if (!j.contains(key))
  {
    throw Error(origin + ": missing \"" + key + "\"");
  }
  auto v = numbers(j, key, 0, origin);
  if (v.size() != N)
  {
    std::ostringstream msg;
    msg << origin << ": \"" << key << "\" must have " << N << " numbers";
    throw Error(msg.str());
  }
  std::array<double, N> out{};
  for (size_t i = 0; i < N; ++i)
    out[i] = v[i];
  return out;
}

} // namespace

TransferFunction1D parsePreset(const std::string& jsonText, const std::string& origin)
{
  json root = parseJson(jsonText, origin);
  const json* obj = &root;
  if (root.is_array())
  {
    if (root.empty())
    {
      throw Error(origin + ": the preset list is empty");
    }
    obj = &root[0];
  }
  if (!obj->is_object())
  {
    throw Error(
      origin + ": expected a ParaView preset (a list of objects with RGBPoints and Points)");
  }
  if (obj->contains("Format") && (*obj)["Format"] == "ddg-transfer-function-2d")
  {
    throw Error(origin + ": this is a 2D transfer function, a 1D preset was expected");
  }
  if (!obj->contains("RGBPoints"))
  {
    throw Error(origin + ": the preset has no \"RGBPoints\"");
  }
  if (!obj->contains("Points"))
  {
    throw Error(
      origin + ": the preset has no opacity \"Points\" (a volume needs an opacity function)");
  }
  TransferFunction1D tf;
  try
  {
    tf.name = obj->value("Name", std::string("unnamed"));
    tf.colorSpace = parseColorSpace(obj->value("ColorSpace", std::string("RGB")));
    tf.hsvWrap = obj->value("HSVWrap", 0) != 0;
  }
  catch (const json::exception& e)
  {
    throw Error(origin + ": " + e.what());
  }
  const auto rgb = numbers(*obj, "RGBPoints", 4, origin);
  for (size_t i = 0; i < rgb.size(); i += 4)
  {
    tf.color.push_back({ rgb[i], rgb[i + 1], rgb[i + 2], rgb[i + 3], 0.5, 0.0 });
  }
  const auto pts = numbers(*obj, "Points", 4, origin);
  for (size_t i = 0; i < pts.size(); i += 4)
  {
    tf.opacity.push_back({ pts[i], pts[i + 1], pts[i + 2], pts[i + 3] });
  }
  try
  {
    tf.validate();
  }
  catch (const Error& e)
  {
    throw Error(origin + ": " + e.what());
  }
  return tf;
}

TransferFunction1D readPreset(const std::string& path)
{
  return parsePreset(readTextFile(path, "transfer function"), "transfer function '" + path + "'");
}

std::string presetToJson(const TransferFunction1D& tf)
{
  json obj;
  obj["Name"] = tf.name.empty() ? "ddg" : tf.name;
  obj["Creator"] = "ddg (Differentiable Design Gallery)";
  obj["ColorSpace"] = colorSpaceName(tf.colorSpace);
  if (tf.hsvWrap)
  {
    obj["HSVWrap"] = 1;
  }
  json rgb = json::array();
  for (const auto& n : tf.color)
  {
    rgb.insert(rgb.end(), { n.x, n.r, n.g, n.b });
  }
  json pts = json::array();
  for (const auto& n : tf.opacity)
  {
    pts.insert(pts.end(), { n.x, n.alpha, n.midpoint, n.sharpness });
  }
  obj["RGBPoints"] = rgb;
  obj["Points"] = pts;
  return json::array({ obj }).dump(2) + "\n";
}

void writePreset(const TransferFunction1D& tf, const std::string& path)
{
  writeFileAtomic(path, presetToJson(tf), "transfer function");
}

TransferFunction2D parseTransferFunction2D(const std::string& jsonText, const std::string& origin)
{
  json j = parseJson(jsonText, origin);
  if (!j.is_object() || j.value("Format", std::string()) != "ddg-transfer-function-2d")
  {
    throw Error(
      origin + ": not a 2D transfer function (\"Format\": \"ddg-transfer-function-2d\" missing)");
  }
  TransferFunction2D tf;
  try
  {
    if (j.value("Version", 1) != 1)
    {
      throw Error(origin + ": unsupported Version (this build reads version 1)");
    }
    tf.name = j.value("Name", std::string("unnamed"));
    tf.table.valueRange = pair(j, "ValueRange", origin);
    tf.table.gradientRange = pair(j, "GradientRange", origin);
    if (j.contains("Size"))
    {
      auto s = fixed<2>(j, "Size", origin);
      tf.table.width = static_cast<int>(s[0]);
      tf.table.height = static_cast<int>(s[1]);
      if (s[0] != tf.table.width || s[1] != tf.table.height || tf.table.width < 2 ||
        tf.table.height < 2 || tf.table.width > 4096 || tf.table.height > 4096)
      {
        throw Error(origin + ": \"Size\" must be two integers in [2, 4096]");
      }
    }
    if (j.contains("Primitives"))
    {
      if (!j["Primitives"].is_array())
      {
        throw Error(origin + ": \"Primitives\" must be a list");
      }
      for (const auto& p : j["Primitives"])
      {
        GaussianPrimitive g;
        const auto m = fixed<2>(p, "mean", origin);
        const auto s = fixed<2>(p, "stddev", origin);
        const auto c = fixed<3>(p, "rgb", origin);
        g.mean = { m[0], m[1] };
        g.stddev = { s[0], s[1] };
        g.rgb = { c[0], c[1], c[2] };
        if (!p.contains("opacity") || !p["opacity"].is_number())
        {
          throw Error(origin + ": every primitive needs a numeric \"opacity\"");
        }
        g.opacity = p["opacity"].get<double>();
        tf.primitives.push_back(g);
      }
      validatePrimitives(tf.primitives, true);
    }
    if (j.contains("RGBA"))
    {
      if (tf.table.width < 2)
      {
        throw Error(origin + ": \"RGBA\" needs \"Size\"");
      }
      const auto v = numbers(j, "RGBA", 4, origin);
      tf.table.rgba.assign(v.begin(), v.end());
    }
    if (tf.primitives.empty() && tf.table.rgba.empty())
    {
      throw Error(origin + ": needs \"Primitives\" or \"RGBA\"");
    }
    if (!tf.table.rgba.empty())
    {
      tf.table.validate();
    }
    else if (!(tf.table.valueRange[0] < tf.table.valueRange[1]) ||
      !(tf.table.gradientRange[0] < tf.table.gradientRange[1]))
    {
      throw Error(origin + ": ValueRange and GradientRange must be increasing");
    }
  }
  catch (const json::exception& e)
  {
    throw Error(origin + ": " + e.what());
  }
  catch (const Error& e)
  {
    const std::string what = e.what();
    throw Error(what.rfind(origin, 0) == 0 ? what : origin + ": " + what);
  }
  return tf;
}

TransferFunction2D readTransferFunction2D(const std::string& path)
{
  return parseTransferFunction2D(
    readTextFile(path, "2D transfer function"), "2D transfer function '" + path + "'");
}

std::string transferFunction2DToJson(const TransferFunction2D& tf)
{
  json j;
  j["Format"] = "ddg-transfer-function-2d";
  j["Version"] = 1;
  j["Name"] = tf.name.empty() ? "ddg" : tf.name;
  j["ValueRange"] = { tf.table.valueRange[0], tf.table.valueRange[1] };
  j["GradientRange"] = { tf.table.gradientRange[0], tf.table.gradientRange[1] };
  if (tf.table.width > 1)
  {
    j["Size"] = { tf.table.width, tf.table.height };
  }
  if (!tf.primitives.empty())
  {
    json prims = json::array();
    for (const auto& p : tf.primitives)
    {
      prims.push_back(
        { { "mean", { p.mean[0], p.mean[1] } }, { "stddev", { p.stddev[0], p.stddev[1] } },
          { "rgb", { p.rgb[0], p.rgb[1], p.rgb[2] } }, { "opacity", p.opacity } });
    }
    j["Primitives"] = prims;
  }
  if (!tf.table.rgba.empty())
  {
    j["RGBA"] = tf.table.rgba;
  }
  return j.dump(1) + "\n";
}

void writeTransferFunction2D(const TransferFunction2D& tf, const std::string& path)
{
  writeFileAtomic(path, transferFunction2DToJson(tf), "2D transfer function");
}

TransferFunctionFile parseTransferFunctionFile(
  const std::string& jsonText, const std::string& origin)
{
  TransferFunctionFile f;
  // Cheap sniff; both parsers validate fully.
  if (jsonText.find("ddg-transfer-function-2d") != std::string::npos)
  {
    f.is2D = true;
    f.tf2D = parseTransferFunction2D(jsonText, origin);
  }
  else if (jsonText.find("\"Boxes\"") != std::string::npos)
  {
    f.isParaView2D = true;
    f.paraview2D = ParaViewTransferFunction2D::fromJson(jsonText, origin);
  }
  else
  {
    f.tf1D = parsePreset(jsonText, origin);
  }
  return f;
}

TransferFunctionFile readTransferFunctionFile(const std::string& path)
{
  return parseTransferFunctionFile(
    readTextFile(path, "transfer function"), "transfer function '" + path + "'");
}

} // namespace ddg
