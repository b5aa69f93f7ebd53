// TestDesignState.cxx: the Design Gallery panel's state (pqDDGDesignState) driven without any
// widget or GUI event script, on the shipped Tooth model.
//
// How (the cheapest robust way found): a plain ParaView client process, like pvpython
// (TestDesignStateMain.cxx): vtkInitializationHelper (client), a builtin session
// (vtkSMSession::ConnectToSelf), the plugin loaded with vtkSMPluginManager for its filter
// proxies; then this file, a module with the state's sources compiled in (the plugin is a MODULE
// library one cannot link to), is opened and run: an XML reader of tooth.vti registered as
// "tooth.vti", the state driven. Opened after ParaView and the plugin, as the plugin is opened
// in ParaView (a program linking ParaView and libtorch at once crashed in protobuf's static
// initialisation). No pqApplicationCore, no QApplication (the state is a QObject with signals;
// QImage needs no GUI), no render view: the state's ViewFunction returns
// Data/Views/tooth_oblique.json scaled to the asked size, so nothing renders with OpenGL and no
// X display is needed.
//
// Compared: the history steps the state writes against literal ddg history JSON (README "File
// contracts"): pick, latent (with the query image's name), blend of two pins, edit (at the
// design's view), axes (consecutive moves merged into one step), lock (the steps at lock time);
// the outline (50 000 designs, 32 thumbnails of 64 px), the query's 5 neighbours and their
// thumbnails (64 px, each showing a design), the preview (192 px on the longer side), the blend
// corner u = v = 0 reproducing the first pin's latent (tolerance 1e-5: float latents through JSON;
// latents in steps are compared as floats), a failing edit dropped with its message, a chart
// refused as a query (its message, the steps unchanged), the messages of a state without a model, a
// failed build (constant volume) reported as failed (Plugin.GuiBuildFails checks the LastError
// text), and a match of the query's picture at the current camera: cancelled from its progress
// signal
// ("Match cancelled: ..."), then run (the camera given back as it is, PSNR against the picture
// >= 35 dB and above the query design's, the render and overlay mask at the picture's size,
// previews while fitting; the match's tile: the picture, tinted where the match left it out); a
// query that fails after it (the chart again) keeps the last query
// whole (its picture, nearest designs and match; no queried signal), and a picked nearest
// design's figure against the picture is the strip's; a WebP picture (no Qt reader here) has its
// tile drawn from the pixels the filters read.
//
// Usage: TestDesignState BODY PLUGIN DATA TESTDATA OUTDIR (BODY: this module)
#include "pqDDGDesignState.h"

#include <vtkDataSetAttributes.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPVArrayInformation.h>
#include <vtkPVDataInformation.h>
#include <vtkPVDataSetAttributesInformation.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMProxyManager.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSMSourceProxy.h>

