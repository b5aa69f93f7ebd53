// pqDDGDesignStateMatch.cxx: the panel state's match of the query's picture (DDG Reconstruct
// Transfer Function with MatchPicture) and what it found (pqDDGDesignState).
#include "pqDDGDesignState.h"
#include "pqDDGScene.h"
#include <QCoreApplication>
#include <QFileInfo>
#include <QJsonDocument>
#include <QPainter>
#include <QRegion>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDDGReconstructTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkImageData.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkSMDDGScene.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSMSourceProxy.h>
#include <vtkTable.h>

// --- matching the query's picture ---------------------------------------------------------------

#ifndef DDG_DATA_DIR
#define DDG_DATA_DIR ""
#endif
namespace
{
/// A 1-component 8-bit array of an image output as a grey QImage (null when there is none).
QImage maskOf(vtkDataObject* data, const char* name)
{
  auto* image = vtkImageData::SafeDownCast(data);
  vtkDataArray* a = image ? image->GetPointData()->GetArray(name) : nullptr;
  if (!a)
    return {};
  int dims[3];
  image->GetDimensions(dims);
  QImage out(dims[0], dims[1], QImage::Format_Grayscale8);
  for (int y = 0; y < dims[1]; ++y)
  {
    uchar* row = out.scanLine(y);
    for (int x = 0; x < dims[0]; ++x) // VTK rows go up
      row[x] = static_cast<uchar>(
        a->GetComponent(static_cast<vtkIdType>(dims[1] - 1 - y) * dims[0] + x, 0));
  }
  return out;
}

double first(const QJsonArray& values, int k = 0)
{
  return values.size() > k ? values[k].toDouble() : std::numeric_limits<double>::quiet_NaN();
}
} // namespace

