// pqDDGDesignStateSteps.cxx: the history steps the Design Gallery panel writes (the ddg history
// JSON of README "File contracts", read by DDG Design and `ddg replay`), built by Core's history
// through vtkDDGDesignHistory (DDG::Filters), the one writer `ddg`, the filters and pvpython use.
// The state keeps its steps as JSON; these functions are the only place they are made.
#include "pqDDGDesignState.h"

#include <vtkDDGDesignHistory.h>
#include <vtkNew.h>

#include <QJsonDocument>

namespace
{
std::string compact(const QJsonValue& value)
{
  const QJsonDocument doc =
    value.isArray() ? QJsonDocument(value.toArray()) : QJsonDocument(value.toObject());
  return doc.toJson(QJsonDocument::Compact).toStdString();
}

QJsonArray stepsOf(vtkDDGDesignHistory* history)
{
  const QByteArray text = QByteArray::fromStdString(history->GetJSON());
  return QJsonDocument::fromJson(text).object().value("steps").toArray();
}

/// The last step of `history` (the one just added), or {} when it refused it.
QJsonObject lastStep(vtkDDGDesignHistory* history)
{
  const QJsonArray steps = stepsOf(history);
  return steps.isEmpty() ? QJsonObject() : steps.last().toObject();
}

/// The history JSON of `steps` as the panel holds them (before Core reads it).
QByteArray rawHistory(const QJsonArray& steps)
{
  return QJsonDocument(
    QJsonObject{ { "format", "ddg-history" }, { "version", 1 }, { "steps", steps } })
    .toJson(QJsonDocument::Indented);
}
} // namespace

QJsonObject pqDDGDesignState::pickStep(int row)
{
  vtkNew<vtkDDGDesignHistory> h;
  h->AddPick(row);
  return lastStep(h);
}

QJsonObject pqDDGDesignState::latentStep(const QJsonArray& latent, const QString& image)
{
  vtkNew<vtkDDGDesignHistory> h;
  h->AddLatent(compact(latent), image.toStdString());
  return lastStep(h);
}

QJsonObject pqDDGDesignState::blendStep(const QJsonArray& latents, double u, double v)
{
  vtkNew<vtkDDGDesignHistory> h;
  h->AddBlend(compact(latents), u, v);
  return lastStep(h);
}

QJsonObject pqDDGDesignState::editStep(
  const QJsonObject& view, int cluster, double hue, double visibility)
{
  vtkNew<vtkDDGDesignHistory> h; // saturation 1, lightness 0, on black, 4 colour clusters
  h->AddEdit(compact(view), cluster, -1, -1, 4, hue, 1.0, 0.0, visibility, false);
  return lastStep(h);
}

QJsonObject pqDDGDesignState::axesStep(const QVector<double>& steps)
{
  QJsonArray values;
  for (double s : steps)
    values.append(s);
  vtkNew<vtkDDGDesignHistory> h;
  h->SetAxes(compact(values));
  return lastStep(h);
}

QJsonObject pqDDGDesignState::matchStep(const Match& match)
{
  vtkNew<vtkDDGDesignHistory> h; // the panel matches with the filter's 128 bins and 500 steps
  h->AddMatch(match.Picture.toStdString(), compact(match.View), match.CameraEstimated,
    match.Preset.toStdString(), !match.ParaView2D.isEmpty(), 128, 500);
  return lastStep(h);
}

QJsonArray pqDDGDesignState::exportSteps() const
{
  QJsonArray steps = this->Steps;
  if (!this->LastMatch.Preset.isEmpty() && this->LastMatch.Steps == this->Steps)
  {
    const QJsonObject step = matchStep(this->LastMatch);
    if (!step.isEmpty())
      steps.append(step);
  }
  return steps;
}

QJsonArray pqDDGDesignState::appendStep(QJsonArray steps, const QJsonObject& step)
{
  vtkNew<vtkDDGDesignHistory> h;
  if (step.value("action") != "axes" || !h->SetJSON(rawHistory(steps).toStdString()) ||
    !h->SetAxes(compact(step.value("steps"))))
  {
    steps.append(step);
    return steps;
  }
  return stepsOf(h); // an axes step after an axes step replaces it: the sliders move one step
}

QString pqDDGDesignState::historyText(const QJsonArray& steps)
{
  vtkNew<vtkDDGDesignHistory> h;
  const QByteArray raw = rawHistory(steps);
  // steps Core cannot read go as they are: DDG Design then says what is wrong with them
  return QString::fromStdString(h->SetJSON(raw.toStdString()) ? h->GetJSON() : raw.toStdString());
}
