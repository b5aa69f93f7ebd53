// pqDDGDesignGalleryDock.cxx: the Design Gallery panel: widgets <-> state, source, apply, export.
#include "pqDDGDesignGalleryDock.h"
#include "ui_pqDDGDesignGalleryDock.h"

#include "pqDDGDesignState.h"
#include "pqDDGNavigationPad.h"
#include "pqDDGOutlineView.h"
#include "pqDDGPinStrip.h"
#include "pqDDGQueryBox.h"
#include "pqDDGScene.h"

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

#include <QApplication>
#include <QCheckBox>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QJsonDocument>
#include <QMimeData>
#include <QPainter>
#include <QScrollArea>
#include <QShortcut>
#include <QTimer>

#include <cmath>

#ifndef DDG_DATA_DIR
#define DDG_DATA_DIR ""
#endif

namespace
{
/// While a long filter run processes events (match, build): user input reaches only the given
/// Cancel buttons. pqProgressManager's own blocking lets "non-blockable" widgets through by the
/// receiver of the event, but a click first goes to the top-level QWindow, which it blocks, so
/// no button gets it; its blocking is lifted for the run and this filter blocks instead: input
/// to windows passes (they route it to the widget under the cursor), input to any widget but the
/// Cancel buttons, and shortcuts, are dropped (no re-entrant pipeline updates from the GUI).
class InputGuard : public QObject
{
public:
  InputGuard(std::initializer_list<QWidget*> allowed)
    : Allowed(allowed)
  {
    auto* progress = pqApplicationCore::instance()->getProgressManager();
    this->WasUnblocked = progress->unblockEvents(true);
    QApplication::instance()->installEventFilter(this);
  }
  ~InputGuard() override
  {
    QApplication::instance()->removeEventFilter(this);
    pqApplicationCore::instance()->getProgressManager()->unblockEvents(this->WasUnblocked);
  }

protected:
  bool eventFilter(QObject* receiver, QEvent* event) override
  {
    switch (event->type())
    {
      case QEvent::MouseButtonPress:
      case QEvent::MouseButtonRelease:
      case QEvent::MouseButtonDblClick:
      case QEvent::KeyPress:
      case QEvent::KeyRelease:
      case QEvent::Wheel:
      case QEvent::Shortcut:
      case QEvent::ShortcutOverride:
      case QEvent::Drop:
        if (receiver->isWindowType() && event->type() != QEvent::Shortcut &&
          event->type() != QEvent::ShortcutOverride)
          return false;
        for (QWidget* w : this->Allowed)
          if (receiver == w)
            return false;
        return true;
      default:
        return false;
    }
  }

private:
  QList<QWidget*> Allowed;
  bool WasUnblocked = false;
};

bool writeText(const QString& path, const QString& text)
{
  QFile f(path);
  if (!f.open(QIODevice::WriteOnly | QIODevice::Truncate))
    return false;
  return f.write(text.toUtf8()) >= 0;
}
} // namespace