bool pqDDGDesignState::match(bool fromCurrentCamera, bool otherVolume)
{
  const ddgpanel::NoUndo quiet;         // the panel's own proxies (its steps are Apply's alone)
  if (this->Busy || !this->hasVolume()) // no model needed: without a design, from grey
    return false;
  if (this->QueryPicture.isEmpty())
  {
    this->report(tr("Query with a picture first: Match fits a transfer function to the "
                    "query's picture."),
      true);
    return false;
  }
  if (!this->MatchProxy)
    this->MatchProxy = ddgpanel::newFilter("DDGReconstructTransferFunction", this->Source, 0);
  if (!this->MatchProxy || !this->MatchProxy->GetProperty("MatchPicture") ||
    !this->MatchProxy->GetProperty("CarryLook") || !this->MatchProxy->GetProperty("KindNetwork"))
  {
    this->MatchProxy = nullptr;
    this->report(tr("The DesignGallery plugin on the server cannot match pictures (load this "
                    "version of it on the server too)."),
      true);
    return false;
  }
  const QJsonObject view = this->currentView(PreviewSide);
  const bool twoD = !this->Current.ParaView2D.isEmpty();
  vtkSMSourceProxy* p = this->MatchProxy;
  vtkSMPropertyHelper(p, "SelectInputScalars")
    .SetInputArrayToProcess(vtkDataObject::POINT, this->Array.toUtf8().constData());
  vtkSMPropertyHelper(p, "MatchPicture").Set(1);
  vtkSMPropertyHelper(p, "CarryLook").Set(otherVolume ? 1 : 0);
  vtkSMPropertyHelper(p, "TargetImageData").Set(this->QueryPicture.toBase64().constData());
  // the picture's camera: the current one (its size becomes the picture's), or estimated from
  // ParaView's reset camera; the representation's opacity unit distance either way. The carried
  // look reads only the view's lighting: it is fitted under the Shade the volume is shown with
  vtkSMPropertyHelper(p, "ViewJSON")
    .Set(fromCurrentCamera || (otherVolume && !view.isEmpty())
        ? ddgpanel::jsonText(view).toUtf8().constData()
        : "");
  vtkSMPropertyHelper(p, "EstimateCamera").Set(0);
  vtkSMPropertyHelper(p, "OpacityUnitDistance")
    .Set(view.value("opacity_unit_distance").toDouble(0.0));
  // from the design shown (the query's, a nearest design picked, an edit: its TF at the current
  // camera); 2D models fit a 2D TF from grey; the carried look starts from the picture's colours
  // matched to the regions (measured better than from the query's design on the brain pairs)
  vtkSMPropertyHelper(p, "TwoD").Set(twoD ? 1 : 0);
  vtkSMPropertyHelper(p, "InitialTransferFunction")
    .Set(twoD || otherVolume ? "" : this->Current.Preset.toUtf8().constData());
  // the carried look's picture is checked for another kind of volume by the project's network
  vtkSMPropertyHelper(p, "KindNetwork")
    .Set(otherVolume ? pqDDGDesignState::kindNetwork().toUtf8().constData() : "");
  vtkSMPropertyHelper(p, "PreviewEvery").Set(10);
  p->UpdateVTKObjects();

  this->LastMatch = Match();
  Q_EMIT this->matchChanged();
  this->report(otherVolume ? tr("Carrying the look of another volume's picture over (Cancel "
                                "stops it)...")
                           : tr("Matching the picture (Cancel stops it)..."));
  this->setBusy(true);
  // progress and cancel: ParaView processes events while the filter reports progress; in a
  // builtin session the filter is reachable here, so Cancel sets its AbortExecute and its
  // preview shows (with a remote server the progress bar follows pqProgressManager and the
  // match runs to its end)
  auto* filter = vtkDDGReconstructTransferFunction::SafeDownCast(p->GetClientSideObject());
  struct Watch
  {
    pqDDGDesignState* Self;
    vtkMTimeType PreviewTime = 0;
  } watch{ this };
  vtkNew<vtkCallbackCommand> onProgress;
  onProgress->SetClientData(&watch);
  onProgress->SetCallback(
    [](vtkObject* caller, unsigned long, void* data, void*)
    {
      auto* w = static_cast<Watch*>(data);
      auto* f = static_cast<vtkDDGReconstructTransferFunction*>(caller);
      QImage preview;
      if (vtkImageData* image = f->GetPreview())
        if (image->GetMTime() != w->PreviewTime)
        {
          w->PreviewTime = image->GetMTime();
          preview = ddgpanel::imageOf(image);
        }
      const char* stage = f->GetProgressText();
      Q_EMIT w->Self->matchProgress(
        QString::fromUtf8(stage ? stage : ""), f->GetProgress(), preview);
      QCoreApplication::processEvents();
      if (w->Self->Cancelled)
        f->SetAbortExecute(1);
    });
  const unsigned long observer =
    filter ? filter->AddObserver(vtkCommand::ProgressEvent, onProgress) : 0;
  p->UpdatePipeline();
  if (filter)
    filter->RemoveObserver(observer);
  const bool cancelled = this->Cancelled;
  this->setBusy(false);

  const QString error = ddgpanel::lastError(p);
  vtkSmartPointer<vtkTable> table = vtkTable::SafeDownCast(ddgpanel::fetch(p, 0));
  vtkSmartPointer<vtkDataObject> images = table ? ddgpanel::fetch(p, 1) : nullptr;
  vtkSMPropertyHelper(p, "TargetImageData").Set(""); // do not keep megabytes around
  vtkSMPropertyHelper(p, "InitialTransferFunction").Set("");
  p->UpdateVTKObjects();
  if (cancelled || error == "cancelled")
  {
    // what the user asked for: said in the panel, not as a warning in Output Messages
    this->report(tr("Match cancelled: nothing was applied, the scene is unchanged."), false);
    return false;
  }
  if (!table || !error.isEmpty())
  {
    const QString text =
      tr("The match failed: %1. Nothing was applied, the scene is unchanged.%2")
        .arg(error.isEmpty() ? tr("no transfer function (see the Output Messages)") : error)
        .arg(!otherVolume && error.contains("no camera explains")
            ? tr(" If the picture shows another volume, tick \"the picture shows another "
                 "volume\" and Match again.")
            : QString());
    this->report(text, true);
    return false;
  }
  Match& m = this->LastMatch;
  m.Preset = ddgpanel::fieldText(table, "Preset");
  if (m.Preset.isEmpty())
    m.Preset = ddgpanel::fieldText(table, "TransferFunction2D");
  m.ParaView2D = ddgpanel::fieldText(table, "ParaViewTransferFunction2D");
  m.View = QJsonDocument::fromJson(ddgpanel::fieldText(table, "View").toUtf8()).object();
  m.Carried = otherVolume;
  if (otherVolume)
  {
    const QJsonArray rows = ddgpanel::fieldNumbers(table, "Regions");
    for (int k = 0; k + 5 < rows.size(); k += 6)
      m.Regions.push_back({ rows[k].toDouble(), rows[k + 1].toDouble(), rows[k + 2].toDouble(),
        rows[k + 3].toDouble(), rows[k + 4].toDouble(), rows[k + 5].toDouble() });
    const QJsonArray distance = ddgpanel::fieldNumbers(table, "ColourDistance");
    m.DistanceStart = first(distance, 0);
    m.DistanceEnd = first(distance, 1);
    const QJsonArray agreement = ddgpanel::fieldNumbers(table, "ShapeAgreement");
    m.ShapeAgreement = first(agreement, 0);
    m.ShapesAgree = first(agreement, 1) > 0.5;
    m.Kind = QJsonDocument::fromJson(ddgpanel::fieldText(table, "Kind").toUtf8()).object();
  }
  m.CameraEstimated = first(ddgpanel::fieldNumbers(table, "CameraEstimated")) != 0;
  m.LightingEstimated = first(ddgpanel::fieldNumbers(table, "LightingEstimated")) != 0;
  m.Overlap = otherVolume ? 0.0 : first(ddgpanel::fieldNumbers(table, "Overlap"));
  m.FitPSNR = first(ddgpanel::fieldNumbers(table, "FitPSNR"));
  const QJsonArray psnr = ddgpanel::fieldNumbers(table, "PicturePSNR");
  m.PSNRBefore = first(psnr, 0);
  m.PSNRAfter = first(psnr, 1);
  for (const auto& t : ddgpanel::fieldNumbers(table, "Timings"))
    m.Timings.push_back(t.toDouble());
  m.Iterations = static_cast<int>(first(ddgpanel::fieldNumbers(table, "Iterations")));
  m.Render = ddgpanel::imageOf(images);
  m.Overlay = maskOf(images, "Overlay");
  const QJsonArray crop = ddgpanel::fieldNumbers(table, "Crop");
  if (crop.size() == 4)
    m.Crop = QRect(crop[0].toInt(), crop[1].toInt(), crop[2].toInt(), crop[3].toInt());
  m.Picture = this->QueryName;
  m.Steps = this->Steps;
  m.FromCurrentCamera = fromCurrentCamera;
  Q_EMIT this->matchChanged();
  if (otherVolume)
  {
    this->report(
      tr("Carried the look of another volume's picture over in %1 s: %2 regions of "
         "this volume matched with its colours (colour distance %3 \u2192 %4). %5")
        .arg(m.Timings.value(0), 0, 'f', 1)
        .arg(m.Regions.size())
        .arg(m.DistanceStart, 0, 'f', 1)
        .arg(m.DistanceEnd, 0, 'f', 1)
        .arg((m.ShapesAgree
                 ? QString()
                 : tr("The shapes disagree: this volume's silhouettes take the picture's object's "
                      "shape at %1 only (under 0.6): it may show a volume of another kind. ")
                     .arg(m.ShapeAgreement, 0, 'f', 2)) +
          (m.kindDiffers() ? m.kindText() + ". " : QString()) +
          (m.ShapesAgree && !m.kindDiffers() ? tr("Apply writes it.")
                                             : tr("Apply writes it anyway."))),
      !m.ShapesAgree || m.kindDiffers());
    return true;
  }
  this->report(tr("Matched in %1 s: PSNR against the picture %2 dB%3. Apply writes it.")
                 .arg(m.Timings.size() == 4 ? m.Timings[3] : 0.0, 0, 'f', 1)
                 .arg(m.PSNRAfter, 0, 'f', 1)
                 .arg(std::isfinite(m.PSNRBefore)
                     ? tr(" (the design it started from: %1 dB)").arg(m.PSNRBefore, 0, 'f', 1)
                     : QString()));
  return true;
}

