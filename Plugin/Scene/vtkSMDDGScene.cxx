// vtkSMDDGScene.cxx: the Design Gallery's scene logic over ParaView proxies.
#include "vtkSMDDGScene.h"

#include <vtkDataObject.h>
#include <vtkDataSetAttributes.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPVArrayInformation.h>
#include <vtkPVDataInformation.h>
#include <vtkPVDataSetAttributesInformation.h>
#include <vtkSMPVRepresentationProxy.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMProxyIterator.h>
#include <vtkSMRenderViewProxy.h>
#include <vtkSMRepresentationProxy.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSMSourceProxy.h>
#include <vtksys/SystemTools.hxx>

#include "Gallery/Export.h"
#include "Image/Image.h"
#include "Render/View.h"
#include "TransferFunction/TransferFunction1D.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <iterator>
#include <sstream>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkSMDDGScene);

using json = nlohmann::json;

namespace
{

// The Volume representation's lighting properties: view-JSON key, property, ddg::Lighting's field
// (ViewJSON reads them, SetLighting writes them); Shade itself is "shade".
struct LightingProperty
{
  const char* key;
  const char* name;
  double ddg::Lighting::*field;
};
constexpr LightingProperty LightingProperties[] = { { "ambient", "Ambient",
                                                      &ddg::Lighting::ambient },
  { "diffuse", "Diffuse", &ddg::Lighting::diffuse },
  { "specular", "Specular", &ddg::Lighting::specular },
  { "specular_power", "SpecularPower", &ddg::Lighting::specularPower } };

json triple(vtkSMProxy* proxy, const char* name)
{
  vtkSMPropertyHelper h(proxy, name);
  return json::array({ h.GetAsDouble(0), h.GetAsDouble(1), h.GetAsDouble(2) });
}

/// The numbers of a JSON array (anything else in it counts as 0; not an array: none).
std::vector<double> numbers(const json& value)
{
  std::vector<double> out;
  if (value.is_array())
    for (const auto& v : value)
      out.push_back(v.is_number() ? v.get<double>() : 0.0);
  return out;
}

json parse(const char* text)
{
  return json::parse(text ? text : "", nullptr, false); // discarded (is_discarded) when invalid
}

const json& member(const json& object, const char* name)
{
  static const json none;
  return object.is_object() && object.contains(name) ? object.at(name) : none;
}

// vtkColorTransferFunction's ColorSpace enumeration, as the LUT proxy's ColorSpace domain names it.
const char* const kColorSpaces[] = { "RGB", "HSV", "Lab", "Diverging", "Lab/CIEDE2000", "Step" };

// The enumeration's index of a preset's ColorSpace (absent: RGB; ParaView's presets also say
// "CIELAB" for Lab); -1 for a name ParaView does not know.
int colorSpace(const json& name)
{
  if (name.is_null())
    return 0;
  const std::string s = name.is_string() ? name.get<std::string>() : "";
  const auto* it =
    std::find(std::begin(kColorSpaces), std::end(kColorSpaces), s == "CIELAB" ? "Lab" : s);
  return it == std::end(kColorSpaces) ? -1 : static_cast<int>(it - std::begin(kColorSpaces));
}

// What keeps a preset's maps from being written (empty: nothing): 4 numbers a node in RGBPoints
// and Points, a ColorSpace ParaView knows, and Core's rules for a 1D TF (finite, increasing x;
// colours, opacities, midpoints and sharpnesses in [0, 1]). A node at the x of the one before
// replaces it, as vtkColorTransferFunction and vtkPiecewiseFunction do (three of ParaView's own
// presets have such nodes).
std::string presetProblem(const json& preset)
{
  for (const char* key : { "RGBPoints", "Points" })
  {
    const json& a = member(preset, key);
    if (!a.is_array() || a.empty() || a.size() % 4 != 0 ||
      !std::all_of(a.begin(), a.end(), [](const json& v) { return v.is_number(); }))
      return std::string("\"") + key + "\" must hold 4 numbers a node (" +
        (key[0] == 'R' ? "x, red, green, blue" : "x, opacity, midpoint, sharpness") + ")";
  }
  if (colorSpace(member(preset, "ColorSpace")) < 0)
    return "ColorSpace " + member(preset, "ColorSpace").dump() +
      " is not one of ParaView's (RGB, HSV, Lab, Diverging, Lab/CIEDE2000, Step)";
  const auto rgb = numbers(member(preset, "RGBPoints"));
  const auto opacity = numbers(member(preset, "Points"));
  for (const auto* nodes : { &rgb, &opacity })
    for (size_t i = 4; i < nodes->size(); i += 4)
      if ((*nodes)[i] < (*nodes)[i - 4]) // a repeated x is ParaView's; a smaller one is not
      {
        std::ostringstream msg;
        msg << (nodes == &rgb ? "RGBPoints" : "Points") << " are not sorted: node " << i / 4
            << " at x = " << (*nodes)[i] << " comes before x = " << (*nodes)[i - 4]
            << " (x must not decrease)";
        return msg.str();
      }
  ddg::TransferFunction1D tf;
  for (size_t i = 0; i < rgb.size(); i += 4)
  {
    if (!tf.color.empty() && tf.color.back().x == rgb[i])
      tf.color.pop_back();
    tf.color.push_back({ rgb[i], rgb[i + 1], rgb[i + 2], rgb[i + 3] });
  }
  for (size_t i = 0; i < opacity.size(); i += 4)
  {
    if (!tf.opacity.empty() && tf.opacity.back().x == opacity[i])
      tf.opacity.pop_back();
    tf.opacity.push_back({ opacity[i], opacity[i + 1], opacity[i + 2], opacity[i + 3] });
  }
  try
  {
    tf.validate();
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  return {};
}

/// The array the volume rule picks (nullptr: none, or not image data): the point array a visible
/// `repr` is coloured by, else the active point scalars, else the first one-component array.
vtkPVArrayInformation* chosenArray(vtkPVDataInformation* info, vtkSMProxy* repr)
{
  const int type = info ? info->GetDataSetType() : -1;
  if (type != VTK_IMAGE_DATA && type != VTK_UNIFORM_GRID && type != VTK_STRUCTURED_POINTS)
    return nullptr;
  vtkPVDataSetAttributesInformation* points = info->GetPointDataInformation();
  if (repr && repr->GetProperty("ColorArrayName") &&
    (!repr->GetProperty("Visibility") || vtkSMPropertyHelper(repr, "Visibility").GetAsInt()))
  {
    vtkSMPropertyHelper colour(repr, "ColorArrayName");
    const char* name = colour.GetInputArrayNameToProcess();
    if (name && *name &&
      colour.GetInputArrayAssociation() == vtkDataObject::FIELD_ASSOCIATION_POINTS &&
      points->GetArrayInformation(name))
      return points->GetArrayInformation(name);
  }
  vtkPVArrayInformation* scalars = points->GetAttributeInformation(vtkDataSetAttributes::SCALARS);
  for (int i = 0; !scalars && i < points->GetNumberOfArrays(); ++i)
    if (points->GetArrayInformation(i)->GetNumberOfComponents() == 1)
      scalars = points->GetArrayInformation(i);
  return scalars;
}

vtkPVDataInformation* dataInformation(vtkSMProxy* source, int port)
{
  auto* s = vtkSMSourceProxy::SafeDownCast(source);
  if (!s || port < 0)
    return nullptr;
  s->CreateOutputPorts(); // no-op once they exist
  return static_cast<unsigned int>(port) < s->GetNumberOfOutputPorts()
    ? s->GetDataInformation(static_cast<unsigned int>(port))
    : nullptr;
}

/// The 2D design of `boxesJSON` (Boxes, Range, OutputDimensions), or a reason it is none.
struct Boxes
{
  std::vector<double> boxes, range, dims;
  std::string error;
};

Boxes parseBoxes(const char* boxesJSON)
{
  const json pv = parse(boxesJSON);
  Boxes b{ numbers(member(pv, "Boxes")), numbers(member(pv, "Range")),
    numbers(member(pv, "OutputDimensions")), {} };
  if (b.boxes.empty() || b.boxes.size() % 8 != 0 || b.range.size() != 4 || b.dims.size() != 2)
    b.error = "the design's 2D transfer function has no ParaView boxes (Boxes, Range, "
              "OutputDimensions)";
  return b;
}

std::string writeBoxes(vtkSMProxy* repr, const std::string& array, const Boxes& b)
{
  vtkSMProxy* tf2 = vtkSMPropertyHelper(repr, "TransferFunction2D").GetAsProxy();
  if (!tf2)
    return "the representation has no TransferFunction2D for '" + array + "'";
  vtkSMPropertyHelper(repr, "UseGradientForTransfer2D").Set(1);
  vtkSMPropertyHelper mode(repr, "VolumeRenderingMode");
  if (mode.GetAsInt() == 1) // Ray Cast Only: vtkFixedPointVolumeRayCastMapper has no 2D TFs
    mode.Set(0);            // Smart
  vtkSMPropertyHelper(tf2, "Range").Set(b.range.data(), 4);
  const int size[2] = { static_cast<int>(b.dims[0]), static_cast<int>(b.dims[1]) };
  vtkSMPropertyHelper(tf2, "OutputDimensions").Set(size, 2);
  vtkSMPropertyHelper(tf2, "Boxes").Set(b.boxes.data(), static_cast<unsigned int>(b.boxes.size()));
  tf2->UpdateVTKObjects();
  return {};
}

/// Shared by the 1D and 2D apply: switches `repr` to Volume coloured by `array` and lets `write`
/// fill its maps (LookupTable, ScalarOpacityFunction).
template <typename Write>
std::string applyMaps(vtkSMProxy* repr, const std::string& array, bool twoD, Write write)
{
  if (!repr->GetProperty("LookupTable"))
    return "the active representation has no colour map";
  if (repr->GetProperty("UseTransfer2D")) // 1D or 2D rendering
    vtkSMPropertyHelper(repr, "UseTransfer2D").Set(twoD ? 1 : 0);
  if (auto* pv = vtkSMPVRepresentationProxy::SafeDownCast(repr))
    pv->SetRepresentationType("Volume");
  vtkSMPVRepresentationProxy::SetScalarColoring(repr, array.c_str(), vtkDataObject::POINT);
  vtkSMProxy* lut = vtkSMPropertyHelper(repr, "LookupTable").GetAsProxy();
  vtkSMProxy* sof = repr->GetProperty("ScalarOpacityFunction")
    ? vtkSMPropertyHelper(repr, "ScalarOpacityFunction").GetAsProxy()
    : nullptr;
  if (!lut || !sof)
    return "the representation has no colour or opacity map for '" + array + "'";
  vtkSMPropertyHelper(lut, "AutomaticRescaleRangeMode").Set(-1); // Never
  const std::string error = write(lut, sof);
  lut->UpdateVTKObjects();
  sof->UpdateVTKObjects();
  repr->UpdateVTKObjects();
  return error;
}
} // namespace

void vtkSMDDGScene::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}

