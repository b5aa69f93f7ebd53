// Export.cxx: ParaView presets, DDG 2D TFs and Slicer volume properties of designs.
#include "Gallery/Export.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Render/RayCaster.h"
#include "Render/View.h"
#include "TransferFunction/TransferFunction2D.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace ddg
{

TransferFunctionFile primitivesToTransferFunction(const std::vector<GaussianPrimitive>& primitives,
  int dimensions, std::array<double, 2> valueRange, std::array<double, 2> gradientRange,
  const std::string& name)
{
  if (dimensions != 1 && dimensions != 2)
    throw Error("a design TF is 1D or 2D");
  if (!(valueRange[0] < valueRange[1]) || !std::isfinite(valueRange[0]) ||
    !std::isfinite(valueRange[1]))
    throw Error("the value range of a design TF must be finite and increasing");
  validatePrimitives(primitives, dimensions == 2);
  TransferFunctionFile out;
  out.is2D = dimensions == 2;
  if (out.is2D)
  {
    if (!(gradientRange[0] < gradientRange[1]))
      throw Error("the gradient-magnitude range of a 2D design TF must be increasing");
    out.tf2D.name = name;
    out.tf2D.primitives = primitives;
    out.tf2D.table.valueRange = valueRange;
    out.tf2D.table.gradientRange = gradientRange;
  }
  else
  {
    out.tf1D = tableToTransferFunction(
      rasterize1D(primitives, valueRange[0], valueRange[1], 1024), 1.0 / 512.0, name);
  }
  return out;
}

std::string exportName(
  const std::string& volume, const std::string& origin, const std::string& path, std::time_t when)
{
  const std::string volumeName = std::filesystem::path(volume).stem().string();
  const std::string stem = std::filesystem::path(path).stem().string();
  std::tm local{};
  localtime_r(&when, &local);
  char date[32];
  std::strftime(date, sizeof(date), "%Y-%m-%d %H:%M:%S", &local);
  std::ostringstream name;
  name << "DDG";
  for (const std::string& part : { volumeName, origin == stem ? std::string() : origin, stem })
    if (!part.empty())
      name << ' ' << part;
  name << ' ' << date;
  return name.str();
}

std::string designOrigin(const std::string& action)
{
  if (action == "pick")
    return "outline design";
  if (action == "latent")
    return "design";
  if (action == "axes")
    return "edit";
  return action;
}

TransferFunctionFile renamed(TransferFunctionFile tf, const std::string& name)
{
  if (tf.is2D)
    tf.tf2D.name = name;
  else
    tf.tf1D.name = name;
  return tf;
}

std::string slicerVolumePropertyJson(
  const TransferFunction1D& tf, std::array<double, 2> effectiveRange, double opacityUnitDistance)
{
  tf.validate();
  if (!(effectiveRange[0] < effectiveRange[1]))
    throw Error("the effective range must be increasing");
  if (!(opacityUnitDistance > 0) || !std::isfinite(opacityUnitDistance))
    throw Error("the scalar opacity unit distance must be positive");
  using json = nlohmann::json;
  json opacity = json::array(), color = json::array();
  for (const auto& n : tf.opacity)
    opacity.push_back(
      { { "x", n.x }, { "y", n.alpha }, { "midpoint", n.midpoint }, { "sharpness", n.sharpness } });
  for (const auto& n : tf.color)
    color.push_back({ { "x", n.x }, { "color", { n.r, n.g, n.b } }, { "midpoint", n.midpoint },
      { "sharpness", n.sharpness } });
  json component = { { "componentWeight", 1.0 }, { "shade", false },
    { "lighting",
      { { "ambient", 0.1 }, { "diffuse", 0.7 }, { "specular", 0.2 }, { "specularPower", 10.0 } } },
    { "disableGradientOpacity", true }, { "scalarOpacityUnitDistance", opacityUnitDistance },
    { "scalarOpacity", { { "points", opacity } } },
    { "gradientOpacity",
      { { "points",
        { { { "x", 0.0 }, { "y", 1.0 }, { "midpoint", 0.5 }, { "sharpness", 0.0 } },
          { { "x", 1.0e6 }, { "y", 1.0 }, { "midpoint", 0.5 }, { "sharpness", 0.0 } } } } } },
    { "rgbTransferFunction", { { "points", color } } } };
  json property = { { "effectiveRange", { effectiveRange[0], effectiveRange[1] } },
    { "isoSurfaceValues", json::array() }, { "independentComponents", true },
    { "interpolationType", "linear" }, { "useClippedVoxelIntensity", false },
    { "clippedVoxelIntensity", 0.0 }, { "scatteringAnisotropy", 0.0 },
    { "components", { component } } };
  json doc = { { "@schema",
                 "https://raw.githubusercontent.com/slicer/slicer/main/Modules/Loadable/"
                 "VolumeRendering/Resources/Schema/volume-property-schema-v1.0.0.json#" },
    { "volumeProperties", { property } } };
  return doc.dump(2) + "\n";
}

void exportTransferFunction(const TransferFunctionFile& tf, const std::string& path,
  const std::string& format, std::array<double, 2> valueRange, double opacityUnitDistance)
{
  if (format == "paraview")
  {
    if (tf.is2D)
      writeTransferFunction2D(tf.tf2D, path);
    else
      writePreset(tf.tf1D, path);
  }
  else if (format == "slicer")
  {
    if (tf.is2D)
      throw Error("Slicer's volume property holds 1D TFs only; export a 2D TF as \"paraview\"");
    writeFileAtomic(path, slicerVolumePropertyJson(tf.tf1D, valueRange, opacityUnitDistance),
      "Slicer volume property");
  }
  else
    throw Error("unknown export format '" + format + "' (paraview, paraview-2d or slicer)");
}

std::string paraViewTransferFunction2DJson(const RayCaster& caster, const TransferFunction2D& tf,
  const View& view, const ParaViewBoxFitOptions& options, ParaViewBoxFitReport* report)
{
  return paraViewTransferFunction2DJson(caster.paraviewMapping2D(view), tf, options, report);
}

std::string paraViewTransferFunction2DJson(const ParaViewTransfer2DMapping& mapping,
  const TransferFunction2D& tf, const ParaViewBoxFitOptions& options, ParaViewBoxFitReport* report)
{
  ParaViewBoxFitReport own;
  ParaViewBoxFitReport& r = report ? *report : own;
  const auto boxes = fitParaViewBoxes(tf, mapping, options, &r);
  return boxes.toJson(&r);
}

std::string exportTransferFunction(const TransferFunctionFile& tf, const std::string& path,
  const std::string& format, const RayCaster& caster, const View& view, int boxIterations)
{
  if (format != "paraview-2d")
  {
    exportTransferFunction(tf, path, format, caster.dataRange(), caster.opacityUnitDistance(view));
    return format;
  }
  if (!tf.is2D)
    throw Error("--format paraview-2d exports 2D TFs; a 1D TF is a ParaView preset (paraview)");
  ParaViewBoxFitOptions options;
  options.iterations = boxIterations;
  ParaViewBoxFitReport report;
  const auto boxes = fitParaViewBoxes(tf.tf2D, caster.paraviewMapping2D(view), options, &report);
  writeFileAtomic(path, boxes.toJson(&report), "ParaView 2D transfer function");
  char text[160];
  std::snprintf(text, sizeof(text),
    "paraview-2d: %zu boxes; fit RMSE %.4f, alpha RMSE %.4f, from %.4f", boxes.boxes.size(),
    report.rmse, report.alphaRmse, report.initialRmse);
  return text;
}

} // namespace ddg
