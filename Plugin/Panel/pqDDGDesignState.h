// pqDDGDesignState.h: the Design Gallery panel's state without any widget: the volume, the
// server-side filter proxies on it, the outline being browsed, the history steps of the current
// design and what DDG Design made of them, the query's picture and its match, the pins and the
// lock. The dock panel shows it and
// forwards the user's actions; a test drives it directly (Testing/Plugin/TestDesignState.cxx).
#pragma once

#include <QColor>
#include <QHash>
#include <QImage>
#include <QJsonArray>
#include <QJsonObject>
#include <QObject>
#include <QPointF>
#include <QRect>
#include <QRectF>
#include <QVector>
#include <array>

#include <vtkSmartPointer.h>
#include <vtkWeakPointer.h>

#include <functional>
#include <limits>

class QTimer;
class vtkSMSourceProxy;

class pqDDGDesignState : public QObject
{
  Q_OBJECT

public:
  /// What DDG Design made of the current steps at the camera it was asked at.
  struct Design
  {
    QJsonArray Latent;
    QString Preset;     ///< ParaView preset (1D) or DDG 2D TF JSON (2D models)
    QString ParaView2D; ///< 2D models: the TransferFunction2D proxy's properties (JSON)
    QString Slicer;     ///< 3D Slicer's .vp.json (1D models)
    QJsonObject View;   ///< the view JSON it was made at (edits refer to it)
    QImage Preview;
    QJsonArray Position; ///< on the outline plane (2 numbers)
    QJsonArray Fidelity; ///< PSNR dB, SSIM, max error
    QJsonArray Regions;  ///< feature regions: (low, high) value pairs
    QVector<QColor> ClusterColours;
    QVector<double> ClusterShares;
    int Row = -1; ///< the outline row when the steps are a single pick, else -1
  };
  /// A pinned design: its steps, its latent vector and its preview as icon.
  struct Pin
  {
    QJsonArray Steps;
    QJsonArray Latent;
    QImage Icon;
  };
  /// The outline part shown: every outline design and thumbnails of a sample of them.
  struct Outline
  {
    QVector<QPointF> Points;    ///< plane position of every outline row
    QVector<int> ThumbnailRows; ///< the outline row of each thumbnail
    QVector<QImage> Thumbnails; ///< their images
    QRectF Box;                 ///< the plane part shown (when BoxKnown)
    bool BoxKnown = false;
  };
  /// What a match of the query's picture found (DDG Reconstruct Transfer Function with
  /// MatchPicture): the TF, the picture's camera, the figures and the masks.
  struct Match
  {
    QString Preset;     ///< ParaView preset (1D) or DDG 2D TF JSON (2D models)
    QString ParaView2D; ///< 2D: the TransferFunction2D proxy's properties (JSON)
    QJsonObject View;   ///< the picture's camera as view JSON (the background estimated)
    bool CameraEstimated = false;
    bool LightingEstimated = false; // View's "lighting" (absent: unlit) came from the fit
    double Overlap = 0;             ///< silhouette IoU of the camera
    double FitPSNR = 0;             ///< Core's PSNR of the fit over the compared pixels
    /// the design it started from, at that camera, vs the picture (NaN: none)
    double PSNRBefore = 0;
    double PSNRAfter = 0;    ///< the matched TF at that camera vs the picture
    QVector<double> Timings; ///< seconds: background, camera, fit, total
    int Iterations = 0;
    QImage Render;                  ///< the matched TF at the picture's camera over its background
    QImage Overlay;                 ///< the overlay mask (white: left out), the size of Crop
    QRect Crop;                     ///< the part of the picture matched (inside a letterbox)
    QString Picture;                ///< the picture's name (as the query step records it)
    QJsonArray Steps;               ///< the design's steps the match started from
    bool FromCurrentCamera = false; ///< the camera was given (the current one), not estimated
    bool Carried = false;           ///< another volume's picture: its look carried over (no camera)
    /// Carried: per feature region of this volume, value from, to, the picture's r, g, b it was
    /// matched with, that colour's share of the picture's object
    QVector<std::array<double, 6>> Regions;
    double DistanceStart = 0, DistanceEnd = 0; ///< Carried: colour distance (CIELAB)
    double ShapeAgreement = 0; ///< Carried: silhouette IoU against the picture's object
    bool ShapesAgree = false;  ///< Carried: ShapeAgreement reaches 0.6
    /// Carried: the kind network's check (the filter's "Kind": agreement, threshold, differs,
    /// picture_like, volume_like); empty when it was not checked
    QJsonObject Kind;
    /// Carried: the check in a sentence ("" when not checked).
    QString kindText() const { return pqDDGDesignState::kindText(this->Kind); }
    /// Carried: the kind network says the picture may show a volume of another kind.
    bool kindDiffers() const { return Kind.value("differs").toBool(); }
  };

