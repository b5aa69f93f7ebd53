// pqDDGBuildDialog.h: the Design Gallery panel's Build dialog: the bundle's folder (on the
// server), the budget (2 / 10 / 30 minutes or a number) and what the build will cost (its plan:
// stages with their estimated minutes, disk use), asked of the server before OK.
#pragma once

#include <QDialog>
#include <QJsonObject>

#include <functional>
#include <memory>

class pqServer;
namespace Ui
{
class pqDDGBuildDialog;
}

class pqDDGBuildDialog : public QDialog
{
  Q_OBJECT

public:
  /// The plan of a build into `folder` within `minutes` (BuildPlan JSON, pqDDGDesignState).
  using Planner = std::function<QJsonObject(const QString& folder, double minutes)>;

  pqDDGBuildDialog(pqServer* server, Planner planner, QWidget* parent = nullptr);
  ~pqDDGBuildDialog() override;

  /// Fills in a build's folder and budget (the last one the panel started that left no bundle:
  /// cancelled or failed, so that trying again is one click); an empty folder keeps the field.
  void offer(const QString& folder, double minutes);

  QString folder() const;
  /// The budget chosen, in minutes.
  double budgetMinutes() const;
  /// The folder holds a bundle and the user said to replace it.
  bool overwrite() const { return this->Overwrite; }

public Q_SLOTS:
  void accept() override;

private:
  void updatePlan();

  std::unique_ptr<Ui::pqDDGBuildDialog> Ui;
  pqServer* Server;
  Planner Plan;
  QJsonObject LastPlan;
  bool Overwrite = false;
};
