// pqDDGDesignState.cxx: the Design Gallery panel's state: filters on the volume, outline, designs,
// the match of the query's picture.
#include "pqDDGDesignState.h"

#include "pqDDGScene.h"

#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDDGReconstructTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkImageData.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSMSourceProxy.h>
#include <vtkTable.h>

#include <QCoreApplication>
#include <QJsonDocument>
#include <QScopedValueRollback>

#include <algorithm>
#include <limits>
#include <vector>

pqDDGDesignState::pqDDGDesignState(QObject* parent)
  : QObject(parent)
{
}

pqDDGDesignState::~pqDDGDesignState() = default;

// --- the volume and its model --------------------------------------------------------------------

void pqDDGDesignState::report(const QString& text, bool error)
{
  this->LastMessage = text;
  if (error && !this->HoldWarnings) // in Output Messages too, as a warning (a filter's own error
                                    // comes as an error)
    vtkOutputWindow::GetInstance()->DisplayWarningText(
      ("Design Gallery: " + text + "\n").toUtf8().constData());
  Q_EMIT this->statusChanged(text, error);
}

void pqDDGDesignState::setVolume(vtkSMSourceProxy* source, const QString& array)
{
  this->keepVolumeState();
  this->clearModel();
  this->Source = source;
  this->Array = array;
}

vtkSMSourceProxy* pqDDGDesignState::volume() const
{
  return this->Source;
}

QString pqDDGDesignState::volumeName() const
{
  if (!this->Source)
    return {};
  const char* name = this->Source->GetSessionProxyManager()->GetProxyName("sources", this->Source);
  return QString::fromUtf8(name ? name : "");
}

QJsonObject pqDDGDesignState::currentView(int maxSide) const
{
  return this->View ? this->View(maxSide) : QJsonObject();
}

void pqDDGDesignState::clearModel()
{
  this->GalleryProxy = this->QueryProxy = this->DesignProxy = nullptr;
  this->Loaded = false;
  this->Boxes.clear();
  this->Steps = this->LockSteps = QJsonArray();
  this->Locked.clear();
  this->Current = Design();
  this->Pins.clear();
  this->MatchProxy = nullptr;
  this->QueryPicture.clear();
  this->QueryName.clear();
  this->Queried = false;
  this->QueryPSNR = std::numeric_limits<double>::quiet_NaN();
  this->QueryKind = QJsonObject();
  this->QueryNeighbours.clear();
  this->QueryThumbnails.clear();
  this->QueryNeighbourPSNR.clear();
  this->LastMatch = Match();
  Q_EMIT this->modelCleared();
  Q_EMIT this->matchChanged();
}

bool pqDDGDesignState::loadModel(const QString& directory)
{
  const ddgpanel::NoUndo quiet; // the panel's own proxies (its steps are Apply's alone)
  if (!this->Source || this->Array.isEmpty())
    return false;
  // another bundle that cannot be loaded gives the one loaded before back, as it was left
  Kept before;
  bool hadModel = false;
  if (this->Loaded && !this->ModelDirectory.isEmpty() && this->ModelDirectory != directory)
  {
    this->keepVolumeState();
    hadModel = this->takeKept(this->ModelDirectory, before);
  }
  Kept kept;
  bool restore = false;
  {
    const QScopedValueRollback<bool> hold(this->HoldWarnings, hadModel); // until the bundle is in
    auto failed = [&]()
    {
      this->HoldWarnings = false; // what follows reaches Output Messages
      if (!hadModel)
        return false;
      const QString why = this->LastMessage;
      this->putKept(before);
      if (this->loadModel(before.ModelDirectory))
        this->report(
          tr("%1 The model loaded before stays: '%2'.").arg(why, before.ModelDirectory), true);
      return false;
    };
    this->clearModel();
    this->ModelDirectory = directory;
    if (directory.isEmpty())
    {
      this->report(
        tr("No model directory given: Load a bundle of this volume or build one."), true);
      return failed();
    }
    const int port = 0;
    this->GalleryProxy = ddgpanel::newFilter("DDGDesignGallery", this->Source, port);
    this->QueryProxy = ddgpanel::newFilter("DDGQuery", this->Source, port);
    this->DesignProxy = ddgpanel::newFilter("DDGDesign", this->Source, port);
    if (!this->GalleryProxy || !this->QueryProxy || !this->DesignProxy)
    {
      this->HoldWarnings = false; // this reaches Output Messages
      this->report(tr("The DesignGallery plugin is not loaded on the server (Tools > Manage "
                      "Plugins: load it on the remote side too)."),
        true);
      return false;
    }
    for (vtkSMSourceProxy* p :
      { this->GalleryProxy.Get(), this->QueryProxy.Get(), this->DesignProxy.Get() })
    {
      vtkSMPropertyHelper(p, "ModelDirectory").Set(directory.toUtf8().constData());
      vtkSMPropertyHelper(p, "SelectInputScalars")
        .SetInputArrayToProcess(vtkDataObject::POINT, this->Array.toUtf8().constData());
      p->UpdateVTKObjects();
    }
    restore = this->takeKept(directory, kept);
    this->Boxes = restore ? kept.Boxes : QVector<QRectF>{ QRectF() }; // else the whole outline
    if (restore)
      this->Seed = kept.Seed;
    this->Loaded = true;
    this->refreshOutline();
    if (!this->Loaded)
      return failed();
  }
  if (restore)
    this->restoreVolumeState(kept);
  return true;
}