pqDDGDesignGalleryDock::pqDDGDesignGalleryDock(QWidget* parent)
  : QDockWidget(tr("Design Gallery"), parent)
  , Ui(new Ui::pqDDGDesignGalleryDock)
  , State(new pqDDGDesignState(this))
{
  auto* scroll = new QScrollArea(this);
  scroll->setObjectName("scroll");
  scroll->setWidgetResizable(true);
  auto* contents = new QWidget(scroll);
  this->Ui->setupUi(contents);
  scroll->setWidget(contents);
  this->setWidget(scroll);
  this->setAcceptDrops(true);
  this->Ui->pinBox->setState(this->State);
  this->BoxTimer = new QTimer(this);
  this->BoxTimer->setSingleShot(true);
  this->BoxTimer->setInterval(400);
  // the view JSON of the active render view's camera (and the volume's opacity unit distance)
  this->State->setViewFunction(
    [this](int maxSide)
    {
      auto* view = qobject_cast<pqRenderView*>(pqActiveObjects::instance().activeView());
      if (!view)
        return QJsonObject();
      return ddgpanel::viewJson(
        view, this->Source ? this->Source->getRepresentation(0, view) : nullptr, maxSide);
    });
  this->connectWidgets();
  this->connectState();

  pqProgressManager* progress = pqApplicationCore::instance()->getProgressManager();
  progress->addNonBlockableObject(this->Ui->cancel);
  progress->addNonBlockableObject(this->Ui->cancelMatch);
  QObject::connect(progress, &pqProgressManager::progress, this,
    [this](const QString&, int value)
    {
      if (this->State->isBusy())
        this->Ui->progress->setValue(value);
    });
  QObject::connect(&pqActiveObjects::instance(),
    QOverload<pqPipelineSource*>::of(&pqActiveObjects::sourceChanged), this,
    &pqDDGDesignGalleryDock::setSource);
  // the data information of a new source arrives with its first update or representation
  auto retry = [this]()
  {
    if (!this->State->isLoaded() && !this->State->isBusy())
      this->setSource(pqActiveObjects::instance().activeSource());
  };
  QObject::connect(&pqActiveObjects::instance(), &pqActiveObjects::dataUpdated, this, retry);
  QObject::connect(&pqActiveObjects::instance(),
    QOverload<pqDataRepresentation*>::of(&pqActiveObjects::representationChanged), this, retry);
  this->setSource(pqActiveObjects::instance().activeSource());
}

pqDDGDesignGalleryDock::~pqDDGDesignGalleryDock() = default;

void pqDDGDesignGalleryDock::connectWidgets()
{
  auto& ui = *this->Ui;
  pqDDGDesignState* state = this->State;
  QObject::connect(
    ui.modelPath, &QLineEdit::returnPressed, this, &pqDDGDesignGalleryDock::loadModel);
  QObject::connect(ui.loadModel, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::browseModel);
  QObject::connect(ui.buildModel, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::buildModel);
  QObject::connect(ui.cancel, &QPushButton::clicked, state, &pqDDGDesignState::cancel);
  // the outline
  QObject::connect(ui.back, &QPushButton::clicked, state, &pqDDGDesignState::back);
  QObject::connect(ui.resample, &QPushButton::clicked, state, &pqDDGDesignState::resample);
  QObject::connect(ui.refresh, &QPushButton::clicked, state,
    [state]()
    {
      state->setThumbnailsAtCamera(true);
      state->refreshOutline();
    });
  QObject::connect(ui.outline, &pqDDGOutlineView::rowClicked, state, &pqDDGDesignState::pick);
  QObject::connect(ui.outline, &pqDDGOutlineView::drillIn, state, &pqDDGDesignState::drillIn);
  QObject::connect(
    ui.outline, &pqDDGOutlineView::boxChanged, this->BoxTimer, QOverload<>::of(&QTimer::start));
  QObject::connect(this->BoxTimer, &QTimer::timeout, state,
    [this]() { this->State->setShownBox(this->Ui->outline->box()); });
  // the query
  ui.queryBox->setState(state);
  auto* paste = new QShortcut(QKeySequence::Paste, ui.outline);
  QObject::connect(paste, &QShortcut::activated, ui.queryBox, &pqDDGQueryBox::paste);
  // the match
  QObject::connect(ui.match, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::runMatch);
  QObject::connect(ui.cancelMatch, &QPushButton::clicked, state, &pqDDGDesignState::cancel);
  QObject::connect(ui.applyMatch, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::applyMatch);
  // the design
  QObject::connect(ui.apply, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::apply);
  QObject::connect(ui.pin, &QPushButton::clicked, state, &pqDDGDesignState::pin);
  QObject::connect(
    ui.exportPreset, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::exportPreset);
  QObject::connect(
    ui.exportSlicer, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::exportSlicer);
  QObject::connect(
    ui.exportHistory, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::exportHistory);
  // edits
  QObject::connect(ui.recolour, &QPushButton::clicked, state,
    [this]()
    { this->State->edit(this->Ui->cluster->currentIndex(), this->Ui->hue->value(), 1.0); });
  QObject::connect(ui.moreVisible, &QPushButton::clicked, state,
    [this]() { this->State->edit(this->Ui->cluster->currentIndex(), 0.0, 1.5); });
  QObject::connect(ui.lessVisible, &QPushButton::clicked, state,
    [this]() { this->State->edit(this->Ui->cluster->currentIndex(), 0.0, 1.0 / 1.5); });
  for (QSlider* axis : { ui.axis0, ui.axis1, ui.axis2 })
    QObject::connect(axis, &QSlider::sliderReleased, this, &pqDDGDesignGalleryDock::axesReleased);
}

