// View.cxx: view JSON, validation, default camera and ray generation (vtkCamera conventions).
#include "Render/View.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Volume/Volume.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

namespace ddg
{
namespace
{
using nlohmann::json;

Eigen::Vector3d vec3(const json& j, const char* key, const std::string& origin)
{
  if (!j.contains(key))
  {
    throw Error(origin + ": camera needs \"" + key + "\"");
  }
  const json& a = j[key];
  if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
  {
    throw Error(origin + ": camera \"" + key + "\" must be three numbers");
  }
  return { a[0].get<double>(), a[1].get<double>(), a[2].get<double>() };
}

// An optional number (a JSON number) or flag (true/false, or a number: 0 is false) of an object.
double numberOr(const json& j, const char* key, double otherwise, const std::string& what)
{
  if (!j.contains(key) || j[key].is_null())
    return otherwise;
  if (!j[key].is_number())
    throw Error(what + " \"" + key + "\" must be a number");
  return j[key].get<double>();
}
bool flagOr(const json& j, const char* key, bool otherwise, const std::string& what)
{
  if (!j.contains(key) || j[key].is_null())
    return otherwise;
  if (!j[key].is_boolean() && !j[key].is_number())
    throw Error(what + " \"" + key + "\" must be true or false");
  return j[key].is_boolean() ? j[key].get<bool>() : j[key].get<double>() != 0;
}

// "lighting": every key optional (ParaView's default), no other key (a typo would silently
// render unlit or with the default coefficients).
Lighting lightingOf(const json& l, const std::string& origin)
{
  if (!l.is_object())
  {
    throw Error(origin + ": \"lighting\" must be an object");
  }
  Lighting out;
  for (const auto& [key, value] : l.items())
  {
    if (key == "shade")
    {
      if (!value.is_boolean() && !value.is_number_integer())
        throw Error(origin + ": lighting \"shade\" must be true or false");
      out.shade = value.is_boolean() ? value.get<bool>() : value.get<int>() != 0;
      continue;
    }
    double* target = key == "ambient" ? &out.ambient
      : key == "diffuse"              ? &out.diffuse
      : key == "specular"             ? &out.specular
      : key == "specular_power"       ? &out.specularPower
                                      : nullptr;
    if (!target)
    {
      throw Error(origin + ": unknown lighting key \"" + key +
        "\" (known: shade, ambient, diffuse, specular, specular_power)");
    }
    if (!value.is_number())
    {
      throw Error(origin + ": lighting \"" + key + "\" must be a number");
    }
    *target = value.get<double>();
  }
  return out;
}

bool finite(const Eigen::Vector3d& v)
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

/// `text` parsed as JSON; ddg::Error "<origin> is not valid JSON: ..." otherwise.
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
} // namespace

void View::validate() const
{
  const Camera& c = camera;
  if (!finite(c.position) || !finite(c.focalPoint) || !finite(c.viewUp))
  {
    throw Error("degenerate camera: position, focal_point and view_up must be finite");
  }
  const Eigen::Vector3d dir = c.focalPoint - c.position;
  if (dir.norm() <= 1e-12 * (1.0 + c.position.norm()))
  {
    throw Error("degenerate camera: position and focal_point coincide");
  }
  if (c.viewUp.norm() == 0.0 || dir.normalized().cross(c.viewUp.normalized()).norm() < 1e-6)
  {
    throw Error("degenerate camera: view_up is zero or parallel to the viewing direction");
  }
  if (!c.parallelProjection && !(c.viewAngle > 0.0 && c.viewAngle < 180.0))
  {
    throw Error("degenerate camera: view_angle must lie in (0, 180) degrees");
  }
  if (c.parallelProjection && !(c.parallelScale > 0.0 && std::isfinite(c.parallelScale)))
  {
    throw Error("degenerate camera: parallel_scale must be positive");
  }
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide ||
    static_cast<long long>(width) * height > kMaxImagePixels)
  {
    std::ostringstream msg;
    msg << "image size " << width << " x " << height << " is out of range (each side 1.."
        << kMaxImageSide << ", at most " << kMaxImagePixels << " pixels)";
    throw Error(msg.str());
  }
  for (const auto* colour : { &background, background2 ? &*background2 : &background })
  {
    for (double b : *colour)
    {
      if (!std::isfinite(b) || b < 0 || b > 1)
      {
        throw Error("background colour components must lie in [0, 1]");
      }
    }
  }
  if (opacityUnitDistance && !(*opacityUnitDistance > 0 && std::isfinite(*opacityUnitDistance)))
  {
    throw Error("opacity_unit_distance must be positive");
  }
  lighting.validate();
}

