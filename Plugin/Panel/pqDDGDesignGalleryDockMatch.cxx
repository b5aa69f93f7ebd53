// pqDDGDesignGalleryDockMatch.cxx: the Design Gallery panel's "Match the picture" box: its
// figures, previews and progress, and Apply with the camera (pqDDGDesignGalleryDock).
#include "pqDDGDesignGalleryDock.h"
#include "pqDDGDesignState.h"
#include "pqDDGInputGuard.h"
#include "pqDDGNavigationPad.h"
#include "pqDDGOutlineView.h"
#include "pqDDGPinStrip.h"
#include "pqDDGQueryBox.h"
#include "pqDDGScene.h"
#include "ui_pqDDGDesignGalleryDock.h"
#include <QApplication>
#include <QCheckBox>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QJsonDocument>
#include <QMimeData>
#include <QScrollArea>
#include <QShortcut>
#include <QTimer>
#include <cmath>
#include <pqActiveObjects.h>
#include <pqApplicationCore.h>
#include <pqDataRepresentation.h>
#include <pqFileDialog.h>
#include <pqPipelineSource.h>
#include <pqProgressManager.h>
#include <pqRenderView.h>
#include <pqServer.h>
#include <pqUndoStack.h>
#include <vtkSMDDGScene.h>
#include <vtkSMSourceProxy.h>

namespace
{
/// `image` scaled into `label`'s minimum size.
QPixmap fitted(const QImage& image, const QLabel* label)
{
  return QPixmap::fromImage(
    image.scaled(label->minimumSize(), Qt::KeepAspectRatio, Qt::SmoothTransformation));
}
} // namespace

void pqDDGDesignGalleryDock::showMatch()
{
  auto& ui = *this->Ui;
  const pqDDGDesignState::Match& m = this->State->lastMatch();
  const bool has = this->State->hasMatch();
  ui.applyMatch->setEnabled(has);
  ui.match->setEnabled(!this->State->queryPicture().isEmpty());
  const QImage picture = this->State->pictureTile();
  if (picture.isNull())
    ui.pictureView->clear();
  else
    ui.pictureView->setPixmap(fitted(picture, ui.pictureView));
  if (!has)
  {
    ui.matchPreview->clear();
    ui.matchInfo->setText(this->State->queryPicture().isEmpty()
        ? tr("Query with a picture, then Match fits a transfer function (and the camera) to it.")
        : this->State->isLoaded()
        ? tr("Match refines the design toward the picture.")
        : tr("Match fits a transfer function (and the camera) to the picture, from grey: this "
             "volume has no model."));
    return;
  }
  ui.matchPreview->setPixmap(fitted(m.Render, ui.matchPreview));
  const auto t = [&m](int k) { return m.Timings.size() > k ? m.Timings[k] : 0.0; };
  const QJsonObject lighting = m.View.value("lighting").toObject();
  const QString lit = !lighting.value("shade").toBool() ? tr("unlit")
    : lighting.value("specular").toDouble() > 0
    ? tr("Shade on, Specular %1").arg(lighting.value("specular").toDouble(), 0, 'f', 1)
    : tr("Shade on");
  if (m.Carried)
  {
    QStringList regions;
    for (const auto& r : m.Regions)
      regions << tr("values %1\u2013%2 \u2190 the picture's colour (%3, %4, %5), %6 % of its "
                    "object")
                   .arg(r[0], 0, 'g', 4)
                   .arg(r[1], 0, 'g', 4)
                   .arg(std::lround(255 * r[2]))
                   .arg(std::lround(255 * r[3]))
                   .arg(std::lround(255 * r[4]))
                   .arg(std::lround(100 * r[5]));
    ui.matchInfo->setText(
      tr("Another volume's picture: its look carried over to this volume, %8 as it is shown "
         "(seen from azimuth 30, elevation 20; the camera is not the picture's).\n%1\nColour "
         "distance (CIELAB) %2 \u2192 %3 in %4 steps, %5 s; shape agreement %6%7")
        .arg(regions.join("\n"))
        .arg(m.DistanceStart, 0, 'f', 1)
        .arg(m.DistanceEnd, 0, 'f', 1)
        .arg(m.Iterations)
        .arg(t(0), 0, 'f', 1)
        .arg(m.ShapeAgreement, 0, 'f', 2)
        .arg((m.ShapesAgree
                 ? QString()
                 : tr(" \u2014 the shapes disagree: the picture may show a volume of another "
                      "kind")) +
          (m.Kind.isEmpty() ? QString() : QStringLiteral(". ") + m.kindText()))
        .arg(lit));
    return;
  }
  const bool parallel = m.View.value("camera").toObject().value("parallel_projection").toBool();
  ui.matchInfo->setText(
    tr("PSNR against the picture: %1the match %2 dB (fit %3 dB, "
       "%4 steps)\nCamera %5, silhouette overlap %6; picture %10 (%11)\nTime: background %7 s, "
       "camera %8 s, fit %9 s")
      .arg(std::isfinite(m.PSNRBefore) // none when the match starts from grey (no model)
          ? tr("the design it started from %1 dB \u2192 ").arg(m.PSNRBefore, 0, 'f', 1)
          : QString())
      .arg(m.PSNRAfter, 0, 'f', 1)
      .arg(m.FitPSNR, 0, 'f', 1)
      .arg(m.Iterations)
      .arg((m.CameraEstimated ? tr("estimated") : tr("given (the current one)")) +
        (parallel ? tr(", parallel projection") : QString()))
      .arg(m.Overlap, 0, 'f', 2)
      .arg(t(0), 0, 'f', 1)
      .arg(t(1), 0, 'f', 1)
      .arg(t(2), 0, 'f', 1)
      .arg(lit)
      .arg(m.LightingEstimated ? tr("estimated") : tr("as the view says")));
}

