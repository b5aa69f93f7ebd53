// pqDDGDesignGalleryDockExport.cxx: the Design Gallery panel's design shown, its Apply and its
// exports (preset, Slicer, history) (pqDDGDesignGalleryDock).
#include "pqDDGDesignGalleryDock.h"
#include "pqDDGDesignState.h"
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
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QMessageBox>
#include <QMimeData>
#include <QPainter>
#include <QPushButton>
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
bool writeText(const QString& path, const QString& text)
{
  QFile f(path);
  if (!f.open(QIODevice::WriteOnly | QIODevice::Truncate))
    return false;
  return f.write(text.toUtf8()) >= 0;
}
/// `preset` (a ParaView preset list, or a DDG 2D TF object) with its "Name" set to `name`.
QString renamed(const QString& preset, const QString& name)
{
  QJsonDocument doc = QJsonDocument::fromJson(preset.toUtf8());
  if (doc.isArray() && !doc.array().isEmpty())
  {
    QJsonArray list = doc.array();
    QJsonObject first = list.first().toObject();
    first["Name"] = name;
    list[0] = first;
    doc.setArray(list);
  }
  else if (doc.isObject())
  {
    QJsonObject tf = doc.object();
    tf["Name"] = name;
    doc.setObject(tf);
  }
  else
    return preset;
  return QString::fromUtf8(doc.toJson(QJsonDocument::Indented));
}
} // namespace

// --- the design shown ----------------------------------------------------------------------------

void pqDDGDesignGalleryDock::showDesign()
{
  const pqDDGDesignState::Design& d = this->State->design();
  this->Ui->preview->setPixmap(QPixmap::fromImage(d.Preview));
  if (d.Position.size() == 2)
    this->Ui->outline->setSelection(
      d.Row, QPointF(d.Position[0].toDouble(), d.Position[1].toDouble()));
  QStringList path;
  for (const auto& s : this->State->steps())
    path << s.toObject().value("action").toString();
  // the query's design: how close it looks to the picture (the match, once run, says more)
  const auto& steps = this->State->steps();
  const bool queryDesign = steps.size() == 1 &&
    steps[0].toObject().value("action").toString() == "latent" &&
    steps[0].toObject().value("image").toString() == this->State->queryName() &&
    std::isfinite(this->State->queryPicturePSNR());
  // one of its nearest designs, picked under the query box: the strip's figure again
  const int picked = steps.size() == 1 && steps[0].toObject().value("action").toString() == "pick"
    ? steps[0].toObject().value("row").toInt(-1)
    : -1;
  const double pickedAgainst = this->State->neighbourPicturePSNR(picked);
  QString against;
  if (queryDesign)
    against =
      tr("\nAgainst the picture: %1 dB (framed alike, the design %2; Match finds its camera)")
        .arg(this->State->queryPicturePSNR(), 0, 'f', 1)
        .arg(this->State->queryPictureLit() ? tr("lit") : tr("unlit")) +
      (this->State->queryKind().isEmpty()
          ? QString()
          : QStringLiteral("\n") + pqDDGDesignState::kindText(this->State->queryKind()));
  else if (std::isfinite(pickedAgainst))
    against = tr("\nAgainst the picture: %1 dB (framed alike; nearest design %2 of the query "
                 "'%3')")
                .arg(pickedAgainst, 0, 'f', 1)
                .arg(this->State->queryNeighbours().indexOf(picked) + 1)
                .arg(this->State->queryName());
  // one fill: a picture's name with a '%' or a '<' in it stays as it is
  this->Ui->info->setTextFormat(Qt::PlainText);
  this->Ui->info->setText(
    tr("Path: %1%2\nPreview vs. ray cast of its TF: %3 dB, SSIM %4")
      .arg(path.join(QString::fromUtf8(" \u2192 ")), against,
        QString::number(d.Fidelity.size() >= 2 ? d.Fidelity[0].toDouble() : 0.0, 'f', 1),
        QString::number(d.Fidelity.size() >= 2 ? d.Fidelity[1].toDouble() : 0.0, 'f', 3)));
  this->Ui->info->setToolTip(
    tr("Against the picture: the query's design against its picture, each cut to its content and "
       "compared at one size (PSNR; the picture's camera is not known, so a different viewpoint "
       "lowers it; nor is its lighting: the better of the design unlit and lit is shown; Match "
       "estimates the camera and fits the picture).\nPreview vs. ray cast: the "
       "network's image of the design against ParaView's way of rendering its TF at this camera."));
  // colour clusters: what edits act on
  const int current = this->Ui->cluster->currentIndex();
  this->Ui->cluster->clear();
  for (int k = 0; k < d.ClusterColours.size(); ++k)
  {
    QPixmap swatch(16, 16);
    swatch.fill(d.ClusterColours[k]);
    this->Ui->cluster->addItem(
      QIcon(swatch), tr("colour %1 (%2 %)").arg(k + 1).arg(std::lround(100 * d.ClusterShares[k])));
  }
  if (current >= 0 && current < this->Ui->cluster->count())
    this->Ui->cluster->setCurrentIndex(current);
  // feature locks: one per region of the model
  if (this->Locks.size() != d.Regions.size() / 2)
  {
    for (auto* c : this->Locks)
      delete c;
    this->Locks.clear();
    for (int k = 0; k + 1 < d.Regions.size(); k += 2)
    {
      auto* box = new QCheckBox(QString::number(k / 2 + 1), this->Ui->locks);
      box->setObjectName(QString("lock%1").arg(k / 2));
      box->setToolTip(tr("Keep feature region %1 (values %2 to %3) as it is now")
                        .arg(k / 2 + 1)
                        .arg(d.Regions[k].toDouble(), 0, 'g', 4)
                        .arg(d.Regions[k + 1].toDouble(), 0, 'g', 4));
      this->Ui->locks->layout()->addWidget(box);
      QObject::connect(box, &QCheckBox::toggled, this, &pqDDGDesignGalleryDock::lockChanged);
      this->Locks.push_back(box);
    }
  }
  for (int k = 0; k < this->Locks.size(); ++k) // as the state has them (a volume kept)
  {
    this->Locks[k]->blockSignals(true);
    this->Locks[k]->setChecked(this->State->lockedRegions().contains(k));
    this->Locks[k]->blockSignals(false);
  }
}