// --- the view --------------------------------------------------------------------------------

std::string vtkSMDDGScene::SetCamera(vtkSMProxy* view, const char* viewJSON, bool checkOnly)
{
  auto* proxy = vtkSMRenderViewProxy::SafeDownCast(view);
  if (!proxy)
    return "not a render view";
  const std::string text = viewJSON ? viewJSON : "";
  ddg::View v;
  try
  {
    v = ddg::parseView(text); // checked as every reader checks it
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  if (checkOnly)
    return {};
  const ddg::Camera& c = v.camera;
  vtkSMPropertyHelper(proxy, "CameraPosition").Set(c.position.data(), 3);
  vtkSMPropertyHelper(proxy, "CameraFocalPoint").Set(c.focalPoint.data(), 3);
  vtkSMPropertyHelper(proxy, "CameraViewUp").Set(c.viewUp.data(), 3);
  vtkSMPropertyHelper(proxy, "CameraViewAngle").Set(c.viewAngle);
  vtkSMPropertyHelper(proxy, "CameraParallelProjection").Set(c.parallelProjection ? 1 : 0);
  // a JSON without a parallel scale leaves the view's (it matters only in parallel projection)
  if (json::parse(text).at("camera").contains("parallel_scale"))
    vtkSMPropertyHelper(proxy, "CameraParallelScale").Set(c.parallelScale);
  proxy->UpdateVTKObjects();
  return {};
}

std::string vtkSMDDGScene::FitToView(vtkSMProxy* view, const char* viewJSON)
{
  auto* proxy = vtkSMRenderViewProxy::SafeDownCast(view);
  const std::string text = viewJSON ? viewJSON : "";
  json doc = json::parse(text, nullptr, false); // not JSON: not an object
  if (!proxy || !doc.is_object() || !doc.contains("size"))
    return text;
  ddg::View v;
  try
  {
    v = ddg::parseView(text); // a camera, as every reader checks it
  }
  catch (const std::exception&)
  {
    return text; // SetCamera says why
  }
  vtkSMPropertyHelper size(proxy, "ViewSize");
  const int w = std::max(1, size.GetAsInt(0)), h = std::max(1, size.GetAsInt(1));
  const ddg::Camera c = ddg::cameraForShape(v, w, h);
  doc["camera"]["view_angle"] = c.viewAngle;
  if (doc["camera"].contains("parallel_scale"))
    doc["camera"]["parallel_scale"] = c.parallelScale;
  doc["size"] = json::array({ w, h });
  return doc.dump();
}

std::string vtkSMDDGScene::SetLighting(
  vtkSMProxy* representation, const char* viewJSON, bool checkOnly)
{
  if (!representation || !representation->GetProperty("Shade"))
    return "not a representation with Shade";
  ddg::Lighting l;
  try
  {
    l = ddg::parseView(viewJSON ? viewJSON : "").lighting; // checked as every reader checks it
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  if (checkOnly)
    return {};
  vtkSMPropertyHelper(representation, "Shade").Set(l.shade ? 1 : 0);
  if (l.shade)
    for (const auto& p : LightingProperties)
      if (representation->GetProperty(p.name))
        vtkSMPropertyHelper(representation, p.name).Set(l.*p.field);
  representation->UpdateVTKObjects();
  return {};
}

namespace
{
/// Whether a render view shows any of its representations.
bool showsAnything(vtkSMProxy* view)
{
  vtkSMPropertyHelper shown(view, "Representations", true);
  for (unsigned int i = 0; i < shown.GetNumberOfElements(); ++i)
  {
    vtkSMProxy* r = shown.GetAsProxy(i);
    if (r && r->GetProperty("Visibility") && vtkSMPropertyHelper(r, "Visibility").GetAsInt() != 0)
      return true;
  }
  return false;
}
} // namespace

std::string vtkSMDDGScene::ViewJSON(
  vtkSMProxy* view, vtkSMProxy* representationOrSource, int maxSide)
{
  auto* proxy = vtkSMRenderViewProxy::SafeDownCast(view);
  if (!proxy)
    return {};
  proxy->SynchronizeCameraProperties();
  vtkSMPropertyHelper size(proxy, "ViewSize");
  const double w = std::max(1, size.GetAsInt(0)), h = std::max(1, size.GetAsInt(1));
  // A view that shows nothing (pvpython's after OpenDataFile) has ParaView's first camera, which
  // does not look at the volume: the volume is seen as ParaView shows it once shown (Reset
  // Camera on its bounds; paraview.simple's first render), not as an empty picture
  ddg::Camera c; // the view's own, or that reset camera
  auto* source = vtkSMSourceProxy::SafeDownCast(representationOrSource);
  std::array<double, 6> b{ 1, 0, 1, 0, 1, 0 }; // none
  if (source && !showsAnything(proxy))
  {
    source->UpdatePipeline(); // a reader never shown has not read its file: no bounds yet
    if (vtkPVDataInformation* info = dataInformation(source, 0))
      info->GetBounds(b.data());
  }
  if (b[0] <= b[1] && b[2] <= b[3] && b[4] <= b[5])
    c = ddg::resetCameraView(b, static_cast<int>(w), static_cast<int>(h)).camera;
  else
  {
    vtkSMPropertyHelper(proxy, "CameraPosition").Get(c.position.data(), 3);
    vtkSMPropertyHelper(proxy, "CameraFocalPoint").Get(c.focalPoint.data(), 3);
    vtkSMPropertyHelper(proxy, "CameraViewUp").Get(c.viewUp.data(), 3);
    c.viewAngle = vtkSMPropertyHelper(proxy, "CameraViewAngle").GetAsDouble();
    c.parallelProjection = vtkSMPropertyHelper(proxy, "CameraParallelProjection").GetAsInt() != 0;
    c.parallelScale = vtkSMPropertyHelper(proxy, "CameraParallelScale").GetAsDouble();
  }
  const auto xyz = [](const Eigen::Vector3d& p) { return json::array({ p[0], p[1], p[2] }); };
  json camera;
  camera["position"] = xyz(c.position);
  camera["focal_point"] = xyz(c.focalPoint);
  camera["view_up"] = xyz(c.viewUp);
  camera["view_angle"] = c.viewAngle;
  camera["parallel_projection"] = c.parallelProjection;
  camera["parallel_scale"] = c.parallelScale;
  const double scale = maxSide > 0 ? std::min(1.0, maxSide / std::max(w, h)) : 1.0;
  json out;
  out["camera"] = camera;
  out["size"] = json::array({ std::max(1, static_cast<int>(std::lround(w * scale))),
    std::max(1, static_cast<int>(std::lround(h * scale))) });
  // The background ParaView draws: a new view takes it from the colour palette
  // (UseColorPaletteForBackground, default on; ParaView 5.11's palette: 0.32 0.34 0.43), and only
  // otherwise from its own Background property (0.329 0.349 0.427 by default, never drawn then).
  out["background"] = triple(proxy, "Background");
  vtkSMProxy* palette = proxy->GetSessionProxyManager()
    ? proxy->GetSessionProxyManager()->GetProxy("settings", "ColorPalette")
    : nullptr;
  if (proxy->GetProperty("UseColorPaletteForBackground") &&
    vtkSMPropertyHelper(proxy, "UseColorPaletteForBackground").GetAsInt() != 0 && palette &&
    palette->GetProperty("BackgroundColor")) // labelled "Background" in Python
    out["background"] = triple(palette, "BackgroundColor");
  vtkSMProxy* repr = vtkSMRepresentationProxy::SafeDownCast(representationOrSource);
  if (!repr && vtkSMSourceProxy::SafeDownCast(representationOrSource))
    repr = proxy->FindRepresentation(vtkSMSourceProxy::SafeDownCast(representationOrSource), 0);
  if (repr && repr->GetProperty("ScalarOpacityUnitDistance"))
    out["opacity_unit_distance"] =
      vtkSMPropertyHelper(repr, "ScalarOpacityUnitDistance").GetAsDouble();
  // Shade on: the representation's coefficients (the view's light kit is ParaView's default)
  if (repr && repr->GetProperty("Shade") && vtkSMPropertyHelper(repr, "Shade").GetAsInt() != 0)
  {
    json lighting;
    lighting["shade"] = true;
    for (const auto& p : LightingProperties)
      if (repr->GetProperty(p.name))
        lighting[p.key] = vtkSMPropertyHelper(repr, p.name).GetAsDouble();
    out["lighting"] = lighting;
  }
  return out.dump();
}

// --- the volume ------------------------------------------------------------------------------

int vtkSMDDGScene::CheckVolume(vtkSMProxy* source, vtkSMProxy* representation, int port)
{
  vtkPVDataInformation* info = dataInformation(source, port);
  const int type = info ? info->GetDataSetType() : -1;
  if (type < 0 || (info->GetNumberOfPoints() == 0 && type == VTK_IMAGE_DATA))
    return NO_DATA;
  vtkPVArrayInformation* a = chosenArray(info, representation);
  return a && a->GetNumberOfComponents() == 1 ? IS_VOLUME : NOT_A_VOLUME;
}

std::string vtkSMDDGScene::VolumeProblem(int check)
{
  switch (check)
  {
    case IS_VOLUME:
      return {};
    case NO_DATA:
      return "has no data yet";
    default:
      return "is not a volume: the Design Gallery needs image data with a one-component point "
             "array (e.g. a .vti, .raw or DICOM volume)";
  }
}

std::string vtkSMDDGScene::VolumeProblemOf(vtkSMProxy* source, vtkSMProxy* representation, int port)
{
  const int check = CheckVolume(source, representation, port);
  if (check != NOT_A_VOLUME)
    return VolumeProblem(check);
  vtkPVArrayInformation* a = chosenArray(dataInformation(source, port), representation);
  if (!a || !a->GetName())
    return VolumeProblem(check);
  return "is not a volume: its point array '" + std::string(a->GetName()) + "' has " +
    std::to_string(a->GetNumberOfComponents()) +
    " components (colour it by, or make active, a one-component point array)";
}

std::string vtkSMDDGScene::VolumeArray(vtkSMProxy* source, vtkSMProxy* representation, int port)
{
  if (CheckVolume(source, representation, port) != IS_VOLUME)
    return {};
  return chosenArray(dataInformation(source, port), representation)->GetName();
}

std::string vtkSMDDGScene::DefaultModelDirectory(vtkSMProxy* source, const char* dataDirectory)
{
  if (!source || !source->GetProperty("FileName") ||
    vtkSMPropertyHelper(source, "FileName").GetNumberOfElements() == 0)
    return {};
  const char* file = vtkSMPropertyHelper(source, "FileName").GetAsString(0);
  std::string stem = vtksys::SystemTools::GetFilenameWithoutLastExtension(file ? file : "");
  std::transform(stem.begin(), stem.end(), stem.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const std::string dir = std::string(dataDirectory ? dataDirectory : "") + "/Models/" + stem;
  return !stem.empty() && vtksys::SystemTools::FileExists(dir + "/bundle.json", true)
    ? dir
    : std::string();
}

// --- transfer functions ----------------------------------------------------------------------

std::string vtkSMDDGScene::Apply1D(
  vtkSMProxy* representation, const char* array, const char* presetJSON, bool checkOnly)
{
  if (!representation && !checkOnly)
    return "there is no representation of the volume in the active view";
  const json doc = parse(presetJSON);
  const json& preset = doc.is_array() && !doc.empty() ? doc.at(0) : doc;
  if (doc.is_discarded() || !preset.is_object())
    return "the transfer function is not a ParaView preset (JSON with RGBPoints and Points)";
  if (const std::string problem = presetProblem(preset); !problem.empty())
    return "the transfer function cannot be written into ParaView's maps: " + problem;
  if (checkOnly)
    return {};
  const auto rgb = numbers(member(preset, "RGBPoints"));
  const auto opacity = numbers(member(preset, "Points"));
  return applyMaps(representation, array ? array : "", false,
    [&](vtkSMProxy* lut, vtkSMProxy* sof)
    {
      vtkSMPropertyHelper(lut, "ColorSpace").Set(colorSpace(member(preset, "ColorSpace")));
      vtkSMPropertyHelper(lut, "RGBPoints").Set(rgb.data(), static_cast<unsigned int>(rgb.size()));
      vtkSMPropertyHelper(sof, "Points")
        .Set(opacity.data(), static_cast<unsigned int>(opacity.size()));
      return std::string();
    });
}

namespace
{
bool separateMap(vtkSMProxy* repr)
{
  return repr->GetProperty("UseSeparateColorMap") &&
    vtkSMPropertyHelper(repr, "UseSeparateColorMap").GetAsInt() != 0;
}

vtkSMProxy* inputOf(vtkSMProxy* repr)
{
  return repr->GetProperty("Input") ? vtkSMPropertyHelper(repr, "Input").GetAsProxy() : nullptr;
}
} // namespace

std::string vtkSMDDGScene::SharedColorMapUsers(vtkSMProxy* representation, const char* array)
{
  if (!representation || !array || !*array || separateMap(representation))
    return {};
  vtkSMProxy* self = inputOf(representation);
  vtkSMSessionProxyManager* pxm = representation->GetSessionProxyManager();
  std::vector<std::string> names;
  vtkNew<vtkSMProxyIterator> it;
  it->SetSession(representation->GetSession());
  it->SetModeToOneGroup();
  for (it->Begin("representations"); !it->IsAtEnd(); it->Next())
  {
    vtkSMProxy* other = it->GetProxy();
    if (!other || other == representation || !other->GetProperty("LookupTable") ||
      !other->GetProperty("ColorArrayName") || !other->GetProperty("Visibility") ||
      separateMap(other) || vtkSMPropertyHelper(other, "Visibility").GetAsInt() == 0 ||
      !vtkSMPropertyHelper(other, "LookupTable").GetAsProxy())
      continue;
    const char* colour =
      vtkSMPropertyHelper(other, "ColorArrayName", true).GetInputArrayNameToProcess();
    vtkSMProxy* input = inputOf(other);
    if (!colour || std::string(colour) != array || !input || input == self)
      continue;
    const char* name = pxm->GetProxyName("sources", input);
    names.push_back(name ? name : "(unnamed)");
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  std::string text;
  for (const auto& n : names)
    text += (text.empty() ? "" : "\n") + n;
  return text;
}

std::string vtkSMDDGScene::UseSeparateColorMap(vtkSMProxy* representation, const char* array)
{
  if (!representation || !representation->GetProperty("UseSeparateColorMap"))
    return "the representation cannot have a separate colour map";
  if (!array || !*array)
    return "no array to colour by";
  vtkSMProxy* shared = representation->GetProperty("LookupTable")
    ? vtkSMPropertyHelper(representation, "LookupTable").GetAsProxy()
    : nullptr;
  const std::string before = shared ? CurrentPreset(representation) : std::string();
  vtkSMPropertyHelper(representation, "UseSeparateColorMap").Set(1);
  representation->UpdateVTKObjects();
  vtkSMPVRepresentationProxy::SetScalarColoring(representation, array, vtkDataObject::POINT);
  vtkSMProxy* own = vtkSMPropertyHelper(representation, "LookupTable").GetAsProxy();
  if (!own || own == shared)
    return "ParaView did not give the representation its own colour map";
  if (!before.empty()) // the same look as before, in maps of its own
    return Apply1D(representation, array, before.c_str());
  return {};
}

std::string vtkSMDDGScene::Apply2D(
  vtkSMProxy* representation, const char* array, const char* boxesJSON, bool checkOnly)
{
  if (!representation && !checkOnly)
    return "there is no representation of the volume in the active view";
  const Boxes b = parseBoxes(boxesJSON);
  if (!b.error.empty() || checkOnly)
    return b.error;
  if (!representation->GetProperty("UseTransfer2D") ||
    !representation->GetProperty("TransferFunction2D"))
    return "the active representation has no 2D transfer function (ParaView 5.11's volume "
           "representation of image data has)";
  const std::string name = array ? array : "";
  return applyMaps(representation, name, true,
    [&](vtkSMProxy*, vtkSMProxy*) { return writeBoxes(representation, name, b); });
}

std::string vtkSMDDGScene::WriteTransferFunction2D(
  vtkSMProxy* representation, const char* boxesJSON)
{
  if (!representation || !representation->GetProperty("TransferFunction2D"))
    return "the active representation has no 2D transfer function (ParaView 5.11's volume "
           "representation of image data has)";
  const Boxes b = parseBoxes(boxesJSON);
  if (!b.error.empty())
    return b.error;
  vtkSMPropertyHelper colour(representation, "ColorArrayName", true);
  const char* array = colour.GetInputArrayNameToProcess();
  const std::string error = writeBoxes(representation, array ? array : "", b);
  representation->UpdateVTKObjects();
  return error;
}

std::string vtkSMDDGScene::CurrentPreset(vtkSMProxy* representation)
{
  if (!representation || !representation->GetProperty("LookupTable"))
    return {};
  vtkSMProxy* lut = vtkSMPropertyHelper(representation, "LookupTable").GetAsProxy();
  vtkSMProxy* sof = representation->GetProperty("ScalarOpacityFunction")
    ? vtkSMPropertyHelper(representation, "ScalarOpacityFunction").GetAsProxy()
    : nullptr;
  if (!lut || !sof)
    return {};
  const int space = vtkSMPropertyHelper(lut, "ColorSpace").GetAsInt();
  json preset;
  preset["Name"] = "before the design gallery";
  preset["ColorSpace"] =
    space >= 0 && space < static_cast<int>(std::size(kColorSpaces)) ? kColorSpaces[space] : "RGB";
  preset["RGBPoints"] = vtkSMPropertyHelper(lut, "RGBPoints").GetDoubleArray();
  preset["Points"] = vtkSMPropertyHelper(sof, "Points").GetDoubleArray();
  return preset.dump();
}

std::string vtkSMDDGScene::ExportName(const char* volume, const char* origin, const char* path)
{
  return ddg::exportName(
    volume ? volume : "", ddg::designOrigin(origin ? origin : ""), path ? path : "");
}

std::string vtkSMDDGScene::DesignOrigin(const char* action)
{
  return ddg::designOrigin(action ? action : "");
}

std::vector<unsigned char> vtkSMDDGScene::DecodePicture(
  const std::string& bytes, int& width, int& height)
{
  width = height = 0;
  ddg::Image rgb;
  try
  {
    rgb = ddg::toChannels(ddg::inColour(ddg::decodeImage(bytes, "the picture")), 3);
  }
  catch (const std::exception&)
  {
    return {};
  }
  std::vector<unsigned char> out(rgb.pixels.size());
  std::transform(rgb.pixels.begin(), rgb.pixels.end(), out.begin(),
    [](float v)
    { return static_cast<unsigned char>(std::lround(255 * std::clamp(v, 0.0f, 1.0f))); });
  width = rgb.width;
  height = rgb.height;
  return out;
}

std::string vtkSMDDGScene::PictureFormat(const std::string& firstBytes)
{
  return ddg::imageFormat(firstBytes);
}