  /// Makes the view JSON of the current camera with `maxSide` pixels on its longer side (empty
  /// when there is no view).
  using ViewFunction = std::function<QJsonObject(int maxSide)>;

  static constexpr int PreviewSide = 192;
  static constexpr int ThumbnailCount = 32;
  static constexpr int ThumbnailSize = 64;
  static constexpr int QueryNeighbourCount = 5; ///< a query's nearest designs shown

  explicit pqDDGDesignState(QObject* parent = nullptr);
  ~pqDDGDesignState() override;

  // --- the volume and its model -----------------------------------------------------------------
  /// The volume (`array`: its point scalars) the panel works on; clears the model. nullptr or
  /// an empty `array`: none.
  void setVolume(vtkSMSourceProxy* source, const QString& array);
  vtkSMSourceProxy* volume() const;
  const QString& array() const { return this->Array; }
  /// The volume's name in the pipeline (its registration name).
  QString volumeName() const;
  void setViewFunction(ViewFunction view) { this->View = std::move(view); }
  /// The view JSON of the current camera (ViewFunction).
  QJsonObject currentView(int maxSide) const;

  /// Creates the filters on the volume for the bundle in `directory` (on the server) and shows
  /// the whole outline; false when there is no volume or the plugin is missing on the server.
  bool loadModel(const QString& directory);
  void clearModel();
  bool isLoaded() const { return this->Loaded; }
  const QString& modelDirectory() const { return this->ModelDirectory; }
  /// The model last loaded on `source` in this session before another volume was selected (""
  /// when none): loading it again brings back that volume's query, design, match, pins, locks
  /// and outline zoom (pqDDGDesignStateKeep.cxx).
  QString keptModel(vtkSMSourceProxy* source) const;
  // --- building a model (pqDDGDesignStateBuild.cxx) -------------------------------------------
  /// What a build of the volume into `directory` within `budgetMinutes` would cost (DDG Build
  /// Design Space's PlanBuild on the server: BuildPlan JSON, with "error" for a volume no design
  /// space can be built on and "output_error" for a folder that would be refused).
  QJsonObject planBuild(const QString& directory, double budgetMinutes, bool overwrite);
  /// Starts building a design space for the volume into `directory` on the server, in the
  /// background (StartBuild; `budgetMinutes` > 0 sizes it, 0: the filter's defaults), and polls
  /// it every 250 ms (buildProgress) until buildFinished; cancel() stops it. False with a
  /// message when it cannot start or failed at once.
  bool startBuild(const QString& directory, double budgetMinutes = 0, bool overwrite = false);
  bool isBuilding() const { return this->BuildProxy != nullptr; }
  /// startBuild, then waits (processing events) for its end: true when it was built (then load
  /// it), false with a message when it failed or was cancelled.
  bool buildModel(const QString& directory, double budgetMinutes = 0, bool overwrite = false);

  bool isBusy() const { return this->Busy; }
  void setBusy(bool busy);
  bool isCancelled() const { return this->Cancelled; }
  /// Asks the running build, animation or match to stop.
  void cancel();

