// pqDDGBuildDialog.cxx: folder, budget and the plan's cost; asks before replacing a bundle.
#include "pqDDGBuildDialog.h"
#include "ui_pqDDGBuildDialog.h"

#include <pqFileDialog.h>

#include <QComboBox>
#include <QMessageBox>
#include <QPushButton>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace
{
constexpr double kBudgets[] = { 2, 10, 30 }; // the combo's first items; the last is "Custom"
}

pqDDGBuildDialog::pqDDGBuildDialog(pqServer* server, Planner planner, QWidget* parent)
  : QDialog(parent)
  , Ui(new Ui::pqDDGBuildDialog)
  , Server(server)
  , Plan(std::move(planner))
{
  this->Ui->setupUi(this);
  this->setObjectName("BuildDialog");
  this->Ui->budget->setCurrentIndex(1);
  this->Ui->minutes->setEnabled(false);
  this->Ui->buttons->button(QDialogButtonBox::Ok)->setObjectName("ok"); // for test scripts
  this->Ui->buttons->button(QDialogButtonBox::Cancel)->setObjectName("cancel");
  QObject::connect(this->Ui->buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  QObject::connect(this->Ui->buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  QObject::connect(this->Ui->budget, QOverload<int>::of(&QComboBox::currentIndexChanged), this,
    [this](int index)
    {
      this->Ui->minutes->setEnabled(index == 3);
      if (index < 3)
        this->Ui->minutes->setValue(kBudgets[index]);
      this->updatePlan();
    });
  QObject::connect(
    this->Ui->minutes, &QDoubleSpinBox::editingFinished, this, &pqDDGBuildDialog::updatePlan);
  QObject::connect(
    this->Ui->folder, &QLineEdit::editingFinished, this, &pqDDGBuildDialog::updatePlan);
  QObject::connect(this->Ui->folder, &QLineEdit::textChanged, this,
    [this]()
    { this->Ui->buttons->button(QDialogButtonBox::Ok)->setEnabled(!this->folder().isEmpty()); });
  QObject::connect(this->Ui->browse, &QPushButton::clicked, this,
    [this]()
    {
      pqFileDialog dialog(this->Server, this, tr("Folder of the new model bundle"));
      dialog.setObjectName("BuildDirectoryDialog");
      dialog.setFileMode(pqFileDialog::Directory);
      if (dialog.exec() == QDialog::Accepted && !dialog.getSelectedFiles().isEmpty())
      {
        this->Ui->folder->setText(dialog.getSelectedFiles().first());
        this->updatePlan();
      }
    });
  this->updatePlan();
}

pqDDGBuildDialog::~pqDDGBuildDialog() = default;

void pqDDGBuildDialog::offer(const QString& folder, double minutes)
{
  if (!folder.isEmpty())
    this->Ui->folder->setText(folder);
  const double* known = std::find(std::begin(kBudgets), std::end(kBudgets), minutes);
  const int index = static_cast<int>(known - std::begin(kBudgets)); // 3: Custom
  this->Ui->minutes->setValue(minutes);
  if (index == this->Ui->budget->currentIndex())
    this->updatePlan();
  else
    this->Ui->budget->setCurrentIndex(index); // plans again
}

QString pqDDGBuildDialog::folder() const
{
  return this->Ui->folder->text().trimmed();
}

double pqDDGBuildDialog::budgetMinutes() const
{
  return this->Ui->minutes->value();
}

void pqDDGBuildDialog::updatePlan()
{
  this->LastPlan = this->Plan ? this->Plan(this->folder(), this->budgetMinutes()) : QJsonObject();
  QString text;
  if (this->LastPlan.contains("error"))
    text = tr("<b>Cannot build:</b> %1").arg(this->LastPlan["error"].toString().toHtmlEscaped());
  else if (!this->LastPlan.isEmpty())
  {
    text =
      tr("<b>About %1 min</b><br>").arg(this->LastPlan["total_seconds"].toDouble() / 60, 0, 'f', 1);
    text += this->LastPlan["describe"].toString().toHtmlEscaped().replace("\n", "<br>");
    if (this->LastPlan.contains("output_error"))
      text +=
        tr("<br><b>Folder:</b> %1").arg(this->LastPlan["output_error"].toString().toHtmlEscaped());
  }
  this->Ui->plan->setText(text);
  this->adjustSize(); // the plan's lines (and the folder's problem) all shown
  this->Ui->buttons->button(QDialogButtonBox::Ok)->setEnabled(!this->folder().isEmpty());
}

void pqDDGBuildDialog::accept()
{
  this->Overwrite = false;
  if (this->LastPlan["output_error"].toString().contains("already holds a model bundle"))
  {
    QMessageBox question(QMessageBox::Question, tr("Replace the bundle?"),
      tr("%1 already holds a model bundle. Replace it with the new one (only once the build "
         "has finished)?")
        .arg(this->folder()),
      QMessageBox::Yes | QMessageBox::No, this);
    question.setObjectName("OverwriteQuestion");
    if (question.exec() != QMessageBox::Yes)
      return;
    this->Overwrite = true;
  }
  QDialog::accept();
}