void Lighting::validate() const
{
  for (auto [name, value, top] : { std::tuple{ "ambient", ambient, 1.0 },
         std::tuple{ "diffuse", diffuse, 1.0 }, std::tuple{ "specular", specular, 1.0 },
         std::tuple{ "specular_power", specularPower, 100.0 } })
  {
    if (!(value >= 0.0 && value <= top))
    {
      std::ostringstream msg;
      msg << "lighting \"" << name << "\" must lie in [0, " << top << "] as in ParaView, got "
          << value;
      throw Error(msg.str());
    }
  }
}

Lighting parseLighting(const std::string& jsonText, const std::string& origin)
{
  json j = parseJson(jsonText, origin);
  const Lighting l = lightingOf(j, origin);
  try
  {
    l.validate();
  }
  catch (const Error& e)
  {
    throw Error(origin + ": " + e.what());
  }
  return l;
}

std::string lightingToJson(const Lighting& l)
{
  return json{
    { "shade", l.shade }, { "ambient", l.ambient }, { "diffuse", l.diffuse },
    { "specular", l.specular }, { "specular_power", l.specularPower }
  }.dump();
}

Lighting viewLighting(const std::string& viewJsonText, const std::string& origin)
{
  json j = parseJson(viewJsonText, origin);
  if (!j.is_object())
    throw Error(origin + ": not a JSON object");
  if (!j.contains("lighting"))
    return Lighting();
  return parseLighting(j["lighting"].dump(), origin + "'s lighting");
}

View parseView(const std::string& jsonText, const std::string& origin)
{
  json j = parseJson(jsonText, origin);
  if (!j.is_object() || !j.contains("camera") || !j["camera"].is_object())
  {
    throw Error(origin + ": needs a \"camera\" object");
  }
  View v;
  try
  {
    const json& c = j["camera"];
    v.camera.position = vec3(c, "position", origin);
    v.camera.focalPoint = vec3(c, "focal_point", origin);
    v.camera.viewUp = vec3(c, "view_up", origin);
    v.camera.viewAngle = numberOr(c, "view_angle", 30.0, origin + ": camera");
    v.camera.parallelProjection = flagOr(c, "parallel_projection", false, origin + ": camera");
    v.camera.parallelScale = numberOr(c, "parallel_scale", 1.0, origin + ": camera");
    if (j.contains("size"))
    {
      const json& s = j["size"];
      if (!s.is_array() || s.size() != 2 || !s[0].is_number() || !s[1].is_number())
      {
        throw Error(origin + ": \"size\" must be [width, height]");
      }
      const double w = s[0].get<double>(), h = s[1].get<double>();
      if (w != std::floor(w) || h != std::floor(h) || w < 0 || h < 0 || w > 1e9 || h > 1e9)
      {
        throw Error(origin + ": \"size\" must be two non-negative integers");
      }
      v.width = static_cast<int>(w);
      v.height = static_cast<int>(h);
    }
    if (j.contains("background"))
    {
      const auto b = vec3(j, "background", origin);
      v.background = { b[0], b[1], b[2] };
    }
    if (j.contains("background2") && !j["background2"].is_null())
    {
      const auto b = vec3(j, "background2", origin);
      v.background2 = std::array<double, 3>{ b[0], b[1], b[2] };
    }
    if (j.contains("opacity_unit_distance") && !j["opacity_unit_distance"].is_null())
    {
      v.opacityUnitDistance = numberOr(j, "opacity_unit_distance", 0.0, origin + ":");
    }
    if (j.contains("lighting") && !j["lighting"].is_null())
    {
      v.lighting = lightingOf(j["lighting"], origin);
    }
  }
  catch (const json::exception& e)
  {
    throw Error(origin + ": " + e.what());
  }
  try
  {
    v.validate();
  }
  catch (const Error& e)
  {
    throw Error(origin + ": " + e.what());
  }
  return v;
}

View readView(const std::string& path)
{
  return parseView(readTextFile(path, "view"), "view '" + path + "'");
}

std::string viewToJson(const View& v)
{
  json c;
  const auto& cam = v.camera;
  c["position"] = { cam.position[0], cam.position[1], cam.position[2] };
  c["focal_point"] = { cam.focalPoint[0], cam.focalPoint[1], cam.focalPoint[2] };
  c["view_up"] = { cam.viewUp[0], cam.viewUp[1], cam.viewUp[2] };
  c["view_angle"] = cam.viewAngle;
  c["parallel_projection"] = cam.parallelProjection;
  c["parallel_scale"] = cam.parallelScale;
  json j;
  j["camera"] = c;
  j["size"] = { v.width, v.height };
  j["background"] = { v.background[0], v.background[1], v.background[2] };
  if (v.background2)
  {
    j["background2"] = { (*v.background2)[0], (*v.background2)[1], (*v.background2)[2] };
  }
  if (v.opacityUnitDistance)
  {
    j["opacity_unit_distance"] = *v.opacityUnitDistance;
  }
  if (v.lighting != Lighting{})
  {
    j["lighting"] = json::parse(lightingToJson(v.lighting));
  }
  return j.dump(2) + "\n";
}