  /// True when there is a volume, a model and (`needDesign`) a design; else says what is missing.
  bool ready(bool needDesign = false);
  /// True when there is a volume (what the match of a picture needs: no model); else says so.
  bool hasVolume();

  // --- the outline ---------------------------------------------------------------------------
  /// Renders the thumbnails of the outline part shown (outlineChanged or a message). `announce`
  /// false (thumbnails drawn again for a moved camera): the status line says nothing on success,
  /// so the last message (e.g. what Apply did) stays.
  void refreshOutline(bool announce = true);
  void drillIn(const QRectF& box);
  void back();
  void resample();
  /// The part shown changed by zoom or pan.
  void setShownBox(const QRectF& box);
  /// Thumbnails at the view's camera (the default), else at the volume's default view.
  void setThumbnailsAtCamera(bool atCamera) { this->ThumbnailsAtCamera = atCamera; }
  /// True when the thumbnails shown were rendered at a camera far from `view`'s: its direction
  /// turned by more than 30 degrees, or the volume's size on screen changed by more than 1.5x
  /// (distance or parallel scale): time to render them again at `view`. Also when `view`'s
  /// lighting (the volume's Shade) is not the one they were lit with, at any camera.
  bool thumbnailsOutdated(const QJsonObject& view) const;

  // --- designs -------------------------------------------------------------------------------
  /// Queries with an image file's bytes (PNG, JPEG, TIFF, BMP, GIF or WebP); `name` is recorded in
  /// the step. Without a model the picture is kept for the match alone (queryDone, no design).
  void query(const QByteArray& imageFile, const QString& name);
  void pick(int row);
  /// The outline part shown now (its drill-in depth: depth()).
  QRectF shownBox() const { return this->Boxes.isEmpty() ? QRectF() : this->Boxes.last(); }
  int depth() const { return static_cast<int>(this->Boxes.size()); }
  /// The blend of pins `pins` (2-4) at (u, v).
  void navigate(const QList<int>& pins, double u, double v);
  /// Recolours colour cluster `cluster` of the design by `hue` degrees and scales its visibility.
  void edit(int cluster, double hue, double visibility);
  /// Moves along the principal axes (standard deviations); consecutive moves are one step.
  void moveAlongAxes(const QVector<double>& steps);
  /// Locks feature regions `regions` as they are in the design shown now (empty: unlocks).
  void setLockedRegions(const QVector<int>& regions);
  /// Makes `steps` the current design's path (`newPath`: a new path, the axes start at 0).
  bool setSteps(const QJsonArray& steps, bool newPath = true);
  /// Runs DDG Design on the steps at the current camera; false (and a message) on error.
  bool updateDesign();
  const QJsonArray& steps() const { return this->Steps; }
  const QJsonArray& lockSteps() const { return this->LockSteps; }
  const QVector<int>& lockedRegions() const { return this->Locked; }
  const Design& design() const { return this->Current; }

