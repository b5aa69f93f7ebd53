// DesignJson.h (Core-internal: included by .cxx files only): the JSON of feature regions and
// Gaussian primitives shared by datasets (dataset.json) and model bundles. 2D regions and
// primitives add their gradient-magnitude fields; 1D ones are written exactly as before.
#pragma once

#include "Design/DesignSpace.h"

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

} // namespace ddg