void pqDDGDesignGalleryDock::connectState()
{
  auto& ui = *this->Ui;
  pqDDGDesignState* state = this->State;
  QObject::connect(
    state, &pqDDGDesignState::statusChanged, this, &pqDDGDesignGalleryDock::setStatus);
  QObject::connect(state, &pqDDGDesignState::busyChanged, this,
    [this](bool busy)
    {
      this->Ui->cancel->setEnabled(busy);
      this->Ui->cancelMatch->setEnabled(busy);
      this->Ui->progress->setValue(busy ? 0 : 100);
    });
  QObject::connect(ui.pinBox, &pqDDGPinStrip::progress, ui.progress, &QProgressBar::setValue);
  QObject::connect(
    state, &pqDDGDesignState::modelCleared, this, &pqDDGDesignGalleryDock::clearModel);
  QObject::connect(state, &pqDDGDesignState::outlineChanged, this,
    [this](const pqDDGDesignState::Outline& outline)
    {
      this->Ui->outline->setPoints(outline.Points);
      if (outline.BoxKnown)
        this->Ui->outline->setBox(outline.Box);
      this->Ui->outline->setThumbnails(outline.ThumbnailRows, outline.Thumbnails);
    });
  QObject::connect(
    state, &pqDDGDesignState::outlineFailed, ui.outline, &pqDDGOutlineView::setMessage);
  QObject::connect(state, &pqDDGDesignState::queried, this,
    [this](const QPointF& position, const QVector<int>& neighbours)
    { this->Ui->outline->setQuery(true, position, neighbours); });
  QObject::connect(state, &pqDDGDesignState::pathStarted, this,
    [this]()
    {
      for (QSlider* axis : { this->Ui->axis0, this->Ui->axis1, this->Ui->axis2 })
      {
        axis->blockSignals(true);
        axis->setValue(0);
        axis->blockSignals(false);
      }
    });
  QObject::connect(
    state, &pqDDGDesignState::designChanged, this, &pqDDGDesignGalleryDock::showDesign);
  QObject::connect(state, &pqDDGDesignState::queryDone, this,
    [this]()
    {
      this->showMatch(); // the picture
      if (this->Ui->matchAfterQuery->isChecked())
        this->runMatch();
    });
  QObject::connect(
    state, &pqDDGDesignState::matchChanged, this, &pqDDGDesignGalleryDock::showMatch);
  QObject::connect(
    state, &pqDDGDesignState::matchProgress, this, &pqDDGDesignGalleryDock::showMatchProgress);
  this->showMatch();
}

// --- what the state reports ----------------------------------------------------------------------

