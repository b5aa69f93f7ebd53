// pqDDGDesignStateQuery.cxx: the panel state's query with a picture (DDG Query): the design the
// analyzer reads from it, its place on the outline and its nearest designs with their thumbnails.
#include "pqDDGDesignState.h"

#include "pqDDGScene.h"

#include <vtkDataArray.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMSourceProxy.h>
#include <vtkTable.h>

#include <QJsonDocument>

#include <limits>

void pqDDGDesignState::query(const QByteArray& imageFile, const QString& name)
{
  const ddgpanel::NoUndo quiet; // the panel's own proxies (its steps are Apply's alone)
  if (!this->hasVolume())
    return;
  if (!this->Loaded) // no design space: the picture is what Match fits, from grey
  {
    this->dropQueryPicture();
    this->QueryPicture = imageFile;
    this->QueryName = name;
    this->QueryPSNR = std::numeric_limits<double>::quiet_NaN();
    this->QueryKind = QJsonObject();
    this->report(tr("No model for this volume: Match fits a transfer function (and the camera) "
                    "to '%1' without one. Build or Load a model to browse designs like it.")
                   .arg(name));
    Q_EMIT this->queryDone();
    return;
  }
  vtkSMPropertyHelper(this->QueryProxy, "ImageData").Set(imageFile.toBase64().constData());
  const QJsonObject view = this->currentView(PreviewSide);
  vtkSMPropertyHelper(this->QueryProxy, "ViewJSON")
    .Set(ddgpanel::jsonText(view).toUtf8().constData());
  vtkSMPropertyHelper(this->QueryProxy, "Neighbours").Set(QueryNeighbourCount);
  vtkSMPropertyHelper(this->QueryProxy, "ThumbnailSize").Set(ThumbnailSize);
  if (this->QueryProxy->GetProperty("KindNetwork")) // is the picture of this kind of volume?
    vtkSMPropertyHelper(this->QueryProxy, "KindNetwork")
      .Set(pqDDGDesignState::kindNetwork().toUtf8().constData());
  this->QueryProxy->UpdateVTKObjects();
  this->QueryProxy->UpdatePipeline();
  vtkSmartPointer<vtkTable> table = vtkTable::SafeDownCast(ddgpanel::fetch(this->QueryProxy, 1));
  vtkSMPropertyHelper(this->QueryProxy, "ImageData").Set(""); // do not keep megabytes around
  this->QueryProxy->UpdateVTKObjects();
  if (!table) // the last query (its picture, nearest designs and match) stays as it was
  {
    this->report(
      tr("The query failed ('%1'): %2").arg(name, ddgpanel::lastError(this->QueryProxy)), true);
    return;
  }
  this->dropQueryPicture();
  this->QueryPicture = imageFile; // what Match fits, even if the design below cannot be made
  this->QueryName = name;
  QVector<int> neighbours;
  QVector<double> nearAgainst; // each against the picture (with the thumbnails)
  vtkDataArray* rows = vtkDataArray::SafeDownCast(table->GetColumnByName("Row"));
  vtkDataArray* figures =
    vtkDataArray::SafeDownCast(table->GetColumnByName("NeighbourPicturePSNR"));
  for (vtkIdType i = 0; rows && i < rows->GetNumberOfTuples(); ++i)
  {
    neighbours.push_back(static_cast<int>(rows->GetTuple1(i)));
    nearAgainst.push_back(
      figures ? figures->GetTuple1(i) : std::numeric_limits<double>::quiet_NaN());
  }
  const QJsonArray position = ddgpanel::fieldNumbers(table, "Position");
  const QJsonArray latent = ddgpanel::fieldNumbers(table, "Latent");
  this->Queried = position.size() == 2;
  if (this->Queried)
  {
    this->QueryPosition = QPointF(position[0].toDouble(), position[1].toDouble());
    this->QueryNeighbours = neighbours;
    this->QueryThumbnails = ddgpanel::sheetCells(
      ddgpanel::imageOf(ddgpanel::fetch(this->QueryProxy, 2)), neighbours.size(), ThumbnailSize);
    this->QueryNeighbourPSNR = nearAgainst;
    Q_EMIT this->queried(
      this->QueryPosition, neighbours, this->QueryThumbnails, this->QueryNeighbourPSNR);
  }
  if (this->setSteps(QJsonArray{ latentStep(latent, name) }))
  {
    const QJsonArray against = ddgpanel::fieldNumbers(table, "PicturePSNR");
    this->QueryPSNR =
      against.isEmpty() ? std::numeric_limits<double>::quiet_NaN() : against[0].toDouble();
    const QJsonArray lit = ddgpanel::fieldNumbers(table, "PictureLit");
    this->QueryLit = !lit.isEmpty() && lit[0].toDouble() != 0;
    const QString warning = ddgpanel::fieldText(table, "Warning");
    if (!warning.isEmpty()) // the filter's VTK warning is in Output Messages already
      this->report(tr("Query with '%1': %2.").arg(name, warning));
    this->QueryKind = QJsonDocument::fromJson(ddgpanel::fieldText(table, "Kind").toUtf8()).object();
    if (this->QueryKind.value("differs").toBool())
      this->report(tr("Query with '%1': %2. The design is this model's nearest reading of it.")
                     .arg(name, kindText(this->QueryKind)),
        true);
    Q_EMIT this->queryDone();
  }
}

void pqDDGDesignState::dropQueryPicture()
{
  if (this->hasMatch() || !this->QueryPicture.isEmpty())
  {
    this->QueryPicture.clear(); // a new picture: the match of the last one goes
    this->QueryPSNR = std::numeric_limits<double>::quiet_NaN(); // and its figures
    this->QueryLit = false;
    this->QueryKind = QJsonObject();
    this->LastMatch = Match();
    Q_EMIT this->matchChanged();
  }
}

double pqDDGDesignState::neighbourPicturePSNR(int row) const
{
  const int k = this->QueryNeighbours.indexOf(row);
  return k < 0 ? std::numeric_limits<double>::quiet_NaN()
               : this->QueryNeighbourPSNR.value(k, std::numeric_limits<double>::quiet_NaN());
}
