// pqDDGDesignStateSteps.cxx: the history steps the Design Gallery panel writes (the ddg history
// JSON of README "File contracts", read by DDG Design and `ddg replay`). Every step the panel
// makes is built here and nowhere else, so that these few functions can be replaced by the
// Core-backed history helper of the Filters module in one place.
#include "pqDDGDesignState.h"

#include <QJsonDocument>

QJsonObject pqDDGDesignState::pickStep(int row)
{
  return QJsonObject{ { "action", "pick" }, { "row", row } };
}

QJsonObject pqDDGDesignState::latentStep(const QJsonArray& latent, const QString& image)
{
  QJsonObject step{ { "action", "latent" }, { "latent", latent } };
  if (!image.isEmpty())
    step["image"] = image;
  return step;
}

QJsonObject pqDDGDesignState::blendStep(const QJsonArray& latents, double u, double v)
{
  return QJsonObject{ { "action", "blend" }, { "latents", latents }, { "u", u }, { "v", v } };
}

QJsonObject pqDDGDesignState::editStep(
  const QJsonObject& view, int cluster, double hue, double visibility)
{
  return QJsonObject{ { "action", "edit" }, { "view", view }, { "cluster", cluster },
    { "clusters", 4 }, { "hue", hue }, { "saturation", 1.0 }, { "lightness", 0.0 },
    { "visibility", visibility }, { "white", false } };
}

QJsonObject pqDDGDesignState::axesStep(const QVector<double>& steps)
{
  QJsonArray values;
  for (double s : steps)
    values.append(s);
  return QJsonObject{ { "action", "axes" }, { "steps", values } };
}

QJsonArray pqDDGDesignState::appendStep(QJsonArray steps, const QJsonObject& step)
{
  const bool axes = step.value("action") == "axes";
  if (axes && !steps.isEmpty() && steps.last().toObject().value("action") == "axes")
    steps[steps.size() - 1] = step; // the sliders move one step (QJsonArray::last() is a copy)
  else
    steps.append(step);
  return steps;
}

QString pqDDGDesignState::historyText(const QJsonArray& steps)
{
  QJsonObject h;
  h["format"] = "ddg-history";
  h["version"] = 1;
  h["steps"] = steps;
  return QString::fromUtf8(QJsonDocument(h).toJson(QJsonDocument::Indented));
}