  // --- matching the query's picture
  // ---------------------------------------------------------------
  /// Refines a TF toward the last query's picture by differentiable rendering (DDG Reconstruct
  /// Transfer Function with MatchPicture), starting from the current design's TF, at the current
  /// camera (`fromCurrentCamera`: the picture was taken from it) or at a camera estimated from
  /// the picture. Reports progress (matchProgress, with a preview in a builtin session), stops on
  /// cancel(); true when a match was found (matchChanged), false with a message (the scene is
  /// never touched here). `otherVolume`: the picture shows another volume of the same kind; its
  /// look is carried over instead (the filter's CarryLook: no camera, no design needed).
  bool match(bool fromCurrentCamera, bool otherVolume = false);
  bool hasMatch() const { return !this->LastMatch.Preset.isEmpty(); }
  const Match& lastMatch() const { return this->LastMatch; }
  /// The picture of the last query (an image file's bytes) and its name.
  const QByteArray& queryPicture() const { return this->QueryPicture; }
  /// The query's picture as the match's tile shows it: what the match left out (overlays; the
  /// bands of a letterbox and the panels around a window's render view: outside its crop) tinted
  /// red when there is a match. Decoded by Qt, or as the filters read it when Qt has no reader for
  /// its format (WebP); null when there is no picture.
  QImage pictureTile() const;
  const QString& queryName() const { return this->QueryName; }
  /// The query's design against its picture, both framed on their content (Core's framedPSNR;
  /// NaN without a query): how close it looks without knowing the picture's camera.
  double queryPicturePSNR() const { return this->QueryPSNR; }
  /// Whether that figure is of the design lit (the better of unlit and lit is taken: the
  /// picture's lighting is not known).
  bool queryPictureLit() const { return this->QueryLit; }
  /// The last query's kind check (DDG Query's "Kind": agreement, threshold, differs, ...), empty
  /// when it was not checked.
  const QJsonObject& queryKind() const { return this->QueryKind; }
  /// The shipped kind network (DDG_DATA_DIR/Models/kind) when it is there, else "": what the
  /// query and the carried look check the picture's kind of volume with.
  static QString kindNetwork();
  /// A kind check (the filters' "Kind" field) in a sentence ("" when there is none).
  static QString kindText(const QJsonObject& kind);
  /// A nearest design of the last query against its picture (dB, as in the strip; NaN when
  /// `row` is not one of them or was not scored).
  double neighbourPicturePSNR(int row) const;
  /// The last query's nearest designs (outline rows, nearest first).
  const QVector<int>& queryNeighbours() const { return this->QueryNeighbours; }

  // --- pins ----------------------------------------------------------------------------------
  /// Pins the current design (pinAdded).
  void pin();
  /// Removes the pins at `rows`.
  void unpin(QVector<int> rows);
  const QVector<Pin>& pins() const { return this->Pins; }

  /// Says `text` in the panel (statusChanged); `error` shows it as one (and in Output Messages,
  /// as a warning).
  void report(const QString& text, bool error = false);
  /// The last text reported.
  const QString& lastMessage() const { return this->LastMessage; }

  // --- history steps: the ddg history JSON (README "File contracts"), made only by these (through
  // vtkDDGDesignHistory, Core's history writer; pqDDGDesignStateSteps.cxx) ---------------------
  static QJsonObject pickStep(int row);
  static QJsonObject latentStep(const QJsonArray& latent, const QString& image);
  static QJsonObject blendStep(const QJsonArray& latents, double u, double v);
  static QJsonObject editStep(const QJsonObject& view, int cluster, double hue, double visibility);
  static QJsonObject axesStep(const QVector<double>& steps);
  /// The "match" step of a match (the picture, its camera, the TF found) for ddg replay.
  static QJsonObject matchStep(const Match& match);
  /// The history to export: the design's steps, and the last match's step when it matched the
  /// design those steps give.
  QJsonArray exportSteps() const;
  /// `steps` with `step` appended; an axes step after an axes step replaces it (one move).
  static QJsonArray appendStep(QJsonArray steps, const QJsonObject& step);
  /// The history file's text of `steps` (what `ddg replay` reads).
  static QString historyText(const QJsonArray& steps);

Q_SIGNALS:
  void statusChanged(const QString& text, bool error);
  void busyChanged(bool busy);
  /// The model was dropped (new volume, new bundle): clear what shows it.
  void modelCleared();
  void outlineChanged(const pqDDGDesignState::Outline& outline);
  /// The outline could not be shown (`message` says why; the model is not usable).
  void outlineFailed(const QString& message);
  /// A query landed at `position` with its nearest outline rows, their thumbnails (at the
  /// view's camera and lighting; fewer or none when they could not be rendered) and each one's
  /// figure against the query's picture (dB, as the query's own design is judged).
  void queried(const QPointF& position, const QVector<int>& neighbours,
    const QVector<QImage>& thumbnails, const QVector<double>& againstPicture);
  /// A new path starts (the axes sliders go back to 0).
  void pathStarted();
  /// A kept design came back whose last step moved along the axes by `steps` (the sliders).
  void axesRestored(const QVector<double>& steps);
  void designChanged();
  void pinAdded();
  /// A query succeeded and its design shows.
  void queryDone();
  /// A match runs: its stage ("background", "camera", "fit"), the fraction done and, every few
  /// fit steps in a builtin session, a preview (else a null image).
  void matchProgress(const QString& stage, double fraction, const QImage& preview);
  /// The match was found or dropped (a new query, a new model).
  void matchChanged();
  /// A build runs: its stage, the fraction done and the seconds left (-1: not known yet).
  void buildProgress(const QString& stage, double fraction, double secondsLeft);
  /// The build ended: `built` (its bundle is in `directory`) or not (the message said why).
  void buildFinished(bool built, const QString& directory);

private:
  void pollBuild();
  /// A new picture replaces the last query's: its match goes (matchChanged).
  void dropQueryPicture();
  /// What the panel keeps of a volume while another is selected (pqDDGDesignStateKeep.cxx).
  struct Kept
  {
    QString ModelDirectory;
    QVector<QRectF> Boxes;
    int Seed = 1;
    QJsonArray Steps, LockSteps;
    QVector<int> Locked;
    QVector<Pin> Pins;
    QByteArray QueryPicture;
    QString QueryName;
    double QueryPSNR = 0;
    bool QueryLit = false;
    QJsonObject QueryKind;
    bool Queried = false;
    QPointF QueryPosition;
    QVector<int> QueryNeighbours;
    QVector<QImage> QueryThumbnails;
    QVector<double> QueryNeighbourPSNR;
    Match LastMatch;
  };
  /// Keeps the loaded volume's state (setVolume to another volume).
  void keepVolumeState();
  /// The kept state of the volume for `directory` (taken out of the keep), if there is one.
  bool takeKept(const QString& directory, Kept& kept);
  /// Brings a kept state back once the model is loaded and the outline shows.
  void restoreVolumeState(Kept& kept);
  /// Puts a state taken out of the keep back (a load that failed gives its model back).
  void putKept(const Kept& kept);
  QHash<unsigned int, Kept> KeptStates; ///< by the volume proxy's global id