void pqDDGDesignState::setBusy(bool busy)
{
  this->Busy = busy;
  if (busy)
    this->Cancelled = false;
  Q_EMIT this->busyChanged(busy);
}

bool pqDDGDesignState::hasVolume()
{
  if (!this->Source || this->Array.isEmpty())
  {
    this->report(tr("Select a volume first."), true);
    return false;
  }
  return true;
}

bool pqDDGDesignState::ready(bool needDesign)
{
  if (!this->hasVolume())
    return false;
  if (!this->Loaded)
  {
    this->report(tr("Load or build a model for this volume first."), true);
    return false;
  }
  if (needDesign && this->Steps.isEmpty())
  {
    this->report(tr("Pick a design on the outline or query with a picture first."), true);
    return false;
  }
  return true;
}

// --- the outline ---------------------------------------------------------------------------------

void pqDDGDesignState::refreshOutline(bool announce)
{
  const ddgpanel::NoUndo quiet; // the panel's own proxies (its steps are Apply's alone)
  if (!this->ready())
    return;
  const QRectF box = this->Boxes.isEmpty() ? QRectF() : this->Boxes.last();
  const double b[4] = { box.left(), box.top(), box.right(), box.bottom() };
  vtkSMPropertyHelper(this->GalleryProxy, "Box").Set(b, 4);
  vtkSMPropertyHelper(this->GalleryProxy, "Count").Set(ThumbnailCount);
  vtkSMPropertyHelper(this->GalleryProxy, "ThumbnailSize").Set(ThumbnailSize);
  vtkSMPropertyHelper(this->GalleryProxy, "Seed").Set(this->Seed);
  // the volume's default view (the whole volume in sight), or the view's camera once asked for
  const QJsonObject scene = this->currentView(ThumbnailSize);
  const QJsonObject view = this->ThumbnailsAtCamera ? scene : QJsonObject();
  vtkSMPropertyHelper(this->GalleryProxy, "ViewJSON")
    .Set(view.isEmpty() ? "" : ddgpanel::jsonText(view).toUtf8().constData());
  this->ThumbnailView = view;
  // lit as the volume is shown (its representation's Shade and coefficients; {}: Shade off)
  this->ThumbnailLighting = scene.value("lighting").toObject();
  if (this->GalleryProxy->GetProperty("LightingJSON"))
    vtkSMPropertyHelper(this->GalleryProxy, "LightingJSON")
      .Set(scene.isEmpty() ? "" : ddgpanel::jsonText(this->ThumbnailLighting).toUtf8().constData());
  this->GalleryProxy->UpdateVTKObjects();
  this->setBusy(true);
  this->GalleryProxy->UpdatePipeline();
  this->setBusy(false);
  vtkSmartPointer<vtkTable> table = vtkTable::SafeDownCast(ddgpanel::fetch(this->GalleryProxy, 1));
  auto sheet = ddgpanel::fetch(this->GalleryProxy, 0);
  if (!table)
  {
    const QString error = ddgpanel::lastError(this->GalleryProxy);
    this->Loaded = false;
    this->report(error.contains("another volume")
        ? tr("This model belongs to another volume: %1").arg(error)
        : tr("No usable model in '%1': %2. Load a bundle of this volume or build one.")
            .arg(this->ModelDirectory, error),
      true);
    Q_EMIT this->outlineFailed(this->LastMessage);
    return;
  }
  vtkDataArray* xs = vtkDataArray::SafeDownCast(table->GetColumnByName("X"));
  vtkDataArray* ys = vtkDataArray::SafeDownCast(table->GetColumnByName("Y"));
  vtkDataArray* cells = vtkDataArray::SafeDownCast(table->GetColumnByName("Thumbnail"));
  if (!xs || !ys || !cells)
    return;
  Outline outline;
  outline.Points.resize(static_cast<int>(table->GetNumberOfRows()));
  QVector<int> thumbRows(ThumbnailCount, -1);
  for (vtkIdType i = 0; i < table->GetNumberOfRows(); ++i)
  {
    outline.Points[static_cast<int>(i)] = QPointF(xs->GetTuple1(i), ys->GetTuple1(i));
    const int cell = static_cast<int>(cells->GetTuple1(i));
    if (cell >= 0 && cell < ThumbnailCount)
      thumbRows[cell] = static_cast<int>(i);
  }
  // thumbnails: cells of the sheet, row by row
  const QVector<QImage> images =
    ddgpanel::sheetCells(ddgpanel::imageOf(sheet), ThumbnailCount, ThumbnailSize);
  for (int k = 0; k < images.size(); ++k)
  {
    if (thumbRows[k] < 0)
      continue;
    outline.ThumbnailRows.push_back(thumbRows[k]);
    outline.Thumbnails.push_back(images[k]);
  }
  const QJsonArray shown = ddgpanel::fieldNumbers(table, "Box");
  if (shown.size() == 4)
  {
    outline.Box = QRectF(QPointF(shown[0].toDouble(), shown[1].toDouble()),
      QPointF(shown[2].toDouble(), shown[3].toDouble()))
                    .normalized();
    outline.BoxKnown = true;
    this->Boxes.last() = outline.Box;
  }
  Q_EMIT this->outlineChanged(outline);
  if (announce)
    this->report(tr("%1 designs of '%2'; %3 thumbnails. Click one, or query with a picture.")
                   .arg(outline.Points.size())
                   .arg(this->volumeName())
                   .arg(outline.ThumbnailRows.size()));
}