// --- apply and export ----------------------------------------------------------------------------

bool pqDDGDesignGalleryDock::writeToScene(pqDataRepresentation* repr, const QString& label,
  const std::function<QString()>& write, QString& note)
{
  note.clear();
  if (!repr)
  {
    this->setStatus(
      tr("Apply failed: there is no representation of the volume in the active view"), true);
    return false;
  }
  const QByteArray array = this->State->array().toUtf8();
  const QStringList users =
    QString::fromStdString(vtkSMDDGScene::SharedColorMapUsers(repr->getProxy(), array.constData()))
      .split('\n', Qt::SkipEmptyParts);
  bool separate = false;
  if (!users.isEmpty())
  {
    const QString name = this->Source->getSMName();
    QMessageBox box(QMessageBox::Question, tr("Shared colour map"),
      tr("'%1' shares the colour map of '%2' with %3: Apply would recolour %4 too.")
        .arg(name, this->State->array(), "'" + users.join("', '") + "'",
          users.size() == 1 ? tr("it") : tr("them")),
      QMessageBox::NoButton, this);
    box.setObjectName("SharedColorMapBox");
    QPushButton* own =
      box.addButton(tr("Separate colour map for '%1'").arg(name), QMessageBox::AcceptRole);
    own->setObjectName("SeparateColorMap");
    QPushButton* all = box.addButton(tr("Recolour all"), QMessageBox::DestructiveRole);
    all->setObjectName("RecolourAll");
    box.addButton(QMessageBox::Cancel)->setObjectName("CancelApply");
    box.setDefaultButton(own);
    box.exec();
    if (box.clickedButton() != own && box.clickedButton() != all)
    {
      this->setStatus(tr("Apply cancelled: the scene is unchanged."));
      return false;
    }
    separate = box.clickedButton() == own;
    note = separate ? tr(", now with a colour map of its own (ParaView's separate colour map)")
                    : (users.size() == 1 ? tr(" and to %1, which shares its colour map")
                                         : tr(" and to %1, which share its colour map"))
                        .arg("'" + users.join("', '") + "'");
  }
  pqUndoStack* undo = pqApplicationCore::instance()->getUndoStack();
  bool pushed = false; // an undo set with no change (an error) is not pushed
  QMetaObject::Connection watch;
  if (undo)
    watch =
      QObject::connect(undo, &pqUndoStack::stackChanged, this, [&pushed]() { pushed = true; });
  BEGIN_UNDO_SET(label);
  QString error = separate ? QString::fromStdString(vtkSMDDGScene::UseSeparateColorMap(
                               repr->getProxy(), array.constData()))
                           : QString();
  if (error.isEmpty())
    error = write();
  END_UNDO_SET();
  QObject::disconnect(watch);
  if (error.isEmpty())
    return true;
  if (pushed && undo && undo->canUndo())
    undo->undo(); // a part went in (the separate map, the TF): take it back
  this->setStatus(tr("Apply failed: %1").arg(error), true);
  return false;
}

