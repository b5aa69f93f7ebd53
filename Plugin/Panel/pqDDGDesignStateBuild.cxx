// pqDDGDesignStateBuild.cxx: building a model for the volume in the background on the server
// (DDG Build Design Space's StartBuild / CancelBuild / PlanBuild, its Build* information polled).
#include "pqDDGDesignState.h"

#include "pqDDGScene.h"

#include <vtkDataObject.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMSourceProxy.h>

#include <QEventLoop>
#include <QJsonDocument>
#include <QTimer>

namespace
{
QString text(vtkSMSourceProxy* proxy, const char* name)
{
  return QString::fromUtf8(vtkSMPropertyHelper(proxy, name).GetAsString());
}

/// The build's settings on a DDG Build Design Space proxy (the plan and the build use the same).
void setBuild(vtkSMSourceProxy* proxy, const QString& directory, const QString& array,
  double budgetMinutes, bool overwrite)
{
  vtkSMPropertyHelper(proxy, "OutputDirectory").Set(directory.toUtf8().constData());
  vtkSMPropertyHelper(proxy, "SelectInputScalars")
    .SetInputArrayToProcess(vtkDataObject::POINT, array.toUtf8().constData());
  vtkSMPropertyHelper(proxy, "BudgetMinutes").Set(budgetMinutes);
  vtkSMPropertyHelper(proxy, "Overwrite").Set(overwrite ? 1 : 0);
  proxy->UpdateVTKObjects();
}
} // namespace

QJsonObject pqDDGDesignState::planBuild(
  const QString& directory, double budgetMinutes, bool overwrite)
{
  const ddgpanel::NoUndo quiet; // the panel's own proxies (its steps are Apply's alone)
  if (!this->Source || this->Array.isEmpty())
    return { { "error", tr("Select a volume first.") } };
  if (!this->PlanProxy || this->PlanSource != this->Source)
  {
    this->PlanProxy = ddgpanel::newFilter("DDGBuildDesignSpace", this->Source, 0);
    this->PlanSource = this->Source;
  }
  vtkSMSourceProxy* proxy = this->PlanProxy;
  if (!proxy)
    return { { "error", tr("The DesignGallery plugin is not loaded on the server.") } };
  setBuild(proxy, directory, this->Array, budgetMinutes, overwrite);
  proxy->InvokeCommand("PlanBuild");
  proxy->UpdatePropertyInformation();
  return QJsonDocument::fromJson(text(proxy, "BuildPlan").toUtf8()).object();
}

bool pqDDGDesignState::startBuild(const QString& directory, double budgetMinutes, bool overwrite)
{
  const ddgpanel::NoUndo quiet; // the panel's own proxies (its steps are Apply's alone)
  if (this->BuildProxy)
  {
    this->report(tr("A build is already running."), true);
    return false;
  }
  if (!this->Source || this->Array.isEmpty())
  {
    this->report(tr("Select a volume first."), true);
    return false;
  }
  // the dialog's proxy when it planned for this volume (the build follows the plan shown)
  this->BuildProxy = this->PlanProxy && this->PlanSource == this->Source
    ? this->PlanProxy
    : ddgpanel::newFilter("DDGBuildDesignSpace", this->Source, 0);
  this->PlanProxy = nullptr;
  if (!this->BuildProxy)
  {
    this->report(tr("The DesignGallery plugin is not loaded on the server."), true);
    return false;
  }
  vtkSMSourceProxy* proxy = this->BuildProxy;
  setBuild(proxy, directory, this->Array, budgetMinutes, overwrite);
  this->BuildDirectory = directory;
  this->setBusy(true);
  this->report(tr("Building a design space in %1 (Cancel stops it)...").arg(directory));
  proxy->InvokeCommand("StartBuild");
  if (!this->BuildTimer)
  {
    this->BuildTimer = new QTimer(this);
    this->BuildTimer->setInterval(250);
    QObject::connect(this->BuildTimer, &QTimer::timeout, this, &pqDDGDesignState::pollBuild);
  }
  this->BuildTimer->start();
  this->pollBuild(); // bad input fails at once
  return this->BuildProxy != nullptr;
}

void pqDDGDesignState::pollBuild()
{
  vtkSMSourceProxy* proxy = this->BuildProxy;
  if (!proxy)
    return;
  proxy->UpdatePropertyInformation();
  const QString state = text(proxy, "BuildState");
  if (state == "running" || state == "idle")
  {
    Q_EMIT this->buildProgress(text(proxy, "BuildStage"),
      vtkSMPropertyHelper(proxy, "BuildProgress").GetAsDouble(),
      vtkSMPropertyHelper(proxy, "BuildSecondsLeft").GetAsDouble());
    return;
  }
  this->BuildTimer->stop();
  const double minutes = vtkSMPropertyHelper(proxy, "BuildSecondsElapsed").GetAsDouble() / 60;
  vtkSMPropertyHelper figures(proxy, "BuildFigures");
  const double psnr = figures.GetAsDouble(0), ssim = figures.GetAsDouble(1);
  const QString error = text(proxy, "BuildError");
  this->BuildProxy = nullptr; // deleting it joins its finished thread
  this->setBusy(false);
  const QString dir = this->BuildDirectory;
  if (state == "done")
  {
    this->report(tr("Built a design space in %1 min: held-out imitation %2 dB, SSIM %3.")
                   .arg(minutes, 0, 'f', 1)
                   .arg(psnr, 0, 'f', 1)
                   .arg(ssim, 0, 'f', 3));
    Q_EMIT this->buildFinished(true, dir);
    return;
  }
  if (state == "cancelled") // what the user asked for: not a warning in Output Messages
    this->report(tr("Build cancelled: nothing of it is left in %1.").arg(dir), false);
  else
    this->report(
      tr("The build failed: %1").arg(error.isEmpty() ? tr("see the Output Messages") : error),
      true);
  Q_EMIT this->buildFinished(false, dir);
}

void pqDDGDesignState::cancel()
{
  this->Cancelled = true;
  if (this->BuildProxy)
    this->BuildProxy->InvokeCommand("CancelBuild");
}

bool pqDDGDesignState::buildModel(const QString& directory, double budgetMinutes, bool overwrite)
{
  bool built = false;
  QEventLoop loop;
  auto connection = QObject::connect(this, &pqDDGDesignState::buildFinished, &loop,
    [&](bool ok, const QString&)
    {
      built = ok;
      loop.quit();
    });
  if (this->startBuild(directory, budgetMinutes, overwrite))
    loop.exec();
  QObject::disconnect(connection);
  return built;
}
