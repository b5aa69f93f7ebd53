// pqDDGQueryBox.h: the "Query with a picture" box of the Design Gallery panel: an image file (its
// path, "...", or a drop on the panel) or the clipboard's image, sent to the state's query.
#pragma once

#include <QGroupBox>

#include <memory>

class pqDDGDesignState;
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

  void setState(pqDDGDesignState* state) { this->State = state; }
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
};