  vtkWeakPointer<vtkSMSourceProxy> Source;
  QTimer* BuildTimer = nullptr;
  QString BuildDirectory;
  /// the proxy the build dialog planned with (its probe's rates are reused by the build)
  vtkSmartPointer<vtkSMSourceProxy> PlanProxy;
  vtkWeakPointer<vtkSMSourceProxy> PlanSource;
  QString Array;
  ViewFunction View;
  QString ModelDirectory;
  vtkSmartPointer<vtkSMSourceProxy> GalleryProxy, QueryProxy, DesignProxy, BuildProxy, MatchProxy;
  bool Loaded = false;
  bool Busy = false;
  bool Cancelled = false;
  QString LastMessage;
  /// while a bundle is tried in place of the loaded one: its failure reaches Output Messages once,
  /// with "the model loaded before stays"
  bool HoldWarnings = false;

  QVector<QRectF> Boxes; ///< drill-in stack; the last is shown
  int Seed = 1;
  bool ThumbnailsAtCamera = true;
  QJsonObject ThumbnailView;     ///< the view JSON the thumbnails shown were rendered at
  QJsonObject ThumbnailLighting; ///< the volume's lighting they were lit with ({}: Shade off)

  QJsonArray Steps;
  QJsonArray LockSteps;
  QVector<int> Locked;
  Design Current;
  QVector<Pin> Pins;
  QByteArray QueryPicture;
  QString QueryName;
  bool Queried = false; ///< the query's position on the outline is known
  double QueryPSNR = std::numeric_limits<double>::quiet_NaN();
  bool QueryLit = false;
  QJsonObject QueryKind; // the query's kind check (DDG Query's "Kind"), empty when none
  QPointF QueryPosition;
  QVector<int> QueryNeighbours;
  QVector<QImage> QueryThumbnails;
  QVector<double> QueryNeighbourPSNR; ///< the nearest designs against the picture (dB)
  Match LastMatch;
};
