// DesignJson.h (Core-internal: included by .cxx files only): the JSON of feature regions,
// Gaussian primitives and exemplars shared by datasets (dataset.json) and model bundles. 2D regions
// and primitives add their gradient-magnitude fields; 1D ones are written exactly as before.
#pragma once

#include "Design/DesignSpace.h"
#include "Design/PictureLook.h"
#include "Render/View.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace ddg
{

inline nlohmann::json regionToJson(const FeatureRegion& r)
{
  nlohmann::json j = { { "lo", r.lo }, { "hi", r.hi }, { "peak", r.peak }, { "mass", r.mass } };
  if (r.twoD())
  {
    j["gradient_lo"] = r.gradientLo;
    j["gradient_hi"] = r.gradientHi;
    j["gradient_peak"] = r.gradientPeak;
  }
  return j;
}

inline FeatureRegion regionFromJson(const nlohmann::json& j)
{
  FeatureRegion r;
  r.lo = j.at("lo").get<double>();
  r.hi = j.at("hi").get<double>();
  r.peak = j.at("peak").get<double>();
  r.mass = j.value("mass", 0.0);
  r.gradientLo = j.value("gradient_lo", 0.0);
  r.gradientHi = j.value("gradient_hi", 0.0);
  r.gradientPeak = j.value("gradient_peak", 0.0);
  return r;
}

/// `compact`: numbers rounded to 6 significant digits (model bundles: a third of the size; the
/// designs they describe differ by < 1e-5 relative).
inline nlohmann::json primitiveToJson(const GaussianPrimitive& g, bool twoD, bool compact = false)
{
  auto v = [compact](double x)
  {
    if (!compact || x == 0 || !std::isfinite(x))
      return x;
    const double scale = std::pow(10.0, 5 - static_cast<int>(std::floor(std::log10(std::abs(x)))));
    return std::round(x * scale) / scale;
  };
  nlohmann::json j = { { "mean", v(g.mean[0]) }, { "stddev", v(g.stddev[0]) },
    { "rgb", { v(g.rgb[0]), v(g.rgb[1]), v(g.rgb[2]) } }, { "opacity", v(g.opacity) } };
  if (twoD)
  {
    j["gradient_mean"] = v(g.mean[1]);
    j["gradient_stddev"] = v(g.stddev[1]);
  }
  return j;
}

inline GaussianPrimitive primitiveFromJson(const nlohmann::json& j)
{
  GaussianPrimitive g;
  g.mean = { j.at("mean").get<double>(), j.value("gradient_mean", 0.0) };
  g.stddev = { j.at("stddev").get<double>(), j.value("gradient_stddev", 1.0) };
  const auto rgb = j.at("rgb").get<std::vector<double>>();
  g.rgb = { rgb.at(0), rgb.at(1), rgb.at(2) };
  g.opacity = j.at("opacity").get<double>();
  return g;
}

/// An exemplar as dataset.json (and an exemplar worker's answer) holds it.
inline nlohmann::json exemplarToJson(const Exemplar& e, bool twoD)
{
  nlohmann::json p = nlohmann::json::array();
  for (const auto& g : e.primitives)
    p.push_back(primitiveToJson(g, twoD));
  nlohmann::json j = { { "seed", e.seed }, { "active", e.active }, { "primitives", p },
    { "view_exp", nlohmann::json::parse(viewToJson(e.viewExp)) },
    { "view_view", nlohmann::json::parse(viewToJson(e.viewView)) },
    { "background", e.background } };
  if (e.picture)
    j["picture"] = nlohmann::json::parse(pictureLookToJson(*e.picture));
  return j;
}

inline Exemplar exemplarFromJson(const nlohmann::json& e, const std::string& where)
{
  Exemplar x;
  x.seed = e.at("seed").get<std::uint64_t>();
  x.active = e.at("active").get<std::vector<int>>();
  for (const auto& p : e.at("primitives"))
    x.primitives.push_back(primitiveFromJson(p));
  x.viewExp = parseView(e.at("view_exp").dump(), where);
  x.viewView = parseView(e.at("view_view").dump(), where);
  x.background = e.at("background").get<int>();
  if (e.contains("picture"))
    x.picture = parsePictureLook(e.at("picture").dump(), where);
  return x;
}

} // namespace ddg