void pqDDGDesignState::drillIn(const QRectF& box)
{
  if (!this->ready())
    return;
  this->Boxes.push_back(box.normalized());
  this->refreshOutline();
}

void pqDDGDesignState::back()
{
  if (this->Boxes.size() > 1)
    this->Boxes.pop_back();
  else if (!this->Boxes.isEmpty())
    this->Boxes.last() = QRectF(); // back out to the whole outline
  this->refreshOutline();
}

void pqDDGDesignState::resample()
{
  ++this->Seed;
  this->refreshOutline();
}

void pqDDGDesignState::setShownBox(const QRectF& box)
{
  if (!this->Boxes.isEmpty())
  {
    this->Boxes.last() = box;
    this->refreshOutline();
  }
}

// --- designs -------------------------------------------------------------------------------------

void pqDDGDesignState::pick(int row)
{
  if (!this->ready())
    return;
  this->setSteps(QJsonArray{ pickStep(row) });
}

void pqDDGDesignState::navigate(const QList<int>& pins, double u, double v)
{
  if (pins.size() < 2 || !this->ready())
    return;
  QJsonArray latents;
  for (int k : pins)
    if (k >= 0 && k < this->Pins.size())
      latents.append(this->Pins[k].Latent);
  this->setSteps(QJsonArray{ blendStep(latents, u, v) });
}

void pqDDGDesignState::edit(int cluster, double hue, double visibility)
{
  if (!this->ready(true))
    return;
  if (cluster < 0)
  {
    this->report(tr("This design shows no colour to edit."), true);
    return;
  }
  const QJsonArray before = this->Steps;
  this->Steps = appendStep(this->Steps, editStep(this->Current.View, cluster, hue, visibility));
  if (!this->updateDesign())
  {
    this->Steps = before; // the edit is dropped, the design stays
    this->updateDesign();
  }
}

void pqDDGDesignState::moveAlongAxes(const QVector<double>& steps)
{
  if (!this->ready(true))
    return;
  this->Steps = appendStep(this->Steps, axesStep(steps));
  this->updateDesign();
}

void pqDDGDesignState::setLockedRegions(const QVector<int>& regions)
{
  this->Locked = regions;
  if (!regions.isEmpty() && this->LockSteps.isEmpty())
    this->LockSteps = this->Steps; // the regions stay as in the design shown now
  if (regions.isEmpty())
    this->LockSteps = QJsonArray();
  this->updateDesign();
}