QString pqDDGDesignState::kindNetwork()
{
  const QString dir = QString::fromUtf8(DDG_DATA_DIR "/Models/kind");
  return QFileInfo::exists(dir + "/kind.json") ? dir : QString();
}

QString pqDDGDesignState::kindText(const QJsonObject& kind)
{
  if (kind.isEmpty())
    return QString();
  const double agreement = kind.value("agreement").toDouble();
  const double threshold = kind.value("threshold").toDouble();
  if (!kind.value("differs").toBool())
    return tr("Kind agreement %1 (the same kind: %2 or more)")
      .arg(agreement, 0, 'f', 2)
      .arg(threshold, 0, 'f', 2);
  return tr("The picture may show a volume of another kind: kind agreement %1, under %2 (the "
            "picture looks most like %3, this volume like %4)")
    .arg(agreement, 0, 'f', 2)
    .arg(threshold, 0, 'f', 2)
    .arg(kind.value("picture_like").toString())
    .arg(kind.value("volume_like").toString());
}

QImage pqDDGDesignState::pictureTile() const
{
  QImage picture = QImage::fromData(this->QueryPicture);
  if (picture.isNull() && !this->QueryPicture.isEmpty()) // a format this Qt cannot read
  {
    int width = 0, height = 0;
    const std::vector<unsigned char> rgb =
      vtkSMDDGScene::DecodePicture(this->QueryPicture.toStdString(), width, height);
    if (!rgb.empty())
      picture = QImage(rgb.data(), width, height, 3 * width, QImage::Format_RGB888).copy();
  }
  const Match& m = this->LastMatch;
  const QRect part = m.Crop.isValid() ? m.Crop : QRect(QPoint(0, 0), m.Overlay.size());
  if (picture.isNull() || !this->hasMatch() || m.Overlay.size() != part.size() ||
    !picture.rect().contains(part))
    return picture;
  picture = picture.convertToFormat(QImage::Format_ARGB32);
  QImage tint(part.size(), QImage::Format_ARGB32);
  tint.fill(Qt::transparent);
  for (int y = 0; y < tint.height(); ++y)
  {
    const uchar* mask = m.Overlay.constScanLine(y);
    auto* row = reinterpret_cast<QRgb*>(tint.scanLine(y));
    for (int x = 0; x < tint.width(); ++x)
      if (mask[x] > 127)
        row[x] = qRgba(255, 0, 0, 140);
  }
  QPainter painter(&picture);
  painter.drawImage(part.topLeft(), tint);
  painter.setClipRegion(QRegion(picture.rect()).subtracted(QRegion(part)));
  painter.fillRect(picture.rect(), QColor(255, 0, 0, 140));
  return picture;
}
