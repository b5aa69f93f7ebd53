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
#include <vtkObjectFactory.h>
#include <vtkPVDataMover.h>
#include <vtkPointData.h>
#include <vtkSMDDGScene.h>
#include <vtkSMParaViewPipelineControllerWithRendering.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMProxyManager.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSMSourceProxy.h>
#include <vtkSMUndoElement.h>
#include <vtkSMUndoStackBuilder.h>
#include <vtkSMViewProxy.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkWeakPointer.h>

#include <QCoreApplication>
#include <QJsonArray>
#include <QJsonDocument>

#include <algorithm>
#include <cmath>

namespace ddgpanel
{

QJsonObject viewJson(pqRenderView* view, pqDataRepresentation* repr, int maxSide)
{
  const std::string text = vtkSMDDGScene::ViewJSON(
    view ? view->getProxy() : nullptr, repr ? repr->getProxy() : nullptr, maxSide);
  return QJsonDocument::fromJson(QByteArray::fromStdString(text)).object();
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

QString applyPreset(pqDataRepresentation* repr, const QString& array, const QString& presetText,
  const QString& label, bool undoable)
{
  if (!repr)
    return "there is no representation of the volume in the active view";
  if (undoable)
    BEGIN_UNDO_SET(label); // an undo set with no change (an error) is not pushed
  const std::string error = vtkSMDDGScene::Apply1D(
    repr->getProxy(), array.toUtf8().constData(), presetText.toUtf8().constData());
  if (undoable)
    END_UNDO_SET();
  if (error.empty())
    repr->renderViewEventually();
  return QString::fromStdString(error);
}

QString applyTransferFunction2D(pqDataRepresentation* repr, const QString& array,
  const QString& boxesText, const QString& label, bool undoable)
{
  if (!repr)
    return "there is no representation of the volume in the active view";
  const QByteArray boxes = boxesText.toUtf8();
  if (undoable)
    BEGIN_UNDO_SET(label);
  std::string error =
    vtkSMDDGScene::Apply2D(repr->getProxy(), array.toUtf8().constData(), boxes.constData());
  if (error.empty())
  {
    // ParaView's Color Map Editor follows UseTransfer2D: when it shows its 2D editor it
    // computes a 2D histogram and sets the TF's Range and OutputDimensions from it (queued,
    // after a render). Let it happen here, inside this undo step, then write ours again.
    if (auto* view = repr->getView())
      view->forceRender();
    QCoreApplication::processEvents();
    error = vtkSMDDGScene::WriteTransferFunction2D(repr->getProxy(), boxes.constData());
  }
  if (undoable)
    END_UNDO_SET();
  if (error.empty())
    repr->renderViewEventually();
  return QString::fromStdString(error);
}

namespace
{
/// Sets a render view's camera back on Undo and forth on Redo (ParaView's undo stack leaves
/// camera properties out). A vtkSMUndoElement with the view's session: vtkSMUndoStack takes
/// every element of a set to be one.
class CameraUndo : public vtkSMUndoElement
{
public:
  static CameraUndo* New();
  vtkTypeMacro(CameraUndo, vtkSMUndoElement);
  vtkWeakPointer<vtkSMProxy> View;
  std::string Before, After; ///< view JSON

  int Undo() override { return this->Set(this->Before); }
  int Redo() override { return this->Set(this->After); }

private:
  int Set(const std::string& json)
  {
    if (!this->View)
      return 0;
    const bool ok = vtkSMDDGScene::SetCamera(this->View, json.c_str()).empty();
    if (auto* view = vtkSMViewProxy::SafeDownCast(this->View))
      view->StillRender();
    return ok ? 1 : 0;
  }
};
vtkStandardNewMacro(CameraUndo);
} // namespace

QString setCamera(pqRenderView* view, const QJsonObject& viewJson, bool undoable)
{
  if (!view)
    return "there is no render view";
  vtkNew<CameraUndo> undo;
  undo->View = view->getProxy();
  undo->SetSession(view->getProxy()->GetSession());
  undo->Before = vtkSMDDGScene::ViewJSON(view->getProxy(), nullptr, 0);
  // all the picture shows, in the view's own shape (a view narrower than the picture would cut it)
  undo->After = vtkSMDDGScene::FitToView(view->getProxy(), jsonText(viewJson).toUtf8().constData());
  const std::string error = vtkSMDDGScene::SetCamera(view->getProxy(), undo->After.c_str());
  if (!error.empty())
    return QString::fromStdString(error);
  if (undoable)
    if (auto* stack = pqApplicationCore::instance()->getUndoStack())
      stack->addToActiveUndoSet(undo);
  view->render();
  return {};
}

QString currentPreset(pqDataRepresentation* repr)
{
  return repr ? QString::fromStdString(vtkSMDDGScene::CurrentPreset(repr->getProxy())) : QString();
}

vtkSmartPointer<vtkSMSourceProxy> newFilter(const char* name, vtkSMSourceProxy* input, int port)
{
  const NoUndo quiet; // the panel's own filter
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

NoUndo::NoUndo()
{
  if (auto* builder = vtkSMProxyManager::GetProxyManager()->GetUndoStackBuilder())
  {
    this->Was = builder->GetIgnoreAllChanges();
    builder->SetIgnoreAllChanges(true);
  }
}

NoUndo::~NoUndo()
{
  if (auto* builder = vtkSMProxyManager::GetProxyManager()->GetUndoStackBuilder())
    builder->SetIgnoreAllChanges(this->Was);
}

vtkSmartPointer<vtkDataObject> fetch(vtkSMSourceProxy* producer, int port)
{
  const NoUndo quiet; // the data mover is the panel's
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

QVector<QImage> sheetCells(const QImage& sheet, int count, int side)
{
  constexpr int gap = 2; // as Core's tileRenders lays them out
  QVector<QImage> cells;
  const int cols = sheet.isNull() ? 0 : (sheet.width() - gap) / (side + gap);
  for (int k = 0; k < count && cols > 0; ++k)
  {
    const int x = gap + (k % cols) * (side + gap), y = gap + (k / cols) * (side + gap);
    if (y + side > sheet.height())
      break;
    cells.push_back(sheet.copy(x, y, side, side));
  }
  return cells;
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
