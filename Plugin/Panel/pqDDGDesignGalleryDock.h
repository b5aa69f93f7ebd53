// pqDDGDesignGalleryDock.h: the "Design Gallery" dock panel. Client only: its layout comes from
// pqDDGDesignGalleryDock.ui, its state (filter proxies on the active volume, history steps, the
// current design, pins, lock) is a pqDDGDesignState, the pinned designs are a pqDDGPinStrip. The
// dock follows the active source, forwards the user's actions to the state, shows what the
// state reports and writes the chosen design's (or the match's) transfer function into the
// active representation's maps as one undoable step (the match's with the picture's camera).
#pragma once

#include <QDockWidget>
#include <QImage>
#include <QPointer>

#include <functional>
#include <memory>

class QCheckBox;
class QTimer;
class pqDDGDesignState;
class pqDataRepresentation;
class pqPipelineSource;
namespace Ui
{
class pqDDGDesignGalleryDock;
}

class pqDDGDesignGalleryDock : public QDockWidget
{
  Q_OBJECT

public:
  explicit pqDDGDesignGalleryDock(QWidget* parent = nullptr);
  ~pqDDGDesignGalleryDock() override;

  /// Queries with the image file at `path` (a file on this machine: the client's).
  void queryFile(const QString& path);
  /// Queries with an image (from the clipboard or a drop); `name` is recorded in the history.
  void queryImage(const QImage& image, const QString& name);

protected:
  void dragEnterEvent(QDragEnterEvent*) override;
  void dropEvent(QDropEvent*) override;

private Q_SLOTS:
  void setSource(pqPipelineSource* source);
  void loadModel();
  void browseModel();
  void buildModel();
  void showBuildProgress(const QString& stage, double fraction, double secondsLeft);
  void buildFinished(bool built, const QString& directory);
  void axesReleased();
  void lockChanged();
  void apply();
  void runMatch();
  void applyMatch();
  void showMatch();
  void showMatchProgress(const QString& stage, double fraction, const QImage& preview);
  void exportPreset();
  void exportSlicer();
  void exportHistory();
  void setStatus(const QString& text, bool error = false);
  void clearModel();
  void showDesign();

private:
  void connectWidgets();
  void connectState();
  /// Apply's one undo step named `label`: when other volumes share the colour map, asks whether
  /// to give this volume its own (ParaView's separate colour map), recolour them all, or cancel;
  /// then `write` (the TF, the camera; returns an error or ""). On an error the step is taken
  /// back. True when written (`note`: what the status adds); otherwise the status already says
  /// why (cancelled, or the error).
  bool writeToScene(pqDataRepresentation* repr, const QString& label,
    const std::function<QString()>& write, QString& note);

  std::unique_ptr<Ui::pqDDGDesignGalleryDock> Ui;
  pqDDGDesignState* State;
  QVector<QCheckBox*> Locks;
  QTimer* BoxTimer;
  QPointer<pqPipelineSource> Source;
  QMetaObject::Connection ViewWatch; ///< the active view's renders (thumbnails follow the camera)
  /// what Build... offers: the last build's budget, and its folder while it left no bundle
  QString BuildFolder;
  double BuildMinutes = 0;
};