void pqDDGDesignGalleryDock::apply()
{
  if (!this->State->ready(true) || !this->State->updateDesign()) // the TF at the current camera
    return;
  const pqDDGDesignState::Design& d = this->State->design();
  const bool twoD = !d.ParaView2D.isEmpty();
  pqDataRepresentation* repr = ddgpanel::representation(this->State->volume());
  const QString label = twoD ? tr("Apply Design Gallery 2D Transfer Function")
                             : tr("Apply Design Gallery Transfer Function");
  QString note;
  const bool written = this->writeToScene(
    repr, label,
    [&]()
    {
      return twoD
        ? ddgpanel::applyTransferFunction2D(repr, this->State->array(), d.ParaView2D, label, false)
        : ddgpanel::applyPreset(repr, this->State->array(), d.Preset, label, false);
    },
    note);
  if (!written)
    return;
  if (auto* view = pqActiveObjects::instance().activeView())
    view->render();
  if (twoD)
  {
    const QJsonObject pv = QJsonDocument::fromJson(d.ParaView2D.toUtf8()).object();
    this->setStatus(tr("Applied to '%1'%2 as ParaView 2D boxes (Edit > Undo takes it back; the "
                       "Color Map Editor's 2D editor shows them).")
                      .arg(this->Source->getSMName(), note));
    this->Ui->status->setToolTip(
      tr("%1 Gaussian boxes fitted to the design: RMSE %2 of emission and "
         "per-sample opacity (largest opacity %3)")
        .arg(pv.value("Boxes").toArray().size() / 8)
        .arg(pv.value("Fit").toObject().value("rmse").toDouble(), 0, 'f', 4)
        .arg(pv.value("Fit").toObject().value("max_alpha").toDouble(), 0, 'f', 3));
    return;
  }
  this->setStatus(
    tr("Applied to '%1'%2 (Edit > Undo takes it back; the Color Map Editor shows it).")
      .arg(this->Source->getSMName(), note));
}

void pqDDGDesignGalleryDock::exportPreset()
{
  if (!this->State->ready(true) || this->State->design().Preset.isEmpty())
    return;
  const QString path = QFileDialog::getSaveFileName(
    this, tr("Export ParaView preset"), "design.json", tr("JSON (*.json)"));
  if (path.isEmpty())
    return;
  // named for the volume, the design's origin, the file and the time: ParaView imports each
  const QJsonArray& steps = this->State->steps();
  const QString action =
    steps.isEmpty() ? QString("design") : steps.last().toObject().value("action").toString();
  const QString name =
    QString::fromStdString(vtkSMDDGScene::ExportName(this->State->volumeName().toUtf8().constData(),
      action.toUtf8().constData(), path.toUtf8().constData()));
  if (!writeText(path, renamed(this->State->design().Preset, name)))
    this->setStatus(tr("Cannot write %1.").arg(path), true);
  else
    this->setStatus(tr("Wrote %1 (preset \"%2\").").arg(path, name));
}

void pqDDGDesignGalleryDock::exportSlicer()
{
  if (!this->State->ready(true))
    return;
  if (this->State->design().Slicer.isEmpty())
  {
    this->setStatus(tr("3D Slicer's format holds 1D transfer functions only."), true);
    return;
  }
  const QString path = QFileDialog::getSaveFileName(
    this, tr("Export 3D Slicer volume property"), "design.vp.json", tr("JSON (*.json)"));
  if (!path.isEmpty() && !writeText(path, this->State->design().Slicer))
    this->setStatus(tr("Cannot write %1.").arg(path), true);
}

void pqDDGDesignGalleryDock::exportHistory()
{
  if (!this->State->ready(true))
    return;
  const QString path = QFileDialog::getSaveFileName(
    this, tr("Export design history (ddg replay)"), "history.json", tr("JSON (*.json)"));
  if (!path.isEmpty() &&
    !writeText(path, pqDDGDesignState::historyText(this->State->exportSteps())))
    this->setStatus(tr("Cannot write %1.").arg(path), true);
}
