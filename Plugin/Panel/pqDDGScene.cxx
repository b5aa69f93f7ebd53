// pqDDGScene.cxx: scene access for the Design Gallery panel.
#include "pqDDGScene.h"

#include <pqApplicationCore.h>
#include <pqDataRepresentation.h>
#include <pqOutputPort.h>
#include <pqPipelineSource.h>
#include <pqRenderView.h>
#include <pqServer.h>
#include <pqUndoStack.h>

#include <vtkDataObject.h>
#include <vtkPVDataMover.h>
#include <vtkSMPVRepresentationProxy.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMRenderViewProxy.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSMSourceProxy.h>

#include <QJsonArray>
#include <QJsonDocument>

#include <algorithm>
#include <cmath>
#include <vector>

namespace ddgpanel
{

namespace
{
QJsonArray triple(vtkSMProxy* proxy, const char* name)
{
  vtkSMPropertyHelper h(proxy, name);
  return QJsonArray{ h.GetAsDouble(0), h.GetAsDouble(1), h.GetAsDouble(2) };
}

std::vector<double> numbers(const QJsonValue& value)
{
  std::vector<double> out;
  for (const auto& v : value.toArray())
    out.push_back(v.toDouble());
  return out;
}

// vtkColorTransferFunction's ColorSpace enumeration, as the LUT proxy's ColorSpace domain names it.
const QStringList& colorSpaces()
{
  static const QStringList spaces{ "RGB", "HSV", "Lab", "Diverging", "Lab/CIEDE2000", "Step" };
  return spaces;
}

int colorSpace(const QString& name)
{
  const int i = static_cast<int>(colorSpaces().indexOf(name));
  return i < 0 ? 0 : i;
}
} // namespace

QJsonObject viewJson(pqRenderView* view, pqDataRepresentation* repr, int maxSide)
{
  auto* proxy = vtkSMRenderViewProxy::SafeDownCast(view->getProxy());
  proxy->SynchronizeCameraProperties();
  QJsonObject camera;
  camera["position"] = triple(proxy, "CameraPosition");
  camera["focal_point"] = triple(proxy, "CameraFocalPoint");
  camera["view_up"] = triple(proxy, "CameraViewUp");
  camera["view_angle"] = vtkSMPropertyHelper(proxy, "CameraViewAngle").GetAsDouble();
  camera["parallel_projection"] =
    vtkSMPropertyHelper(proxy, "CameraParallelProjection").GetAsInt() != 0;
  camera["parallel_scale"] = vtkSMPropertyHelper(proxy, "CameraParallelScale").GetAsDouble();
  vtkSMPropertyHelper size(proxy, "ViewSize");
  const double w = std::max(1, size.GetAsInt(0)), h = std::max(1, size.GetAsInt(1));
  const double scale = std::min(1.0, maxSide / std::max(w, h));
  QJsonObject out;
  out["camera"] = camera;
  out["size"] = QJsonArray{ std::max(1, static_cast<int>(std::lround(w * scale))),
    std::max(1, static_cast<int>(std::lround(h * scale))) };
  // ParaView 5.11 keeps the background in "Background" unless the colour palette supplies it
  out["background"] = triple(proxy, "Background");
  if (repr && repr->getProxy()->GetProperty("ScalarOpacityUnitDistance"))
    out["opacity_unit_distance"] =
      vtkSMPropertyHelper(repr->getProxy(), "ScalarOpacityUnitDistance").GetAsDouble();
  return out;
}

QString jsonText(const QJsonObject& object)
{
  return QString::fromUtf8(QJsonDocument(object).toJson(QJsonDocument::Compact));
}

QString applyPreset(pqDataRepresentation* repr, const QString& array, const QString& presetText,
  const QString& label, bool undoable)
{
  if (!repr)
    return "there is no representation of the volume in the active view";
  QJsonParseError error;
  const QJsonDocument doc = QJsonDocument::fromJson(presetText.toUtf8(), &error);
  QJsonObject preset =
    doc.isArray() && !doc.array().isEmpty() ? doc.array().at(0).toObject() : doc.object();
  const auto rgb = numbers(preset.value("RGBPoints"));
  const auto opacity = numbers(preset.value("Points"));
  if (error.error != QJsonParseError::NoError || rgb.empty() || rgb.size() % 4 != 0 ||
    opacity.empty() || opacity.size() % 4 != 0)
    return "the design's transfer function is not a ParaView preset with RGBPoints and Points";

  vtkSMProxy* reprProxy = repr->getProxy();
  if (!reprProxy->GetProperty("LookupTable"))
    return "the active representation has no colour map";
  if (undoable)
    BEGIN_UNDO_SET(label);
  if (auto* pv = vtkSMPVRepresentationProxy::SafeDownCast(reprProxy))
    pv->SetRepresentationType("Volume");
  vtkSMPVRepresentationProxy::SetScalarColoring(
    reprProxy, array.toUtf8().constData(), vtkDataObject::POINT);
  vtkSMProxy* lut = vtkSMPropertyHelper(reprProxy, "LookupTable").GetAsProxy();
  vtkSMProxy* sof = reprProxy->GetProperty("ScalarOpacityFunction")
    ? vtkSMPropertyHelper(reprProxy, "ScalarOpacityFunction").GetAsProxy()
    : nullptr;
  if (!lut || !sof)
  {
    if (undoable)
      END_UNDO_SET();
    return "the representation has no colour or opacity map for '" + array + "'";
  }
  vtkSMPropertyHelper(lut, "AutomaticRescaleRangeMode").Set(-1); // Never
  vtkSMPropertyHelper(lut, "ColorSpace")
    .Set(colorSpace(preset.value("ColorSpace").toString("RGB")));
  vtkSMPropertyHelper(lut, "RGBPoints").Set(rgb.data(), static_cast<unsigned int>(rgb.size()));
  vtkSMPropertyHelper(sof, "Points").Set(opacity.data(), static_cast<unsigned int>(opacity.size()));
  lut->UpdateVTKObjects();
  sof->UpdateVTKObjects();
  reprProxy->UpdateVTKObjects();
  if (undoable)
    END_UNDO_SET();
  repr->renderViewEventually();
  return {};
}

QString currentPreset(pqDataRepresentation* repr)
{
  if (!repr || !repr->getProxy()->GetProperty("LookupTable"))
    return {};
  vtkSMProxy* lut = vtkSMPropertyHelper(repr->getProxy(), "LookupTable").GetAsProxy();
  vtkSMProxy* sof = repr->getProxy()->GetProperty("ScalarOpacityFunction")
    ? vtkSMPropertyHelper(repr->getProxy(), "ScalarOpacityFunction").GetAsProxy()
    : nullptr;
  if (!lut || !sof)
    return {};
  auto values = [](vtkSMProxy* p, const char* name)
  {
    QJsonArray a;
    for (double v : vtkSMPropertyHelper(p, name).GetDoubleArray())
      a.append(v);
    return a;
  };
  QJsonObject preset;
  preset["Name"] = "before the design gallery";
  preset["ColorSpace"] =
    colorSpaces().value(vtkSMPropertyHelper(lut, "ColorSpace").GetAsInt(), "RGB");
  preset["RGBPoints"] = values(lut, "RGBPoints");
  preset["Points"] = values(sof, "Points");
  return jsonText(preset);
}

vtkSmartPointer<vtkSMSourceProxy> newFilter(
  pqServer* server, const char* name, vtkSMSourceProxy* input, int port)
{
  vtkSmartPointer<vtkSMSourceProxy> filter;
  filter.TakeReference(
    vtkSMSourceProxy::SafeDownCast(server->proxyManager()->NewProxy("filters", name)));
  if (filter)
  {
    vtkSMPropertyHelper(filter, "Input").Set(input, static_cast<unsigned int>(port));
    filter->UpdateVTKObjects();
  }
  return filter;
}

vtkSmartPointer<vtkDataObject> fetch(pqServer* server, vtkSMSourceProxy* producer, int port)
{
  vtkSmartPointer<vtkSMProxy> mover;
  mover.TakeReference(server->proxyManager()->NewProxy("misc", "DataMover"));
  if (!mover)
    return nullptr;
  vtkSMPropertyHelper(mover, "Producer").Set(producer);
  vtkSMPropertyHelper(mover, "PortNumber").Set(port);
  vtkSMPropertyHelper(mover, "SourceRanks").Set(0);
  mover->UpdateVTKObjects();
  mover->InvokeCommand("Execute");
  auto* result = vtkPVDataMover::SafeDownCast(mover->GetClientSideObject());
  vtkDataObject* data = result ? result->GetDataSetFromRank(0) : nullptr;
  if (!data ||
    data->GetNumberOfElements(vtkDataObject::POINT) +
        data->GetNumberOfElements(vtkDataObject::ROW) ==
      0)
    return nullptr;
  vtkSmartPointer<vtkDataObject> copy;
  copy.TakeReference(data->NewInstance());
  copy->DeepCopy(data);
  return copy;
}

QString lastError(vtkSMProxy* filter)
{
  if (!filter || !filter->GetProperty("LastError"))
    return {};
  filter->UpdatePropertyInformation();
  return QString::fromUtf8(vtkSMPropertyHelper(filter, "LastError").GetAsString());
}

} // namespace ddgpanel
