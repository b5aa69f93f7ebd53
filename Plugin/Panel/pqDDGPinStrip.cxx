// pqDDGPinStrip.cxx: pins, navigation pad and animation of the Design Gallery panel.
#include "pqDDGPinStrip.h"
#include "ui_pqDDGPinStrip.h"

#include "pqDDGDesignState.h"
#include "pqDDGNavigationPad.h"
#include "pqDDGScene.h"

#include <pqActiveObjects.h>
#include <pqDataRepresentation.h>
#include <pqRenderView.h>
#include <pqSaveScreenshotReaction.h>

#include <QApplication>
#include <QDir>
#include <QFileDialog>
#include <QTimer>

#include <algorithm>

pqDDGPinStrip::pqDDGPinStrip(QWidget* parent)
  : QGroupBox(parent)
  , Ui(new Ui::pqDDGPinStrip)
{
  this->Ui->setupUi(this);
  this->NavigateTimer = new QTimer(this);
  this->NavigateTimer->setSingleShot(true);
  this->NavigateTimer->setInterval(150);
  QObject::connect(this->Ui->unpin, &QPushButton::clicked, this, &pqDDGPinStrip::unpin);
  QObject::connect(
    this->Ui->pins, &QListWidget::itemSelectionChanged, this, &pqDDGPinStrip::updatePad);
  QObject::connect(this->Ui->pad, &pqDDGNavigationPad::moved, this->NavigateTimer,
    QOverload<>::of(&QTimer::start));
  QObject::connect(this->NavigateTimer, &QTimer::timeout, this, &pqDDGPinStrip::navigate);
  QObject::connect(this->Ui->animate, &QPushButton::clicked, this, &pqDDGPinStrip::animate);
}

pqDDGPinStrip::~pqDDGPinStrip() = default;

void pqDDGPinStrip::setState(pqDDGDesignState* state)
{
  this->State = state;
  QObject::connect(state, &pqDDGDesignState::pinAdded, this, &pqDDGPinStrip::addPin);
  QObject::connect(state, &pqDDGDesignState::modelCleared, this, &pqDDGPinStrip::clear);
}

void pqDDGPinStrip::addPin()
{
  const auto& pins = this->State->pins();
  auto* item =
    new QListWidgetItem(QIcon(QPixmap::fromImage(pins.last().Icon)), QString::number(pins.size()));
  this->Ui->pins->addItem(item);
  this->updatePad();
}

void pqDDGPinStrip::unpin()
{
  QVector<int> rows;
  for (auto* item : this->Ui->pins->selectedItems())
    rows.push_back(this->Ui->pins->row(item));
  std::sort(rows.begin(), rows.end(), std::greater<int>());
  for (int r : rows)
    delete this->Ui->pins->takeItem(r);
  this->State->unpin(rows);
  this->updatePad();
}

void pqDDGPinStrip::clear()
{
  this->Ui->pins->clear();
  this->Ui->pad->setAnchors({});
}

void pqDDGPinStrip::updatePad()
{
  // the selected pins when 2-4 are selected, else the first (up to) four
  QList<int> chosen;
  for (auto* item : this->Ui->pins->selectedItems())
    chosen.push_back(this->Ui->pins->row(item));
  std::sort(chosen.begin(), chosen.end());
  const auto& pins = this->State->pins();
  if (chosen.size() < 2 || chosen.size() > 4)
  {
    chosen.clear();
    for (int k = 0; k < std::min(4, static_cast<int>(pins.size())); ++k)
      chosen.push_back(k);
  }
  QVector<QImage> icons;
  for (int k : chosen)
    icons.push_back(pins[k].Icon);
  this->Chosen = chosen;
  this->Ui->pad->setAnchors(icons.size() >= 2 ? icons : QVector<QImage>());
}

void pqDDGPinStrip::navigate()
{
  this->State->navigate(this->Chosen, this->Ui->pad->u(), this->Ui->pad->v());
}

void pqDDGPinStrip::animate()
{
  pqDDGDesignState* state = this->State;
  if (!state->ready() || state->pins().size() < 2)
  {
    state->report(tr("Pin at least two designs to animate between them."), true);
    return;
  }
  auto* view = qobject_cast<pqRenderView*>(pqActiveObjects::instance().activeView());
  pqDataRepresentation* repr = ddgpanel::representation(state->volume());
  if (!view || !repr)
  {
    state->report(tr("Open a render view showing the volume first."), true);
    return;
  }
  const QString dir = QFileDialog::getExistingDirectory(this, tr("Directory of the PNG frames"));
  if (dir.isEmpty())
    return;
  const QString before = ddgpanel::currentPreset(repr);
  const QJsonArray stepsBefore = state->steps();
  const int perLeg = this->Ui->frames->value();
  const int legs = static_cast<int>(state->pins().size()) - 1;
  const QSize size = view->getSize();
  state->setBusy(true);
  int written = 0;
  QString error;
  for (int leg = 0; leg < legs && error.isEmpty() && !state->isCancelled(); ++leg)
    for (int f = (leg == 0 ? 0 : 1); f < perLeg && error.isEmpty() && !state->isCancelled(); ++f)
    {
      const double t = perLeg > 1 ? static_cast<double>(f) / (perLeg - 1) : 1.0;
      const double eased = t * t * (3 - 2 * t); // smoothstep, as ddg animate
      const QJsonArray latents{ state->pins()[leg].Latent, state->pins()[leg + 1].Latent };
      if (!state->setSteps(QJsonArray{ pqDDGDesignState::blendStep(latents, eased, 0.0) }, false))
      {
        error = state->lastMessage();
        break;
      }
      error = ddgpanel::applyPreset(repr, state->array(), state->design().Preset, QString(), false);
      view->forceRender();
      const QString file =
        QDir(dir).filePath(QString("frame_%1.png").arg(written, 4, 10, QChar('0')));
      if (error.isEmpty() && !pqSaveScreenshotReaction::saveScreenshot(file, size, -1))
        error = tr("cannot write %1").arg(file);
      ++written;
      Q_EMIT this->progress(100 * written / std::max(1, legs * (perLeg - 1) + 1));
      QApplication::processEvents();
    }
  state->setBusy(false);
  // the scene as it was
  ddgpanel::applyPreset(repr, state->array(), before, QString(), false);
  view->render();
  state->setSteps(stepsBefore, false);
  state->report(!error.isEmpty() ? tr("Animation stopped: %1").arg(error)
      : state->isCancelled()     ? tr("Animation cancelled after %1 frames.").arg(written)
                                 : tr("Wrote %1 frames to %2.").arg(written).arg(dir),
    !error.isEmpty());
}