#include <QBuffer>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonDocument>
#include <QPainter>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace
{
int Failures = 0;

/// Output Messages as the test sees them: what is written to them while it is installed
class MessageLog : public vtkOutputWindow
{
public:
  static MessageLog* New();
  vtkTypeMacro(MessageLog, vtkOutputWindow);
  void DisplayWarningText(const char* text) override { this->Texts << QString::fromUtf8(text); }
  void DisplayErrorText(const char* text) override { this->Texts << QString::fromUtf8(text); }
  QStringList Texts;
};
vtkStandardNewMacro(MessageLog);

void check(bool ok, const QString& what)
{
  std::cout << (ok ? "ok   " : "FAIL ") << what.toStdString() << std::endl;
  if (!ok)
    ++Failures;
}

QJsonObject object(const char* text)
{
  return QJsonDocument::fromJson(text).object();
}

QString compact(const QJsonValue& v)
{
  return QString::fromUtf8((v.isArray() ? QJsonDocument(v.toArray()) : QJsonDocument(v.toObject()))
                             .toJson(QJsonDocument::Compact));
}

/// Equal as float numbers (latents are floats; the history writes them shortest as floats).
bool sameFloats(const QJsonValue& a, const QJsonValue& b)
{
  if (a.isArray() != b.isArray())
    return false;
  if (!a.isArray())
    return static_cast<float>(a.toDouble()) == static_cast<float>(b.toDouble());
  const QJsonArray x = a.toArray(), y = b.toArray();
  if (x.size() != y.size())
    return false;
  for (int i = 0; i < x.size(); ++i)
    if (!sameFloats(x[i], y[i]))
      return false;
  return true;
}

QByteArray readFile(const QString& path)
{
  QFile f(path);
  return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
}

vtkSmartPointer<vtkSMSourceProxy> reader(vtkSMSessionProxyManager* pxm, const QString& path)
{
  vtkSmartPointer<vtkSMSourceProxy> r;
  r.TakeReference(vtkSMSourceProxy::SafeDownCast(pxm->NewProxy("sources", "XMLImageDataReader")));
  vtkSMPropertyHelper(r, "FileName").Set(path.toUtf8().constData());
  r->UpdateVTKObjects();
  r->UpdatePipeline();
  pxm->RegisterProxy("sources", QFileInfo(path).fileName().toUtf8().constData(), r);
  return r;
}

QString pointScalars(vtkSMSourceProxy* source)
{
  vtkPVArrayInformation* a =
    source->GetDataInformation(0)->GetPointDataInformation()->GetAttributeInformation(
      vtkDataSetAttributes::SCALARS);
  return a ? QString::fromUtf8(a->GetName()) : QString();
}

void run(const QString& data, const QString& testdata, const QString& outdir)
{
  vtkSMSessionProxyManager* pxm =
    vtkSMProxyManager::GetProxyManager()->GetActiveSessionProxyManager();
  auto tooth = reader(pxm, data + "/Volumes/tooth.vti");
  const QJsonObject viewFile =
    QJsonDocument::fromJson(readFile(data + "/Views/tooth_oblique.json")).object();

  pqDDGDesignState state;
  QStringList messages;
  QObject::connect(
    &state, &pqDDGDesignState::statusChanged, [&](const QString& text, bool) { messages << text; });
  pqDDGDesignState::Outline outline;
  QObject::connect(&state, &pqDDGDesignState::outlineChanged,
    [&](const pqDDGDesignState::Outline& o) { outline = o; });
  QVector<int> neighbours;
  QVector<QImage> neighbourThumbnails;
  QVector<double> neighbourPSNR;
  QObject::connect(&state, &pqDDGDesignState::queried,
    [&](const QPointF&, const QVector<int>& rows, const QVector<QImage>& thumbnails,
      const QVector<double>& against)
    {
      neighbours = rows;
      neighbourThumbnails = thumbnails;
      neighbourPSNR = against;
    });
  bool shaded = false;
  state.setViewFunction(
    [&](int maxSide)
    {
      QJsonObject v = viewFile;
      const QJsonArray size = v.value("size").toArray();
      const double w = size[0].toDouble(), h = size[1].toDouble();
      const double scale = std::min(1.0, maxSide / std::max(w, h));
      v["size"] = QJsonArray{ static_cast<int>(std::lround(w * scale)),
        static_cast<int>(std::lround(h * scale)) };
      if (shaded) // the volume shown with Shade on (ParaView's coefficients)
        v["lighting"] = QJsonObject{ { "shade", true } };
      return v;
    });

  // --- no model yet: the state says what is missing ---
  state.setVolume(tooth, pointScalars(tooth));
  check(state.volumeName() == "tooth.vti", "volume name " + state.volumeName());
  state.pick(0);
  check(state.lastMessage() == "Load or build a model for this volume first." &&
      state.steps().isEmpty(),
    "pick without a model: " + state.lastMessage());

  // --- the model and its outline ---
  if (!state.loadModel(data + "/Models/tooth"))
  {
    check(false, "load the Tooth model: " + state.lastMessage());
    return;
  }
  check(outline.Points.size() == 50000 && outline.ThumbnailRows.size() == 32 &&
      outline.Thumbnails.size() == 32 && outline.Thumbnails[0].width() == 64,
    QString("outline: %1 designs, %2 thumbnails")
      .arg(outline.Points.size())
      .arg(outline.ThumbnailRows.size()));
  check(state.lastMessage() ==
      "50000 designs of 'tooth.vti'; 32 thumbnails. Click one, or query with a picture.",
    "outline message: " + state.lastMessage());

  // --- pick ---
  state.pick(4725);
  check(
    compact(state.steps()) == compact(QJsonArray{ object(R"({"action": "pick", "row": 4725})") }),
    "pick steps " + compact(state.steps()));
  const pqDDGDesignState::Design& d = state.design();
  const int latentSize = static_cast<int>(d.Latent.size());
  check(d.Row == 4725 && latentSize > 0 && std::max(d.Preview.width(), d.Preview.height()) == 192 &&
      !QJsonDocument::fromJson(d.Preset.toUtf8()).isNull() && d.Preset.contains("RGBPoints") &&
      d.Fidelity.size() == 3,
    QString("pick design: row %1, latent %2, preview %3x%4")
      .arg(d.Row)
      .arg(latentSize)
      .arg(d.Preview.width())
      .arg(d.Preview.height()));
  check(state.lastMessage().startsWith("Design ready"), "pick message: " + state.lastMessage());
  // the thumbnails drawn again for a moved camera (the panel's camera timer): the outline
  // comes again, the status line keeps its last message (e.g. what Apply did)
  {
    const qsizetype said = messages.size();
    outline = {};
    state.refreshOutline(false);
    check(outline.ThumbnailRows.size() == 32 && messages.size() == said &&
        state.lastMessage().startsWith("Design ready"),
      QString("quiet refresh: %1 thumbnails, %2 new messages, last '%3'")
        .arg(outline.ThumbnailRows.size())
        .arg(messages.size() - said)
        .arg(state.lastMessage()));
  }
  state.pin();

  // --- a chart is refused: the message says why, the design stays ---
  QByteArray chartPng;
  {
    QImage chart(160, 120, QImage::Format_RGB32);
    chart.fill(Qt::white);
    QPainter painter(&chart);
    painter.setPen(QPen(Qt::black, 2));
    painter.drawRect(20, 10, 130, 90);
    painter.setPen(QPen(QColor(20, 80, 230), 2));
    for (int x = 20; x < 149; ++x)
      painter.drawLine(x, static_cast<int>(55 + 35 * std::sin(x / 12.0)), x + 1,
        static_cast<int>(55 + 35 * std::sin((x + 1) / 12.0)));
    painter.end();
    QBuffer buffer(&chartPng);
    buffer.open(QIODevice::WriteOnly);
    chart.save(&buffer, "PNG");
    const QJsonArray before = state.steps();
    state.query(chartPng, "chart.png");
    check(state.lastMessage().startsWith("The query failed ('chart.png')") &&
        state.lastMessage().contains("lines or text") && state.steps() == before,
      "chart query: " + state.lastMessage());
  }

  // --- query with the shipped screenshot ---
  const QString shot = "tooth_dentin_enamel_oblique.png";
  state.query(readFile(data + "/Screenshots/" + shot), shot);
  const QJsonObject latentStep = state.steps().at(0).toObject();
  check(state.steps().size() == 1 && latentStep.value("action") == "latent" &&
      latentStep.value("image") == shot &&
      latentStep.value("latent").toArray().size() == latentSize && latentStep.keys().size() == 3,
    "query step: action latent, image " + latentStep.value("image").toString());
  check(neighbours.size() == 5, QString("query neighbours: %1").arg(neighbours.size()));
  // the query's kind check with the shipped kind network: Tooth's screenshot on Tooth
  check(!state.queryKind().isEmpty() && !state.queryKind().value("differs").toBool(true) &&
      pqDDGDesignState::kindText(state.queryKind()).startsWith("Kind agreement"),
    "query's kind check: " +
      QString::fromUtf8(QJsonDocument(state.queryKind()).toJson(QJsonDocument::Compact)));
  // their thumbnails, as the outline's (64 px at the view's camera): each shows a design
  int drawn = 0;
  for (const QImage& t : neighbourThumbnails)
  {
    const QImage rgb = t.convertToFormat(QImage::Format_RGB888);
    const QRgb corner = rgb.pixel(0, 0);
    bool varies = false;
    for (int y = 0; y < rgb.height() && !varies; ++y)
      for (int x = 0; x < rgb.width() && !varies; ++x)
        varies = rgb.pixel(x, y) != corner;
    drawn +=
      t.size() == QSize(pqDDGDesignState::ThumbnailSize, pqDDGDesignState::ThumbnailSize) && varies;
  }
  int figures = 0; // each against the picture: a PSNR, not a NaN
  for (double f : neighbourPSNR)
    figures += std::isfinite(f) && f > 5 && f < 60;
  check(neighbourThumbnails.size() == 5 && drawn == 5 && figures == 5,
    QString("neighbour thumbnails: %1, %2 of them 64 px and not uniform; %3 figures against the "
            "picture (first %4 dB)")
      .arg(neighbourThumbnails.size())
      .arg(drawn)
      .arg(figures)
      .arg(neighbourPSNR.value(0)));

  // --- match the query's picture at the current camera: cancelled from its progress, then run ---
  int progressEvents = 0;
  auto cancelling = QObject::connect(&state, &pqDDGDesignState::matchProgress,
    [&](const QString&, double, const QImage&)
    {
      ++progressEvents;
      state.cancel();
    });
  bool cancelledMatch = true;
  QStringList cancelWarnings; // the user asked for it: no warning in Output Messages
  {
    vtkSmartPointer<vtkOutputWindow> window = vtkOutputWindow::GetInstance();
    vtkNew<MessageLog> log;
    vtkOutputWindow::SetInstance(log);
    cancelledMatch = state.match(true);
    vtkOutputWindow::SetInstance(window);
    cancelWarnings = log->Texts;
  }
  QObject::disconnect(cancelling);
  check(!cancelledMatch && !state.hasMatch() && progressEvents > 0 && cancelWarnings.isEmpty() &&
      state.lastMessage() == "Match cancelled: nothing was applied, the scene is unchanged.",
    "cancelled match: " + state.lastMessage() +
      " | Output Messages: " + cancelWarnings.join(" | "));
  QStringList stages;
  QImage lastPreview;
  QObject::connect(&state, &pqDDGDesignState::matchProgress,
    [&](const QString& stage, double, const QImage& preview)
    {
      if (!stages.contains(stage))
        stages << stage;
      if (!preview.isNull())
        lastPreview = preview;
    });
  const bool matched = state.match(true);
  const pqDDGDesignState::Match& m = state.lastMatch();
  const QJsonArray position = m.View.value("camera").toObject().value("position").toArray();
  const QJsonArray truePosition = viewFile.value("camera").toObject().value("position").toArray();
  check(matched && m.Preset.contains("RGBPoints") && !m.CameraEstimated && m.PSNRAfter >= 35 &&
      m.PSNRAfter > m.PSNRBefore && position.size() == 3 &&
      std::abs(position[0].toDouble() - truePosition[0].toDouble()) < 1e-9 &&
      std::abs(position[2].toDouble() - truePosition[2].toDouble()) < 1e-9 &&
      m.Render.size() == QSize(400, 320) && m.Overlay.size() == QSize(400, 320) &&
      m.Steps == state.steps() && m.Picture == shot && !lastPreview.isNull() &&
      stages.contains("fit"),
    QString("match at the current camera: PSNR %1 -> %2 dB, stages %3, %4 s")
      .arg(m.PSNRBefore, 0, 'f', 1)
      .arg(m.PSNRAfter, 0, 'f', 1)
      .arg(stages.join(" "))
      .arg(m.Timings.value(3), 0, 'f', 1));
  // the match's tile: the picture as it is where the match used it, tinted red where it did not
  {
    const QImage tile = state.pictureTile();
    const QImage picture = QImage::fromData(readFile(data + "/Screenshots/" + shot))
                             .convertToFormat(QImage::Format_RGB32);
    int kept = 0, tinted = 0, wrong = 0;
    for (int y = 0; y < std::min(tile.height(), m.Overlay.height()); ++y)
      for (int x = 0; x < std::min(tile.width(), m.Overlay.width()); ++x)
      {
        const bool same = (tile.pixel(x, y) & 0xffffff) == (picture.pixel(x, y) & 0xffffff);
        const bool left = qGray(m.Overlay.pixel(x, y)) > 127;
        (same != left ? (left ? tinted : kept) : wrong) += 1;
      }
    check(tile.size() == picture.size() && wrong == 0 && kept > 0,
      QString("match tile: %1 x %2, %3 pixels as the picture's, %4 tinted, %5 otherwise")
        .arg(tile.width())
        .arg(tile.height())
        .arg(kept)
        .arg(tinted)
        .arg(wrong));
  }
  // --- a query that fails keeps the last one whole: its picture, nearest designs and match ---
  {
    int emitted = 0;
    auto counting = QObject::connect(&state, &pqDDGDesignState::queried, [&]() { ++emitted; });
    const QJsonArray before = state.steps();
    state.query(chartPng, "chart.png");
    QObject::disconnect(counting);
    check(state.lastMessage().startsWith("The query failed") && emitted == 0 && state.hasMatch() &&
        state.lastMatch().Picture == shot && state.queryName() == shot &&
        !state.queryPicture().isEmpty() && state.queryNeighbours() == neighbours &&
        state.steps() == before,
      QString("failed query after a match: match kept %1, picture '%2', %3 queried signals")
        .arg(state.hasMatch())
        .arg(state.queryName())
        .arg(emitted));
  }
  // a nearest design picked under the query box: its figure against the picture, as the strip's
  check(state.neighbourPicturePSNR(neighbours[2]) == neighbourPSNR[2] &&
      std::isnan(state.neighbourPicturePSNR(-1)),
    QString("third neighbour against the picture: %1 dB")
      .arg(state.neighbourPicturePSNR(neighbours[2])));
  state.pin();
  check(state.pins().size() == 2 && state.pins()[1].Steps == state.steps() &&
      !state.pins()[1].Icon.isNull(),
    QString("pins: %1").arg(state.pins().size()));

  // --- blend between the two pins ---
  state.navigate({ 0, 1 }, 0.25, 0.0);
  const QJsonObject blend = state.steps().at(0).toObject();
  check(state.steps().size() == 1 &&
      blend.keys() == QStringList({ "action", "latents", "u", "v" }) &&
      blend.value("action") == "blend" && blend.value("u") == 0.25 && blend.value("v") == 0.0 &&
      sameFloats(
        blend.value("latents"), QJsonArray{ state.pins()[0].Latent, state.pins()[1].Latent }),
    "blend step at u = 0.25 of the two pins' latents");
  state.navigate({ 0, 1 }, 0.0, 0.0);
  double worst = 0;
  for (int k = 0; k < latentSize; ++k)
    worst = std::max(
      worst, std::abs(state.design().Latent[k].toDouble() - state.pins()[0].Latent[k].toDouble()));
  check(worst < 1e-5, QString("blend corner (0, 0) = first pin, max |dz| %1").arg(worst));
  state.navigate({ 0 }, 0.5, 0.0); // one pin: nothing to blend
  check(state.steps().at(0).toObject().value("u") == 0.0, "navigate with one pin does nothing");

  // --- edit at the design's view ---
  const QJsonObject designView = state.design().View;
  const QJsonArray latentBefore = state.design().Latent;
  state.edit(0, 60, 1.0);
  QJsonObject edit = object(R"({"action": "edit", "cluster": 0, "clusters": 4, "hue": 60,
    "saturation": 1, "lightness": 0, "visibility": 1, "white": false})");
  edit["view"] = designView;
  check(state.steps().size() == 2 && compact(state.steps()[1]) == compact(edit),
    "edit step " + compact(state.steps().last()).left(80) + "...");
  check(state.design().Latent != latentBefore, "the edit changes the design");
  // a failing edit (no cluster 99) is dropped with its message; the design stays
  const QJsonArray beforeBad = state.steps();
  messages.clear();
  state.edit(99, 30, 1.0);
  check(messages.size() == 2 && messages[0].startsWith("The design could not be made: ") &&
      state.steps() == beforeBad,
    "bad edit dropped: " + messages.value(0));

  // --- axes: consecutive moves are one step ---
  state.moveAlongAxes({ 0.5, 0, 0 });
  state.moveAlongAxes({ 1.0, -0.5, 0 });
  check(state.steps().size() == 3 &&
      compact(state.steps()[2]) == compact(object(R"({"action": "axes", "steps": [1, -0.5, 0]})")),
    "axes merged: " + compact(state.steps().last()));

  // --- lock: the regions stay as in the design shown at lock time ---
  check(state.design().Regions.size() >= 2,
    QString("regions: %1").arg(state.design().Regions.size() / 2));
  const QJsonArray atLock = state.steps();
  state.setLockedRegions({ 0 });
  state.moveAlongAxes({ 2.0, 0, 0 });
  check(state.lockSteps() == atLock && state.steps().size() == 3 &&
      state.lastMessage().startsWith("Design ready"),
    "locked at " + QString::number(atLock.size()) + " steps, then moved: " + state.lastMessage());
  state.setLockedRegions({});
  check(state.lockSteps().isEmpty(), "unlocked");

  // --- the history file ---
  const QJsonObject history =
    QJsonDocument::fromJson(pqDDGDesignState::historyText(state.steps()).toUtf8()).object();
  check(history.value("format") == "ddg-history" && history.value("version") == 1 &&
      history.value("steps").toArray() == state.steps(),
    "history text");

  // --- unpin ---
  state.unpin({ 0 });
  check(
    state.pins().size() == 1 && state.pins()[0].Steps.at(0).toObject().value("action") == "latent",
    "unpin the first pin");

  // --- what is kept of Tooth while another volume is selected (checked below) ---
  state.setLockedRegions({ 0 });
  state.moveAlongAxes({ 2.0, 0, 0 });
  state.drillIn(QRectF(-0.5, -0.5, 1.0, 1.0));
  const QJsonArray keptSteps = state.steps(), keptLockSteps = state.lockSteps();
  const QRectF keptBox = state.shownBox();
  check(state.depth() == 2 && keptBox.isValid(), "drilled in");

  // --- a build that fails (constant volume) is reported as failed, no model loaded ---
  auto constant = reader(pxm, testdata + "/constant.vti");
  state.setVolume(constant, pointScalars(constant));
  QDir(outdir).removeRecursively();
  const bool built = state.buildModel(outdir + "/constant_bundle");
  check(!built && !state.isLoaded() && state.lastMessage().startsWith("The build failed: ") &&
      !QFile::exists(outdir + "/constant_bundle/bundle.json"),
    "failed build: " + state.lastMessage());

  // --- Tooth again: its model, design, pins, lock and outline zoom are as it was left ---
  check(state.keptModel(constant).isEmpty() && state.keptModel(tooth) == data + "/Models/tooth",
    "kept model of Tooth: " + state.keptModel(tooth));
  state.setVolume(tooth, pointScalars(tooth));
  QVector<double> axes;
  auto restored = QObject::connect(
    &state, &pqDDGDesignState::axesRestored, [&](const QVector<double>& a) { axes = a; });
  int pinsAdded = 0;
  auto pinned = QObject::connect(&state, &pqDDGDesignState::pinAdded, [&]() { ++pinsAdded; });
  state.loadModel(state.keptModel(tooth));
  QObject::disconnect(restored);
  QObject::disconnect(pinned);
  check(state.isLoaded() && state.steps() == keptSteps && state.depth() == 2 &&
      state.shownBox() == keptBox && state.pins().size() == 1 && pinsAdded == 1 &&
      state.lockedRegions() == QVector<int>{ 0 } && state.lockSteps() == keptLockSteps &&
      state.queryName() == shot && state.hasMatch() && axes == QVector<double>({ 2.0, 0, 0 }) &&
      !state.design().Latent.isEmpty(),
    QString("Tooth kept: %1 steps, depth %2, %3 pins, message: %4")
      .arg(state.steps().size())
      .arg(state.depth())
      .arg(state.pins().size())
      .arg(state.lastMessage()));
  // the carried look starts from the picture's colours matched to the regions whatever design is
  // shown (Match starts from the design; the carried look does not)
  {
    const bool carried = state.match(false, true);
    const double start = state.lastMatch().DistanceStart;
    state.pick(4725);
    const bool again = state.match(false, true);
    const double other = state.lastMatch().DistanceStart;
    check(carried && again && state.lastMatch().Carried && start > 0 &&
        std::abs(other - start) <= 1e-6 * start && !state.lastMatch().View.contains("lighting"),
      QString("carried look's start with two designs shown: %1, %2").arg(start).arg(other));
    // the shipped kind network checked the picture (a Tooth screenshot) against Tooth: the same
    // kind, said in the panel's words
    const auto& m = state.lastMatch();
    check(m.Kind.value("agreement").toDouble(-1) >= m.Kind.value("threshold").toDouble(2) &&
        !m.kindDiffers() && m.kindText().startsWith("Kind agreement") &&
        m.Kind.value("volume_like").toString() == "tooth",
      "kind check of a Tooth picture on Tooth: " +
        QString::fromUtf8(QJsonDocument(m.Kind).toJson(QJsonDocument::Compact)));
    // the volume shown with Shade on: the look is carried over under it (its View says so; the
    // dock's Apply sets the View's lighting, as for a match)
    shaded = true;
    const bool lit = state.match(false, true);
    shaded = false;
    const QJsonObject lighting = state.lastMatch().View.value("lighting").toObject();
    check(lit && lighting.value("shade").toBool() &&
        std::abs(state.lastMatch().DistanceStart - start) > 1e-3 * start,
      QString("carried look under Shade: lighting %1, start %2 (unlit %3)")
        .arg(QString::fromUtf8(QJsonDocument(lighting).toJson(QJsonDocument::Compact)))
        .arg(state.lastMatch().DistanceStart)
        .arg(start));
  }
  // a bundle that cannot be loaded on this volume (Engine's on Tooth) gives Tooth's model back,
  // its design, pins and match as they were
  // its failure is said once in Output Messages, with the model that stays
  const QJsonArray stepsBefore = state.steps();
  vtkSmartPointer<vtkOutputWindow> window = vtkOutputWindow::GetInstance();
  vtkNew<MessageLog> log;
  vtkOutputWindow::SetInstance(log);
  const bool engine = state.loadModel(data + "/Models/engine");
  vtkOutputWindow::SetInstance(window);
  check(log->Texts.filter("Design Gallery:").size() == 1 &&
      log->Texts.filter("Design Gallery:").front().contains("The model loaded before stays"),
    "one warning for a bundle that cannot be loaded: " + log->Texts.join(" | "));
  check(!engine && state.isLoaded() && state.modelDirectory() == data + "/Models/tooth" &&
      state.steps() == stepsBefore && state.pins().size() == 1 && state.hasMatch() &&
      state.lastMessage().startsWith("This model belongs to another volume") &&
      state.lastMessage().endsWith("The model loaded before stays: '" + data + "/Models/tooth'."),
    "Engine's model on Tooth refused, Tooth's kept: " + state.lastMessage());
  state.loadModel(QString());
  check(state.isLoaded() && state.steps() == stepsBefore &&
      state.lastMessage().startsWith("No model directory given"),
    "no directory, Tooth's kept: " + state.lastMessage());
  // another model on the volume starts afresh (Tooth's bundle through another directory)
  const QString again = outdir + "/tooth_again";
  QDir().mkpath(again);
  for (const QString& f : QDir(data + "/Models/tooth").entryList(QDir::Files))
    QFile::link(data + "/Models/tooth/" + f, again + "/" + f);
  outline = {};
  const bool loaded = state.loadModel(again);
  check(loaded && state.steps().isEmpty() && state.pins().isEmpty() && !state.hasMatch() &&
      outline.Points.size() == 50000 &&
      state.lastMessage().startsWith("50000 designs of 'tooth.vti'"),
    "another model on Tooth starts afresh: " + state.lastMessage());
  // a WebP picture (Debian's Qt 5 has no reader for it): the tile is drawn from the pixels the
  // filters read, the shipped screenshot at half size
  const QByteArray webp = readFile(testdata + "/query_tooth.webp");
  state.query(webp, "query_tooth.webp");
  const QImage tile = state.pictureTile();
  const QImage full = QImage::fromData(readFile(data + "/Screenshots/" + shot));
  const QImage half = full.scaled(full.size() / 2, Qt::IgnoreAspectRatio, Qt::SmoothTransformation);
  double error = 0;
  for (int y = 0; y < std::min(tile.height(), half.height()); ++y)
    for (int x = 0; x < std::min(tile.width(), half.width()); ++x)
    {
      const QRgb a = tile.pixel(x, y), b = half.pixel(x, y);
      error += std::abs(qRed(a) - qRed(b)) + std::abs(qGreen(a) - qGreen(b)) +
        std::abs(qBlue(a) - qBlue(b));
    }
  error /= 3.0 * std::max(1, tile.width() * tile.height());
  check(state.queryName() == "query_tooth.webp" && !tile.isNull() && tile.size() == half.size() &&
      error < 8,
    QString("WebP picture's tile (Qt reads it: %1): %2 x %3, mean error %4 against the "
            "screenshot at half size")
      .arg(!QImage::fromData(webp).isNull())
      .arg(tile.width())
      .arg(tile.height())
      .arg(error, 0, 'f', 2));
}

} // namespace

/// The test body, called by TestDesignStateMain.cxx once ParaView runs with the plugin loaded.
extern "C" int ddgRunDesignStateTest(const char* data, const char* testdata, const char* outdir)
{
  run(data, testdata, outdir);
  std::cout << (Failures ? "FAILED" : "all passed") << std::endl;
  return Failures ? 1 : 0;
}