void writeView(const View& view, const std::string& path)
{
  writeFileAtomic(path, viewToJson(view), "view");
}

std::array<double, 3> View::backgroundAt(int row) const
{
  if (!background2)
  {
    return background;
  }
  // vtkViewport's gradient: Background at the bottom edge, Background2 at the top, interpolated
  // at pixel centres
  const double t = height > 0 ? (static_cast<double>(row) + 0.5) / height : 0.5; // 0 at the top
  std::array<double, 3> c{};
  for (int k = 0; k < 3; ++k)
  {
    c[k] = (*background2)[k] * (1 - t) + background[k] * t;
  }
  return c;
}

View defaultView(const Volume& volume, int width, int height)
{
  return defaultView(volume.bounds(), width, height);
}

double defaultSampleDistance(const std::array<double, 3>& s, const std::array<int, 3>& d)
{
  double dist = (s[0] + s[1] + s[2]) / 6.0;
  const double n = std::pow(static_cast<double>(d[0] - 1) * (d[1] - 1) * (d[2] - 1), 0.333);
  if (n < 100.0)
  {
    dist *= 0.01 + 0.99 * n / 100.0;
  }
  return dist;
}

View defaultView(const std::array<double, 6>& b, int width, int height)
{
  View v;
  v.width = width;
  v.height = height;
  const Eigen::Vector3d center(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]));
  const Eigen::Vector3d extent(b[1] - b[0], b[3] - b[2], b[5] - b[4]);
  double radius = 0.5 * extent.norm();
  if (radius == 0.0)
  {
    radius = 0.5;
  }
  const double distance = radius / std::sin(v.camera.viewAngle * M_PI / 360.0);
  v.camera.focalPoint = center;
  v.camera.position = center + Eigen::Vector3d(0, 0, distance);
  v.camera.viewUp = { 0, 1, 0 };
  v.camera.parallelScale = radius;
  return v;
}

View resetCameraView(const std::array<double, 6>& bounds, int width, int height)
{
  View v = defaultView(bounds, width, height);
  if (width >= height)
    return v;
  const double aspect = static_cast<double>(width) / height;
  const double radius = v.camera.parallelScale;
  const double angle = 2.0 * std::atan(std::tan(v.camera.viewAngle * M_PI / 360.0) * aspect);
  v.camera.position = v.camera.focalPoint + Eigen::Vector3d(0, 0, radius / std::sin(0.5 * angle));
  v.camera.parallelScale = radius / aspect;
  return v;
}

Camera cameraForShape(const View& view, int width, int height)
{
  Camera c = view.camera;
  if (width < 1 || height < 1 || view.width < 1 || view.height < 1)
    return c;
  // the widening: the view's aspect over the target's (> 1: the target is narrower)
  const double widen =
    (static_cast<double>(view.width) / view.height) / (static_cast<double>(width) / height);
  if (widen <= 1.0)
    return c;
  c.parallelScale *= widen;
  const double half = std::atan(std::tan(c.viewAngle * M_PI / 360.0) * widen);
  c.viewAngle = std::min(179.0, 360.0 * half / M_PI);
  return c;
}

RayGenerator::RayGenerator(const View& view)
  : V(view)
{
  view.validate();
  const Camera& c = view.camera;
  Forward = (c.focalPoint - c.position).normalized();
  // vtkCamera / vtkPerspectiveTransform::SetupCamera: side = dir x up, up' = side x dir.
  Right = Forward.cross(c.viewUp).normalized();
  Up = Right.cross(Forward);
  Aspect = static_cast<double>(view.width) / view.height;
  HalfHeight = c.parallelProjection ? c.parallelScale : std::tan(c.viewAngle * M_PI / 360.0);
}

void RayGenerator::ray(int x, int y, Eigen::Vector3d& origin, Eigen::Vector3d& direction) const
{
  // Normalised device coordinates of the pixel centre; rows counted from the bottom.
  const double ndcX = 2.0 * (x + 0.5) / V.width - 1.0;
  const double ndcY = 2.0 * ((V.height - 1 - y) + 0.5) / V.height - 1.0;
  const double sx = ndcX * HalfHeight * Aspect;
  const double sy = ndcY * HalfHeight;
  if (V.camera.parallelProjection)
  {
    origin = V.camera.position + sx * Right + sy * Up;
    direction = Forward;
  }
  else
  {
    origin = V.camera.position;
    direction = (Forward + sx * Right + sy * Up).normalized();
  }
}

} // namespace ddg
