// pqDDGDesignGalleryDock.h: the "Design Gallery" dock panel. Client only: it drives the
// server-side filters (DDG Design Gallery, DDG Query, DDG Design, DDG Build Design Space)
// through unregistered proxies on the active source, fetches their small results (thumbnail
// sheet, outline coordinates, preview, preset text) and writes the chosen design's transfer
// function into the active representation's colour and opacity maps as one undoable step.
#pragma once

#include <QDockWidget>
#include <QImage>
#include <QJsonArray>
#include <QJsonObject>
#include <QPointer>
#include <QRectF>
#include <QVector>

#include <vtkSmartPointer.h>

class QCheckBox;
class QComboBox;
class QLabel;
class QLineEdit;
class QListWidget;
class QProgressBar;
class QPushButton;
class QSlider;
class QSpinBox;
class QTimer;
class pqDDGNavigationPad;
class pqDDGOutlineView;
class pqDataRepresentation;
class pqPipelineSource;
class vtkSMSourceProxy;

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
  void cancel();
  void refreshThumbnails();
  void drillIn(const QRectF& box);
  void back();
  void resample();
  void pickRow(int row);
  void browseQuery();
  void runQuery();
  void pasteQuery();
  void pin();
  void unpin();
  void updatePad();
  void navigate();
  void recolour();
  void moreVisible();
  void lessVisible();
  void axesReleased();
  void lockChanged();
  void apply();
  void exportPreset();
  void exportSlicer();
  void exportHistory();
  void animate();

private:
  struct Pin
  {
    QJsonArray steps;
    QJsonArray latent;
    QImage icon;
  };

  void setStatus(const QString& text, bool error = false);
  void setBusy(bool busy);
  bool ready(bool needDesign = false);
  pqDataRepresentation* representation();
  QJsonObject currentView(int maxSide);
  QString historyText(const QJsonArray& steps) const;
  /// Runs DDG Design on the current steps at the current camera; false (and a message) on error.
  bool updateDesign();
  void setSteps(const QJsonArray& steps);
  void appendEdit(double hue, double visibility);
  void clearModel();

  // widgets
  QLabel* Status;
  QLineEdit* ModelPath;
  QProgressBar* Progress;
  QPushButton* CancelButton;
  pqDDGOutlineView* Outline;
  QLineEdit* QueryPath;
  QLabel* Preview;
  QLabel* Info;
  QListWidget* Pins;
  pqDDGNavigationPad* Pad;
  QComboBox* ClusterBox;
  QSpinBox* Hue;
  QSlider* Axes[3];
  QWidget* LockBox;
  QVector<QCheckBox*> Locks;
  QSpinBox* Frames;
  QTimer* NavigateTimer;
  QTimer* BoxTimer;

  // scene
  QPointer<pqPipelineSource> Source;
  QString Array;
  vtkSmartPointer<vtkSMSourceProxy> GalleryProxy, QueryProxy, DesignProxy, BuildProxy;
  QVector<QRectF> Boxes; ///< drill-in stack; the last is shown
  int Seed = 1;
  bool Loaded = false;
  bool Cancelled = false;
  bool Busy = false;
  bool ThumbnailsAtCamera = false; ///< thumbnails at the view's camera (else the volume's default)

  // the current design
  QJsonArray Steps;
  QJsonArray Latent;
  QString Preset, Slicer;
  QString ParaView2D; ///< 2D designs: the TransferFunction2D proxy's properties (JSON)
  QJsonObject DesignView;
  QImage PreviewImage;
  QVector<Pin> PinList;
  QJsonArray LockSteps;
};