void pqDDGDesignGalleryDock::showMatchProgress(
  const QString& stage, double fraction, const QImage& preview)
{
  this->Ui->progress->setValue(static_cast<int>(std::lround(100 * fraction)));
  this->Ui->matchInfo->setText(tr("Matching: %1 (%2 %)")
                                 .arg(stage.isEmpty() ? tr("starting") : stage)
                                 .arg(std::lround(100 * fraction)));
  if (!preview.isNull())
    this->Ui->matchPreview->setPixmap(fitted(preview, this->Ui->matchPreview));
}

void pqDDGDesignGalleryDock::runMatch()
{
  this->Ui->match->setEnabled(false);
  bool matched = false;
  {
    pqDDGInputGuard guard{ this->Ui->cancelMatch, this->Ui->cancel };
    matched =
      this->State->match(this->Ui->pictureCamera->isChecked(), this->Ui->otherVolume->isChecked());
  }
  this->showMatch();
  if (!matched) // why, next to the Match button too
    this->Ui->matchInfo->setText(this->State->lastMessage());
}

void pqDDGDesignGalleryDock::applyMatch()
{
  if (!this->State->hasVolume())
    return;
  if (!this->State->hasMatch())
  {
    this->setStatus(tr("Match the picture first."), true);
    return;
  }
  const pqDDGDesignState::Match& m = this->State->lastMatch();
  const bool twoD = !m.ParaView2D.isEmpty();
  // another volume's picture has no camera here: Apply writes the TF alone
  const bool moveCamera = this->Ui->moveCamera->isChecked() && !m.Carried;
  pqDataRepresentation* repr = ddgpanel::representation(this->State->volume());
  auto* view = qobject_cast<pqRenderView*>(pqActiveObjects::instance().activeView());
  if (moveCamera && !view)
  {
    this->setStatus(tr("Apply failed: there is no render view to move the camera of."), true);
    return;
  }
  // one undo step: the TF, and the camera when asked (after the TF was written: on an error
  // nothing is recorded and the scene stays as it was)
  const QString label = tr("Apply Design Gallery Match");
  QString note;
  const bool written = this->writeToScene(
    repr, label,
    [&]()
    {
      QString e = twoD
        ? ddgpanel::applyTransferFunction2D(repr, this->State->array(), m.ParaView2D, label, false)
        : ddgpanel::applyPreset(repr, this->State->array(), m.Preset, label, false);
      if (e.isEmpty()) // the picture's lighting (Shade and its coefficients): the look matched
        e = QString::fromStdString(vtkSMDDGScene::SetLighting(
          repr->getProxy(), ddgpanel::jsonText(m.View).toUtf8().constData()));
      if (e.isEmpty() && moveCamera)
        e = ddgpanel::setCamera(view, m.View, true);
      return e;
    },
    note);
  if (!written)
    return;
  if (view)
    view->render();
  const bool shade = m.View.value("lighting").toObject().value("shade").toBool();
  const bool parallel = m.View.value("camera").toObject().value("parallel_projection").toBool();
  if (m.Carried)
  {
    this->setStatus(tr("Applied the look carried over from another volume's picture to '%1'%2; "
                       "the camera stays, Shade %3 (Edit > Undo takes it back).")
                      .arg(this->Source->getSMName(), note, shade ? tr("on") : tr("off")));
    return;
  }
  this->setStatus(
    tr("Applied the match to '%1'%2%3; Shade %4 as in the picture (Edit > Undo "
       "takes it back).")
      .arg(this->Source->getSMName(), note,
        moveCamera ? (parallel ? tr(" with the picture's camera (parallel projection)")
                               : tr(" with the picture's camera"))
                   : QString(),
        shade ? tr("on") : tr("off")));
}
