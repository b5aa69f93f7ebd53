// pqDDGQueryBox.h: the "Query with a picture" box of the Design Gallery panel: an image file (its
// path, "...", or a drop on the panel) or the clipboard's image, sent to the state's query; the
// query's nearest designs as thumbnails under it (a click shows one).
#pragma once

#include <QGroupBox>
#include <QImage>
#include <QVector>

#include <memory>

class pqDDGDesignState;
class QToolButton;
namespace Ui
{
class pqDDGQueryBox;
}

class pqDDGQueryBox : public QGroupBox
{
  Q_OBJECT

public:
  explicit pqDDGQueryBox(QWidget* parent = nullptr);
  ~pqDDGQueryBox() override;

  /// The state it queries; its queries' nearest designs show under the box from then on.
  void setState(pqDDGDesignState* state);
  /// Shows the nearest designs' thumbnails (rows of the outline) with each one's figure against
  /// the picture (dB; NaN: none shown); none: the row hides.
  void showNeighbours(const QVector<int>& rows, const QVector<QImage>& thumbnails,
    const QVector<double>& againstPicture);
  /// Shows `path` and queries with the image file there (a file on this machine: the client's).
  void queryPath(const QString& path);
  /// Queries with the image file at `path`.
  void queryFile(const QString& path);
  /// Queries with an image (from the clipboard or a drop); `name` is recorded in the history.
  void queryImage(const QImage& image, const QString& name);

public Q_SLOTS:
  /// Queries with the clipboard's image.
  void paste();

private Q_SLOTS:
  void browse();
  void run();

private:
  std::unique_ptr<Ui::pqDDGQueryBox> Ui;
  pqDDGDesignState* State = nullptr;
  QVector<QToolButton*> NeighbourButtons;
};