void pqDDGDesignGalleryDock::setStatus(const QString& text, bool error)
{
  this->Ui->status->setText(text);
  this->Ui->status->setToolTip(QString());
  this->Ui->status->setStyleSheet(error ? "color: #b00000;" : "");
}

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
  // the picture, with what the match left out (overlays) tinted red
  QImage picture = QImage::fromData(this->State->queryPicture());
  const QRect part = m.Crop.isValid() ? m.Crop : QRect(QPoint(0, 0), m.Overlay.size());
  if (!picture.isNull() && has && m.Overlay.size() == part.size() && picture.rect().contains(part))
  {
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
  }
  if (picture.isNull())
    ui.pictureView->clear();
  else
    ui.pictureView->setPixmap(fitted(picture, ui.pictureView));
  if (!has)
  {
    ui.matchPreview->clear();
    ui.matchInfo->setText(this->State->queryPicture().isEmpty()
        ? tr("Query with a picture, then Match fits a transfer function (and the camera) to it.")
        : tr("Match refines the design toward the picture."));
    return;
  }
  ui.matchPreview->setPixmap(fitted(m.Render, ui.matchPreview));
  const auto t = [&m](int k) { return m.Timings.size() > k ? m.Timings[k] : 0.0; };
  ui.matchInfo->setText(
    tr("PSNR against the picture: the query's design %1 dB \u2192 the match %2 dB (fit %3 dB, "
       "%4 steps)\nCamera %5, silhouette overlap %6\nTime: background %7 s, camera %8 s, fit "
       "%9 s")
      .arg(m.PSNRBefore, 0, 'f', 1)
      .arg(m.PSNRAfter, 0, 'f', 1)
      .arg(m.FitPSNR, 0, 'f', 1)
      .arg(m.Iterations)
      .arg(m.CameraEstimated ? tr("estimated") : tr("given (the current one)"))
      .arg(m.Overlap, 0, 'f', 2)
      .arg(t(0), 0, 'f', 1)
      .arg(t(1), 0, 'f', 1)
      .arg(t(2), 0, 'f', 1));
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
    InputGuard guard{ this->Ui->cancelMatch, this->Ui->cancel };
    matched = this->State->match(this->Ui->pictureCamera->isChecked());
  }
  this->showMatch();
  if (!matched) // why, next to the Match button too
    this->Ui->matchInfo->setText(this->State->lastMessage());
}

void pqDDGDesignGalleryDock::applyMatch()
{
  if (!this->State->ready(true))
    return;
  if (!this->State->hasMatch())
  {
    this->setStatus(tr("Match the picture first."), true);
    return;
  }
  const pqDDGDesignState::Match& m = this->State->lastMatch();
  const bool twoD = !m.ParaView2D.isEmpty();
  const bool moveCamera = this->Ui->moveCamera->isChecked();
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
  BEGIN_UNDO_SET(label);
  QString error = twoD
    ? ddgpanel::applyTransferFunction2D(repr, this->State->array(), m.ParaView2D, label, false)
    : ddgpanel::applyPreset(repr, this->State->array(), m.Preset, label, false);
  if (error.isEmpty() && moveCamera)
    error = ddgpanel::setCamera(view, m.View, true);
  END_UNDO_SET();
  if (!error.isEmpty())
  {
    if (auto* undo = pqApplicationCore::instance()->getUndoStack())
      if (undo->canUndo() && undo->undoLabel() == label)
        undo->undo(); // the TF went in, the camera did not: take the TF back too
    this->setStatus(tr("Apply failed: %1").arg(error), true);
    return;
  }
  if (view)
    view->render();
  this->setStatus(
    tr("Applied the match to '%1'%2 (Edit > Undo takes it back).")
      .arg(this->Source->getSMName(), moveCamera ? tr(" with the picture's camera") : QString()));
}

void pqDDGDesignGalleryDock::clearModel()
{
  this->Ui->preview->clear();
  this->Ui->info->clear();
  this->Ui->cluster->clear();
  for (auto* c : this->Locks)
    delete c;
  this->Locks.clear();
  this->Ui->outline->setPoints({});
  this->Ui->outline->setThumbnails({}, {});
  this->Ui->outline->setQuery(false, {}, {});
}

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
  this->Ui->info->setText(
    tr("Path: %1\nFidelity (neural vs. ray cast of its TF at this camera): "
       "PSNR %2 dB, SSIM %3")
      .arg(path.join(QString::fromUtf8(" \u2192 ")))
      .arg(d.Fidelity.size() >= 2 ? d.Fidelity[0].toDouble() : 0.0, 0, 'f', 1)
      .arg(d.Fidelity.size() >= 2 ? d.Fidelity[1].toDouble() : 0.0, 0, 'f', 3));
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
}

// --- the volume and its model --------------------------------------------------------------------

