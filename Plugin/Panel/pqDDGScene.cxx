// pqDDGScene.cxx: scene access for the Design Gallery panel.
#include "pqDDGScene.h"

#include <pqActiveObjects.h>
#include <pqApplicationCore.h>
#include <pqDataRepresentation.h>
#include <pqOutputPort.h>
#include <pqPipelineSource.h>
#include <pqRenderView.h>
#include <pqServerManagerModel.h>
#include <pqUndoStack.h>
#include <pqView.h>

#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkPVDataMover.h>
#include <vtkPointData.h>
#include <vtkSMPVRepresentationProxy.h>
#include <vtkSMParaViewPipelineControllerWithRendering.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMRenderViewProxy.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSMSourceProxy.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

#include <QCoreApplication>
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

pqDataRepresentation* representation(vtkSMSourceProxy* source)
{
  auto* view = qobject_cast<pqRenderView*>(pqActiveObjects::instance().activeView());
  auto* pipelineSource = source
    ? pqApplicationCore::instance()->getServerManagerModel()->findItem<pqPipelineSource*>(source)
    : nullptr;
  if (!view || !pipelineSource)
    return nullptr;
  pqDataRepresentation* repr = pipelineSource->getRepresentation(0, view);
  if (!repr)
  {
    vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
    controller->Show(source, 0, view->getViewProxy());
    repr = pipelineSource->getRepresentation(0, view);
  }
  return repr;
}

QString jsonText(const QJsonObject& object)
{
  return QString::fromUtf8(QJsonDocument(object).toJson(QJsonDocument::Compact));
}

namespace
{
// Shared by the 1D and 2D apply: switches `repr` to Volume coloured by `array` and lets `write`
// fill its maps (representation, LookupTable, ScalarOpacityFunction), as one undo step.
template <typename Write>
QString applyMaps(pqDataRepresentation* repr, const QString& array, const QString& label,
  bool undoable, bool twoD, Write write)
{
  vtkSMProxy* reprProxy = repr->getProxy();
  if (!reprProxy->GetProperty("LookupTable"))
    return "the active representation has no colour map";
  if (undoable)
    BEGIN_UNDO_SET(label);
  if (reprProxy->GetProperty("UseTransfer2D")) // 1D or 2D rendering
    vtkSMPropertyHelper(reprProxy, "UseTransfer2D").Set(twoD ? 1 : 0);
  if (auto* pv = vtkSMPVRepresentationProxy::SafeDownCast(reprProxy))
    pv->SetRepresentationType("Volume");
  vtkSMPVRepresentationProxy::SetScalarColoring(
    reprProxy, array.toUtf8().constData(), vtkDataObject::POINT);
  vtkSMProxy* lut = vtkSMPropertyHelper(reprProxy, "LookupTable").GetAsProxy();
  vtkSMProxy* sof = reprProxy->GetProperty("ScalarOpacityFunction")
    ? vtkSMPropertyHelper(reprProxy, "ScalarOpacityFunction").GetAsProxy()
    : nullptr;
  QString error = !lut || !sof
    ? "the representation has no colour or opacity map for '" + array + "'"
    : QString();
  if (error.isEmpty())
  {
    vtkSMPropertyHelper(lut, "AutomaticRescaleRangeMode").Set(-1); // Never
    error = write(reprProxy, lut, sof);
    lut->UpdateVTKObjects();
    sof->UpdateVTKObjects();
    reprProxy->UpdateVTKObjects();
    if (error.isEmpty() && twoD)
    {
      // ParaView's Color Map Editor follows UseTransfer2D: when it shows its 2D editor it
      // computes a 2D histogram and sets the TF's Range and OutputDimensions from it (queued,
      // after a render). Let it happen here, inside this undo step, then write ours again.
      if (auto* view = repr->getView())
        view->forceRender();
      QCoreApplication::processEvents();
      error = write(reprProxy, lut, sof);
    }
  }
  if (undoable)
    END_UNDO_SET();
  if (error.isEmpty())
    repr->renderViewEventually();
  return error;
}

} // namespace

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
  return applyMaps(repr, array, label, undoable, false,
    [&](vtkSMProxy*, vtkSMProxy* lut, vtkSMProxy* sof)
    {
      vtkSMPropertyHelper(lut, "ColorSpace")
        .Set(colorSpace(preset.value("ColorSpace").toString("RGB")));
      vtkSMPropertyHelper(lut, "RGBPoints").Set(rgb.data(), static_cast<unsigned int>(rgb.size()));
      vtkSMPropertyHelper(sof, "Points")
        .Set(opacity.data(), static_cast<unsigned int>(opacity.size()));
      return QString();
    });
}

