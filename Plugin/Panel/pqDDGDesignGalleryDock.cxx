// pqDDGDesignGalleryDock.cxx: the Design Gallery panel: widgets <-> state, source, apply, export.
#include "pqDDGDesignGalleryDock.h"
#include "ui_pqDDGDesignGalleryDock.h"

#include "pqDDGBuildDialog.h"
#include "pqDDGDesignState.h"
#include "pqDDGInputGuard.h"
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
#include <pqView.h>

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
      if (this->State->isBusy() && !this->State->isBuilding())
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
  // thumbnails follow the camera: rendered again 1.5 s after the renders stop, when the camera
  // moved far from the one they show (pqDDGDesignState::thumbnailsOutdated)
  auto* cameraTimer = new QTimer(this);
  cameraTimer->setSingleShot(true);
  cameraTimer->setInterval(1500);
  QObject::connect(cameraTimer, &QTimer::timeout, this,
    [this, cameraTimer]()
    {
      if (this->State->isBusy() || QApplication::mouseButtons() != Qt::NoButton)
      {
        cameraTimer->start(); // not while the user drags or the panel works
        return;
      }
      if (this->State->thumbnailsOutdated(
            this->State->currentView(pqDDGDesignState::ThumbnailSize)))
        this->State->refreshOutline(false); // the status line keeps its message
    });
  auto watchView = [this, cameraTimer](pqView* view)
  {
    QObject::disconnect(this->ViewWatch);
    if (view)
      this->ViewWatch =
        QObject::connect(view, &pqView::endRender, cameraTimer, QOverload<>::of(&QTimer::start));
  };
  QObject::connect(&pqActiveObjects::instance(), &pqActiveObjects::viewChanged, this, watchView);
  watchView(pqActiveObjects::instance().activeView());
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
    state, &pqDDGDesignState::buildProgress, this, &pqDDGDesignGalleryDock::showBuildProgress);
  QObject::connect(
    state, &pqDDGDesignState::buildFinished, this, &pqDDGDesignGalleryDock::buildFinished);
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
  QObject::connect(state, &pqDDGDesignState::axesRestored, this,
    [this](const QVector<double>& steps)
    {
      QSlider* axes[] = { this->Ui->axis0, this->Ui->axis1, this->Ui->axis2 };
      for (int k = 0; k < 3; ++k)
      {
        axes[k]->blockSignals(true);
        axes[k]->setValue(k < steps.size() ? static_cast<int>(std::lround(10 * steps[k])) : 0);
        axes[k]->blockSignals(false);
      }
    });
  QObject::connect(
    state, &pqDDGDesignState::designChanged, this, &pqDDGDesignGalleryDock::showDesign);
  QObject::connect(state, &pqDDGDesignState::queryDone, this,
    [this]()
    {
      if (this->State->isLoaded())
        this->showDesign(); // with its PSNR against the picture
      this->showMatch();    // the picture
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
  // the model this volume had before another was selected, else the shipped bundle named like
  // the volume's file; never another volume's model
  QString guess = this->State->keptModel(proxy);
  if (guess.isEmpty())
    guess = QString::fromStdString(vtkSMDDGScene::DefaultModelDirectory(proxy, DDG_DATA_DIR));
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
  if (!this->State->loadModel(dir) && this->State->isLoaded()) // the model before, given back
    this->Ui->modelPath->setText(this->State->modelDirectory());
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
  pqDDGBuildDialog dialog(
    this->Source->getServer(),
    [this](const QString& folder, double minutes)
    { return this->State->planBuild(folder, minutes, false); },
    this);
  if (this->BuildMinutes > 0)
    dialog.offer(this->BuildFolder, this->BuildMinutes);
  if (dialog.exec() != QDialog::Accepted)
    return;
  this->BuildFolder = dialog.folder();
  this->BuildMinutes = dialog.budgetMinutes();
  // runs on the server in the background: ParaView stays usable, the panel shows its progress
  this->State->startBuild(dialog.folder(), dialog.budgetMinutes(), dialog.overwrite());
}

void pqDDGDesignGalleryDock::showBuildProgress(
  const QString& stage, double fraction, double secondsLeft)
{
  const int percent = static_cast<int>(std::lround(100 * fraction));
  QString left;
  if (secondsLeft >= 90)
    left = tr(" — about %1 min left").arg(std::lround(secondsLeft / 60));
  else if (secondsLeft >= 0)
    left = tr(" — about %1 s left").arg(10 * std::lround(std::max(1.0, secondsLeft / 10)));
  QString name = stage.isEmpty() ? tr("Starting") : stage;
  name[0] = name[0].toUpper();
  this->Ui->progress->setValue(percent);
  this->Ui->progress->setFormat(tr("%1 — %2 %%3").arg(name).arg(percent).arg(left));
}

void pqDDGDesignGalleryDock::buildFinished(bool built, const QString& directory)
{
  this->Ui->progress->setFormat("%p%");
  if (!built)
  {
    this->Ui->progress->setValue(0);
    return;
  }
  this->BuildFolder.clear(); // a bundle is there now: the next build is offered no folder
  this->Ui->modelPath->setText(directory);
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