bool pqDDGDesignState::setSteps(const QJsonArray& steps, bool newPath)
{
  this->Steps = steps;
  if (newPath)
    Q_EMIT this->pathStarted();
  return this->updateDesign();
}

bool pqDDGDesignState::updateDesign()
{
  const ddgpanel::NoUndo quiet; // the panel's own proxies (its steps are Apply's alone)
  if (!this->ready(true))
    return false;
  this->Current.View = this->currentView(PreviewSide);
  if (this->Current.View.isEmpty())
  {
    this->report(tr("Open a render view first."), true);
    return false;
  }
  vtkSMPropertyHelper(this->DesignProxy, "History")
    .Set(historyText(this->Steps).toUtf8().constData());
  vtkSMPropertyHelper(this->DesignProxy, "ViewJSON")
    .Set(ddgpanel::jsonText(this->Current.View).toUtf8().constData());
  vtkSMPropertyHelper(this->DesignProxy, "ComputeFidelity").Set(1);
  const std::vector<int> locked(this->Locked.begin(), this->Locked.end());
  vtkSMPropertyHelper(this->DesignProxy, "LockedRegions")
    .Set(locked.data(), static_cast<unsigned int>(locked.size()));
  vtkSMPropertyHelper(this->DesignProxy, "LockHistory")
    .Set(locked.empty() ? "" : historyText(this->LockSteps).toUtf8().constData());
  this->DesignProxy->UpdateVTKObjects();
  this->DesignProxy->UpdatePipeline();
  vtkSmartPointer<vtkTable> table = vtkTable::SafeDownCast(ddgpanel::fetch(this->DesignProxy, 1));
  if (!table)
  {
    this->report(
      tr("The design could not be made: %1").arg(ddgpanel::lastError(this->DesignProxy)), true);
    return false;
  }
  Design& d = this->Current;
  d.Preview = ddgpanel::imageOf(ddgpanel::fetch(this->DesignProxy, 0));
  d.Latent = ddgpanel::fieldNumbers(table, "Latent");
  d.Preset = ddgpanel::fieldText(table, "Preset");
  if (d.Preset.isEmpty())
    d.Preset = ddgpanel::fieldText(table, "TransferFunction2D");
  d.ParaView2D = ddgpanel::fieldText(table, "ParaViewTransferFunction2D");
  d.Slicer = ddgpanel::fieldText(table, "Slicer");
  d.Position = ddgpanel::fieldNumbers(table, "Position");
  d.Fidelity = ddgpanel::fieldNumbers(table, "Fidelity");
  d.Regions = ddgpanel::fieldNumbers(table, "Regions");
  d.Row = -1;
  if (this->Steps.size() == 1 && this->Steps[0].toObject().value("action") == "pick")
    d.Row = this->Steps[0].toObject().value("row").toInt();
  // colour clusters: what edits act on
  d.ClusterColours.clear();
  d.ClusterShares.clear();
  vtkDataArray* share = vtkDataArray::SafeDownCast(table->GetColumnByName("Share"));
  vtkDataArray* r = vtkDataArray::SafeDownCast(table->GetColumnByName("R"));
  vtkDataArray* g = vtkDataArray::SafeDownCast(table->GetColumnByName("G"));
  vtkDataArray* b = vtkDataArray::SafeDownCast(table->GetColumnByName("B"));
  for (vtkIdType k = 0; share && r && g && b && k < table->GetNumberOfRows(); ++k)
  {
    d.ClusterColours.push_back(QColor::fromRgbF(r->GetTuple1(k), g->GetTuple1(k), b->GetTuple1(k)));
    d.ClusterShares.push_back(share->GetTuple1(k));
  }
  Q_EMIT this->designChanged();
  this->report(tr("Design ready: Apply writes its transfer function into the volume's maps."));
  return true;
}

// --- pins ----------------------------------------------------------------------------------------

void pqDDGDesignState::pin()
{
  if (!this->ready(true) || this->Current.Latent.isEmpty())
    return;
  this->Pins.push_back({ this->Steps, this->Current.Latent, this->Current.Preview });
  Q_EMIT this->pinAdded();
}

void pqDDGDesignState::unpin(QVector<int> rows)
{
  std::sort(rows.begin(), rows.end(), std::greater<int>());
  for (int r : rows)
    if (r >= 0 && r < this->Pins.size())
      this->Pins.removeAt(r);
}