QString applyTransferFunction2D(pqDataRepresentation* repr, const QString& array,
  const QString& boxesText, const QString& label, bool undoable)
{
  if (!repr)
    return "there is no representation of the volume in the active view";
  const QJsonObject pv = QJsonDocument::fromJson(boxesText.toUtf8()).object();
  const auto boxes = numbers(pv.value("Boxes"));
  const auto range = numbers(pv.value("Range"));
  const auto dims = numbers(pv.value("OutputDimensions"));
  if (boxes.empty() || boxes.size() % 8 != 0 || range.size() != 4 || dims.size() != 2)
    return "the design's 2D transfer function has no ParaView boxes (Boxes, Range, "
           "OutputDimensions)";
  if (!repr->getProxy()->GetProperty("UseTransfer2D") ||
    !repr->getProxy()->GetProperty("TransferFunction2D"))
    return "the active representation has no 2D transfer function (ParaView 5.11's volume "
           "representation of image data has)";
  return applyMaps(repr, array, label, undoable, true,
    [&](vtkSMProxy* reprProxy, vtkSMProxy*, vtkSMProxy*)
    {
      vtkSMProxy* tf2 = vtkSMPropertyHelper(reprProxy, "TransferFunction2D").GetAsProxy();
      if (!tf2)
        return QString("the representation has no TransferFunction2D for '%1'").arg(array);
      vtkSMPropertyHelper(reprProxy, "UseGradientForTransfer2D").Set(1);
      vtkSMPropertyHelper mode(reprProxy, "VolumeRenderingMode");
      if (mode.GetAsInt() == 1) // Ray Cast Only: vtkFixedPointVolumeRayCastMapper has no 2D TFs
        mode.Set(0);            // Smart
      vtkSMPropertyHelper(tf2, "Range").Set(range.data(), 4);
      const int size[2] = { static_cast<int>(dims[0]), static_cast<int>(dims[1]) };
      vtkSMPropertyHelper(tf2, "OutputDimensions").Set(size, 2);
      vtkSMPropertyHelper(tf2, "Boxes").Set(boxes.data(), static_cast<unsigned int>(boxes.size()));
      tf2->UpdateVTKObjects();
      return QString();
    });
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

vtkSmartPointer<vtkSMSourceProxy> newFilter(const char* name, vtkSMSourceProxy* input, int port)
{
  vtkSmartPointer<vtkSMSourceProxy> filter;
  filter.TakeReference(
    vtkSMSourceProxy::SafeDownCast(input->GetSessionProxyManager()->NewProxy("filters", name)));
  if (filter)
  {
    vtkSMPropertyHelper(filter, "Input").Set(input, static_cast<unsigned int>(port));
    filter->UpdateVTKObjects();
  }
  return filter;
}

vtkSmartPointer<vtkDataObject> fetch(vtkSMSourceProxy* producer, int port)
{
  vtkSmartPointer<vtkSMProxy> mover;
  mover.TakeReference(producer->GetSessionProxyManager()->NewProxy("misc", "DataMover"));
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

QImage imageOf(vtkDataObject* data)
{
  auto* image = vtkImageData::SafeDownCast(data);
  vtkDataArray* rgb = image ? image->GetPointData()->GetArray("Image") : nullptr;
  if (!rgb || rgb->GetNumberOfComponents() < 3)
    return {};
  int dims[3];
  image->GetDimensions(dims);
  const bool unit = rgb->GetDataType() == VTK_FLOAT || rgb->GetDataType() == VTK_DOUBLE;
  QImage out(dims[0], dims[1], QImage::Format_RGB32);
  for (int y = 0; y < dims[1]; ++y)
    for (int x = 0; x < dims[0]; ++x)
    {
      const vtkIdType i = static_cast<vtkIdType>(dims[1] - 1 - y) * dims[0] + x; // VTK rows go up
      int c[3];
      for (int k = 0; k < 3; ++k)
      {
        const double v = rgb->GetComponent(i, k);
        c[k] = static_cast<int>(std::lround(std::clamp(unit ? 255 * v : v, 0.0, 255.0)));
      }
      out.setPixel(x, y, qRgb(c[0], c[1], c[2]));
    }
  return out;
}

QJsonArray fieldNumbers(vtkTable* table, const char* name)
{
  QJsonArray out;
  vtkDataArray* a = table ? table->GetFieldData()->GetArray(name) : nullptr;
  for (vtkIdType i = 0; a && i < a->GetNumberOfValues(); ++i)
    out.append(a->GetVariantValue(i).ToDouble());
  return out;
}

QString fieldText(vtkTable* table, const char* name)
{
  auto* a =
    table ? vtkStringArray::SafeDownCast(table->GetFieldData()->GetAbstractArray(name)) : nullptr;
  return a && a->GetNumberOfValues() > 0 ? QString::fromStdString(a->GetValue(0)) : QString();
}

} // namespace ddgpanel