void pqDDGDesignGalleryDock::setSource(pqPipelineSource* source)
{
  if (source == this->Source && this->State->isLoaded())
    return;
  if (this->Source != source)
  {
    if (this->Source)
      QObject::disconnect(this->Source, nullptr, this, nullptr);
    if (source) // the data information arrives with the first update (Apply)
      QObject::connect(source, QOverload<pqPipelineSource*>::of(&pqPipelineSource::dataUpdated),
        this,
        [this](pqPipelineSource* updated)
        {
          if (!this->State->isLoaded() && updated == this->Source)
            this->setSource(updated);
        });
  }
  this->Source = source;
  auto* proxy = source ? vtkSMSourceProxy::SafeDownCast(source->getProxy()) : nullptr;
  this->State->setVolume(proxy, QString()); // no volume until it is one
  if (!source)
  {
    this->setStatus(tr("Select a volume (image data) in the Pipeline Browser."));
    this->Ui->outline->setMessage(this->Ui->status->text());
    return;
  }
  const int check = vtkSMDDGScene::CheckVolume(proxy, nullptr, 0);
  if (check != vtkSMDDGScene::IS_VOLUME)
  {
    this->setStatus(check == vtkSMDDGScene::NO_DATA
        ? tr("'%1' has no data yet (Apply it in the Properties panel).").arg(source->getSMName())
        : tr("'%1' %2.")
            .arg(source->getSMName(), QString::fromStdString(vtkSMDDGScene::VolumeProblem(check))),
      check != vtkSMDDGScene::NO_DATA);
    this->Ui->outline->setMessage(this->Ui->status->text());
    return;
  }
  this->State->setVolume(
    proxy, QString::fromStdString(vtkSMDDGScene::VolumeArray(proxy, nullptr, 0)));
  // the shipped bundle named like the volume's file, if there is one
  const QString guess =
    QString::fromStdString(vtkSMDDGScene::DefaultModelDirectory(proxy, DDG_DATA_DIR));
  if (!guess.isEmpty())
    this->Ui->modelPath->setText(guess);
  if (this->Ui->modelPath->text().isEmpty())
  {
    this->setStatus(tr("No model for '%1': load a model bundle of this volume (Load...) or "
                       "build one (Build...).")
                      .arg(source->getSMName()));
    this->Ui->outline->setMessage(this->Ui->status->text());
    return;
  }
  this->loadModel();
}

void pqDDGDesignGalleryDock::loadModel()
{
  if (!this->State->volume() || this->State->array().isEmpty())
    return;
  const QString dir = this->Ui->modelPath->text().trimmed();
  this->Ui->modelPath->setText(dir);
  this->State->loadModel(dir);
}

void pqDDGDesignGalleryDock::browseModel()
{
  if (!this->Source)
    return;
  pqFileDialog dialog(
    this->Source->getServer(), this, tr("Model bundle directory"), this->Ui->modelPath->text());
  dialog.setObjectName("ModelDirectoryDialog");
  dialog.setFileMode(pqFileDialog::Directory);
  if (dialog.exec() == QDialog::Accepted && !dialog.getSelectedFiles().isEmpty())
  {
    this->Ui->modelPath->setText(dialog.getSelectedFiles().first());
    this->loadModel();
  }
}

void pqDDGDesignGalleryDock::buildModel()
{
  if (!this->Source || this->State->array().isEmpty())
  {
    this->setStatus(tr("Select a volume first."), true);
    return;
  }
  pqFileDialog dialog(this->Source->getServer(), this, tr("Directory of the new model bundle"));
  dialog.setObjectName("BuildDirectoryDialog");
  dialog.setFileMode(pqFileDialog::Directory);
  if (dialog.exec() != QDialog::Accepted || dialog.getSelectedFiles().isEmpty())
    return;
  const QString dir = dialog.getSelectedFiles().first();
  bool built = false;
  {
    InputGuard guard{ this->Ui->cancel };
    built = this->State->buildModel(dir);
  }
  if (!built)
    return;
  this->Ui->modelPath->setText(dir);
  this->loadModel();
}

