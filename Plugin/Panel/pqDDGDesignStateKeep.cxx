// pqDDGDesignStateKeep.cxx: what the Design Gallery panel keeps of a volume while another one is
// selected (its model, query, design, match, pins, locks and outline zoom), and brings back when
// the volume is selected again and its model loaded.
#include "pqDDGDesignState.h"

#include <vtkSMSourceProxy.h>

#include <QJsonArray>

#include <algorithm>
#include <cmath>

namespace
{
/// A camera's direction of view (unit), its distance and parallel scale, from a view JSON.
bool cameraOf(const QJsonObject& view, double direction[3], double& distance, double& scale)
{
  const QJsonObject c = view.value("camera").toObject();
  const QJsonArray p = c.value("position").toArray(), f = c.value("focal_point").toArray();
  if (p.size() != 3 || f.size() != 3)
    return false;
  double n = 0;
  for (int k = 0; k < 3; ++k)
  {
    direction[k] = f[k].toDouble() - p[k].toDouble();
    n += direction[k] * direction[k];
  }
  distance = std::sqrt(n);
  if (!(distance > 0))
    return false;
  for (int k = 0; k < 3; ++k)
    direction[k] /= distance;
  scale = c.value("parallel_scale").toDouble(1.0);
  return true;
}

unsigned int keyOf(vtkSMSourceProxy* source)
{
  return source ? source->GetGlobalID() : 0;
}
} // namespace

bool pqDDGDesignState::thumbnailsOutdated(const QJsonObject& view) const
{
  if (this->Loaded && !view.isEmpty() &&
    view.value("lighting").toObject() != this->ThumbnailLighting)
    return true; // Shade (or its coefficients) changed: thumbnails look as the volume is shown
  if (!this->Loaded || !this->ThumbnailsAtCamera || view.isEmpty())
    return false;
  double a[3], b[3], da = 0, db = 0, sa = 0, sb = 0;
  if (!cameraOf(view, a, da, sa))
    return false;
  if (!cameraOf(this->ThumbnailView, b, db, sb))
    return true; // rendered at the volume's default view: now there is a camera
  const double cosine = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const bool parallel = view.value("camera").toObject().value("parallel_projection").toBool();
  const double ratio = parallel ? sa / std::max(1e-12, sb) : da / std::max(1e-12, db);
  return cosine < std::cos(30.0 * 3.14159265358979 / 180) ||
    std::max(ratio, 1 / std::max(1e-12, ratio)) > 1.5;
}

QString pqDDGDesignState::keptModel(vtkSMSourceProxy* source) const
{
  const auto it = this->KeptStates.constFind(keyOf(source));
  return it == this->KeptStates.constEnd() ? QString() : it->ModelDirectory;
}

void pqDDGDesignState::keepVolumeState()
{
  if (!this->Source || !this->Loaded || this->ModelDirectory.isEmpty())
    return;
  Kept k;
  k.ModelDirectory = this->ModelDirectory;
  k.Boxes = this->Boxes;
  k.Seed = this->Seed;
  k.Steps = this->Steps;
  k.LockSteps = this->LockSteps;
  k.Locked = this->Locked;
  k.Pins = this->Pins;
  k.QueryPicture = this->QueryPicture;
  k.QueryName = this->QueryName;
  k.QueryPSNR = this->QueryPSNR;
  k.QueryLit = this->QueryLit;
  k.QueryKind = this->QueryKind;
  k.Queried = this->Queried;
  k.QueryPosition = this->QueryPosition;
  k.QueryNeighbours = this->QueryNeighbours;
  k.QueryThumbnails = this->QueryThumbnails;
  k.QueryNeighbourPSNR = this->QueryNeighbourPSNR;
  k.LastMatch = this->LastMatch;
  this->KeptStates.insert(keyOf(this->Source), k);
}

void pqDDGDesignState::putKept(const Kept& kept)
{
  this->KeptStates.insert(keyOf(this->Source), kept);
}

bool pqDDGDesignState::takeKept(const QString& directory, Kept& kept)
{
  const unsigned int key = keyOf(this->Source);
  const auto it = this->KeptStates.find(key);
  if (it == this->KeptStates.end())
    return false;
  if (it->ModelDirectory != directory) // another model on this volume: its state starts afresh
  {
    this->KeptStates.erase(it);
    return false;
  }
  kept = this->KeptStates.take(key);
  return true;
}

void pqDDGDesignState::restoreVolumeState(Kept& kept)
{
  for (const Pin& p : kept.Pins)
  {
    this->Pins.push_back(p);
    Q_EMIT this->pinAdded();
  }
  this->QueryPicture = kept.QueryPicture;
  this->QueryName = kept.QueryName;
  this->QueryPSNR = kept.QueryPSNR;
  this->QueryLit = kept.QueryLit;
  this->QueryKind = kept.QueryKind;
  this->Queried = kept.Queried;
  this->QueryPosition = kept.QueryPosition;
  this->QueryNeighbours = kept.QueryNeighbours;
  this->QueryThumbnails = kept.QueryThumbnails;
  this->QueryNeighbourPSNR = kept.QueryNeighbourPSNR;
  if (this->Queried)
    Q_EMIT this->queried(
      this->QueryPosition, this->QueryNeighbours, this->QueryThumbnails, this->QueryNeighbourPSNR);
  this->Locked = kept.Locked;
  this->LockSteps = kept.LockSteps;
  if (!kept.Steps.isEmpty() && this->setSteps(kept.Steps))
  {
    const QJsonObject last = kept.Steps.last().toObject();
    if (last.value("action").toString() == "axes")
    {
      QVector<double> steps;
      for (const auto& v : last.value("steps").toArray())
        steps.push_back(v.toDouble());
      Q_EMIT this->axesRestored(steps);
    }
  }
  // the match last: a design's update above leaves it as it was
  this->LastMatch = kept.LastMatch;
  Q_EMIT this->matchChanged();
  this->report(tr("'%1' as you left it: %2%3%4.")
                 .arg(this->volumeName())
                 .arg(kept.Steps.isEmpty() ? tr("no design yet") : tr("its design"))
                 .arg(kept.Pins.isEmpty()    ? QString()
                     : kept.Pins.size() == 1 ? tr(", 1 pin")
                                             : tr(", %1 pins").arg(kept.Pins.size()))
                 .arg(this->QueryPicture.isEmpty() ? QString() : tr(", the query's picture")));
}