// --- the query -----------------------------------------------------------------------------------

void pqDDGDesignGalleryDock::queryFile(const QString& path)
{
  this->Ui->queryBox->queryFile(path);
}

void pqDDGDesignGalleryDock::queryImage(const QImage& image, const QString& name)
{
  this->Ui->queryBox->queryImage(image, name);
}

void pqDDGDesignGalleryDock::dragEnterEvent(QDragEnterEvent* e)
{
  if (e->mimeData()->hasUrls() || e->mimeData()->hasImage())
    e->acceptProposedAction();
}

void pqDDGDesignGalleryDock::dropEvent(QDropEvent* e)
{
  if (e->mimeData()->hasUrls() && e->mimeData()->urls().first().isLocalFile())
  {
    this->Ui->queryBox->queryPath(e->mimeData()->urls().first().toLocalFile());
  }
  else if (e->mimeData()->hasImage())
    this->queryImage(qvariant_cast<QImage>(e->mimeData()->imageData()), tr("dropped image"));
  e->acceptProposedAction();
}

// --- edits ---------------------------------------------------------------------------------------

void pqDDGDesignGalleryDock::axesReleased()
{
  this->State->moveAlongAxes({ this->Ui->axis0->value() / 10.0, this->Ui->axis1->value() / 10.0,
    this->Ui->axis2->value() / 10.0 });
}

void pqDDGDesignGalleryDock::lockChanged()
{
  QVector<int> locked;
  for (int k = 0; k < this->Locks.size(); ++k)
    if (this->Locks[k]->isChecked())
      locked.push_back(k);
  this->State->setLockedRegions(locked);
}

// --- apply and export ----------------------------------------------------------------------------

void pqDDGDesignGalleryDock::apply()
{
  if (!this->State->ready(true) || !this->State->updateDesign()) // the TF at the current camera
    return;
  const pqDDGDesignState::Design& d = this->State->design();
  const bool twoD = !d.ParaView2D.isEmpty();
  pqDataRepresentation* repr = ddgpanel::representation(this->State->volume());
  const QString error = twoD ? ddgpanel::applyTransferFunction2D(repr, this->State->array(),
                                 d.ParaView2D, tr("Apply Design Gallery 2D Transfer Function"))
                             : ddgpanel::applyPreset(repr, this->State->array(), d.Preset,
                                 tr("Apply Design Gallery Transfer Function"));
  if (!error.isEmpty())
  {
    this->setStatus(tr("Apply failed: %1").arg(error), true);
    return;
  }
  if (auto* view = pqActiveObjects::instance().activeView())
    view->render();
  if (twoD)
  {
    const QJsonObject pv = QJsonDocument::fromJson(d.ParaView2D.toUtf8()).object();
    this->setStatus(tr("Applied to '%1' as ParaView 2D boxes (Edit > Undo takes it back; the Color "
                       "Map Editor's 2D editor shows them).")
                      .arg(this->Source->getSMName()));
    this->Ui->status->setToolTip(
      tr("%1 Gaussian boxes fitted to the design: RMSE %2 of emission and "
         "per-sample opacity (largest opacity %3)")
        .arg(pv.value("Boxes").toArray().size() / 8)
        .arg(pv.value("Fit").toObject().value("rmse").toDouble(), 0, 'f', 4)
        .arg(pv.value("Fit").toObject().value("max_alpha").toDouble(), 0, 'f', 3));
    return;
  }
  this->setStatus(tr("Applied to '%1' (Edit > Undo takes it back; the Color Map Editor shows it).")
                    .arg(this->Source->getSMName()));
}

void pqDDGDesignGalleryDock::exportPreset()
{
  if (!this->State->ready(true) || this->State->design().Preset.isEmpty())
    return;
  const QString path = QFileDialog::getSaveFileName(
    this, tr("Export ParaView preset"), "design.json", tr("JSON (*.json)"));
  if (!path.isEmpty() && !writeText(path, this->State->design().Preset))
    this->setStatus(tr("Cannot write %1.").arg(path), true);
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
