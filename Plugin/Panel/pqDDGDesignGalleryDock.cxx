// pqDDGDesignGalleryDock.cxx: the Design Gallery panel.
#include "pqDDGDesignGalleryDock.h"

#include "pqDDGNavigationPad.h"
#include "pqDDGOutlineView.h"
#include "pqDDGScene.h"

#include <pqActiveObjects.h>
#include <pqApplicationCore.h>
#include <pqDataRepresentation.h>
#include <pqFileDialog.h>
#include <pqOutputPort.h>
#include <pqPipelineSource.h>
#include <pqProgressManager.h>
#include <pqRenderView.h>
#include <pqSaveScreenshotReaction.h>
#include <pqServer.h>

#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkPVArrayInformation.h>
#include <vtkPVDataInformation.h>
#include <vtkPVDataSetAttributesInformation.h>
#include <vtkPointData.h>
#include <vtkSMPVRepresentationProxy.h>
#include <vtkSMParaViewPipelineControllerWithRendering.h>
#include <vtkSMPropertyHelper.h>
#include <vtkSMSourceProxy.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

#include <QApplication>
#include <QBuffer>
#include <QCheckBox>
#include <QClipboard>
#include <QComboBox>
#include <QDir>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QImageReader>
#include <QJsonDocument>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMimeData>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QShortcut>
#include <QSlider>
#include <QSpinBox>
#include <QTimer>
#include <QVBoxLayout>

#include <cmath>

#ifndef DDG_DATA_DIR
#define DDG_DATA_DIR ""
#endif

namespace
{
constexpr int kPreviewSide = 192;
constexpr int kThumbnails = 32;
constexpr int kThumbnailSize = 64;

/// The "Image" array (RGB over the background) of a filter's image output as a QImage.
QImage toQImage(vtkDataObject* data)
{
  auto* image = vtkImageData::SafeDownCast(data);
  vtkDataArray* rgb = image ? image->GetPointData()->GetArray("Image") : nullptr;
  if (!rgb || rgb->GetNumberOfComponents() < 3)
    return {};
  int dims[3];
  image->GetDimensions(dims);
  const bool unit = rgb->GetDataType() == VTK_FLOAT || rgb->GetDataType() == VTK_DOUBLE;
  QImage out(dims[0], dims[1], QImage::Format_RGB32);
  for (int y = 0; y < dims[1]; ++y)
    for (int x = 0; x < dims[0]; ++x)
    {
      const vtkIdType i = static_cast<vtkIdType>(dims[1] - 1 - y) * dims[0] + x; // VTK rows go up
      int c[3];
      for (int k = 0; k < 3; ++k)
      {
        const double v = rgb->GetComponent(i, k);
        c[k] = static_cast<int>(std::lround(std::clamp(unit ? 255 * v : v, 0.0, 255.0)));
      }
      out.setPixel(x, y, qRgb(c[0], c[1], c[2]));
    }
  return out;
}

QJsonArray fieldArray(vtkTable* table, const char* name)
{
  QJsonArray out;
  vtkDataArray* a = table ? table->GetFieldData()->GetArray(name) : nullptr;
  for (vtkIdType i = 0; a && i < a->GetNumberOfValues(); ++i)
    out.append(a->GetVariantValue(i).ToDouble());
  return out;
}

QString fieldString(vtkTable* table, const char* name)
{
  auto* a =
    table ? vtkStringArray::SafeDownCast(table->GetFieldData()->GetAbstractArray(name)) : nullptr;
  return a && a->GetNumberOfValues() > 0 ? QString::fromStdString(a->GetValue(0)) : QString();
}

QString base64Of(const QByteArray& bytes)
{
  return QString::fromLatin1(bytes.toBase64());
}

bool writeText(const QString& path, const QString& text)
{
  QFile f(path);
  if (!f.open(QIODevice::WriteOnly | QIODevice::Truncate))
    return false;
  return f.write(text.toUtf8()) >= 0;
}
} // namespace

pqDDGDesignGalleryDock::pqDDGDesignGalleryDock(QWidget* parent)
  : QDockWidget(tr("Design Gallery"), parent)
{
  auto* scroll = new QScrollArea(this);
  scroll->setObjectName("scroll");
  scroll->setWidgetResizable(true);
  auto* contents = new QWidget(scroll);
  contents->setObjectName("contents");
  auto* layout = new QVBoxLayout(contents);
  auto button = [contents](const QString& text, const char* name)
  {
    auto* b = new QPushButton(text, contents);
    b->setObjectName(name);
    return b;
  };

  this->Status = new QLabel(tr("Select a volume (image data) in the Pipeline Browser."), contents);
  this->Status->setObjectName("status");
  this->Status->setWordWrap(true);
  layout->addWidget(this->Status);

  // model
  auto* modelRow = new QHBoxLayout();
  this->ModelPath = new QLineEdit(contents);
  this->ModelPath->setObjectName("modelPath");
  this->ModelPath->setPlaceholderText(tr("model bundle directory (on the server)"));
  auto* browseModel = button(tr("Load..."), "loadModel");
  auto* buildModel = button(tr("Build..."), "buildModel");
  buildModel->setToolTip(tr("Build a design space for this volume (exemplars, training, outline)"));
  modelRow->addWidget(this->ModelPath, 1);
  modelRow->addWidget(browseModel);
  modelRow->addWidget(buildModel);
  layout->addLayout(modelRow);
  auto* progressRow = new QHBoxLayout();
  this->Progress = new QProgressBar(contents);
  this->Progress->setObjectName("progress");
  this->Progress->setRange(0, 100);
  this->Progress->setValue(0);
  this->CancelButton = button(tr("Cancel"), "cancel");
  this->CancelButton->setEnabled(false);
  progressRow->addWidget(this->Progress, 1);
  progressRow->addWidget(this->CancelButton);
  layout->addLayout(progressRow);

  // outline
  this->Outline = new pqDDGOutlineView(contents);
  this->Outline->setObjectName("outline");
  layout->addWidget(this->Outline, 1);
  auto* outlineRow = new QHBoxLayout();
  auto* backButton = button(tr("Back"), "back");
  auto* resampleButton = button(tr("Resample"), "resample");
  auto* refreshButton = button(tr("At this camera"), "refresh");
  refreshButton->setToolTip(tr("Render the thumbnails at the view's current camera"));
  outlineRow->addWidget(backButton);
  outlineRow->addWidget(resampleButton);
  outlineRow->addWidget(refreshButton);
  layout->addLayout(outlineRow);

  // query
  auto* queryBox = new QGroupBox(tr("Query with a picture"), contents);
  queryBox->setObjectName("queryBox");
  auto* queryRow = new QHBoxLayout(queryBox);
  this->QueryPath = new QLineEdit(queryBox);
  this->QueryPath->setObjectName("queryPath");
  this->QueryPath->setPlaceholderText(tr("image file, or drop / paste an image"));
  auto* browseQuery = new QPushButton(tr("..."), queryBox);
  browseQuery->setObjectName("browseQuery");
  auto* runQuery = new QPushButton(tr("Query"), queryBox);
  runQuery->setObjectName("query");
  auto* pasteQuery = new QPushButton(tr("Paste"), queryBox);
  pasteQuery->setObjectName("paste");
  queryRow->addWidget(this->QueryPath, 1);
  queryRow->addWidget(browseQuery);
  queryRow->addWidget(runQuery);
  queryRow->addWidget(pasteQuery);
  layout->addWidget(queryBox);

  // the current design
  auto* designBox = new QGroupBox(tr("Design"), contents);
  designBox->setObjectName("designBox");
  auto* designLayout = new QHBoxLayout(designBox);
  this->Preview = new QLabel(designBox);
  this->Preview->setObjectName("preview");
  this->Preview->setFixedSize(kPreviewSide, kPreviewSide);
  this->Preview->setAlignment(Qt::AlignCenter);
  this->Preview->setFrameShape(QFrame::StyledPanel);
  auto* designSide = new QVBoxLayout();
  this->Info = new QLabel(designBox);
  this->Info->setObjectName("info");
  this->Info->setWordWrap(true);
  auto* applyButton = new QPushButton(tr("Apply"), designBox);
  applyButton->setObjectName("apply");
  applyButton->setToolTip(tr("Write this design's transfer function at the current camera into "
                             "the volume's colour and opacity maps (undoable)"));
  auto* pinButton = new QPushButton(tr("Pin"), designBox);
  pinButton->setObjectName("pin");
  auto* exportPreset = new QPushButton(tr("Export preset..."), designBox);
  exportPreset->setObjectName("exportPreset");
  auto* exportSlicer = new QPushButton(tr("Export Slicer..."), designBox);
  exportSlicer->setObjectName("exportSlicer");
  auto* exportHistory = new QPushButton(tr("Export history..."), designBox);
  exportHistory->setObjectName("exportHistory");
  designSide->addWidget(this->Info, 1);
  designSide->addWidget(applyButton);
  designSide->addWidget(pinButton);
  designSide->addWidget(exportPreset);
  designSide->addWidget(exportSlicer);
  designSide->addWidget(exportHistory);
  designLayout->addWidget(this->Preview);
  designLayout->addLayout(designSide, 1);
  layout->addWidget(designBox);

  // edits
  auto* editBox = new QGroupBox(tr("Edit"), contents);
  editBox->setObjectName("editBox");
  auto* editForm = new QFormLayout(editBox);
  this->ClusterBox = new QComboBox(editBox);
  this->ClusterBox->setObjectName("cluster");
  this->Hue = new QSpinBox(editBox);
  this->Hue->setObjectName("hue");
  this->Hue->setRange(-180, 180);
  this->Hue->setValue(60);
  this->Hue->setSuffix(QString::fromUtf8("\u00b0"));
  auto* recolourButton = new QPushButton(tr("Recolour"), editBox);
  recolourButton->setObjectName("recolour");
  auto* hueRow = new QHBoxLayout();
  hueRow->addWidget(this->Hue, 1);
  hueRow->addWidget(recolourButton);
  auto* moreButton = new QPushButton(tr("More visible"), editBox);
  moreButton->setObjectName("moreVisible");
  auto* lessButton = new QPushButton(tr("Less visible"), editBox);
  lessButton->setObjectName("lessVisible");
  auto* visRow = new QHBoxLayout();
  visRow->addWidget(moreButton);
  visRow->addWidget(lessButton);
  editForm->addRow(tr("Colour"), this->ClusterBox);
  editForm->addRow(tr("Hue"), hueRow);
  editForm->addRow(tr("Visibility"), visRow);
  for (int k = 0; k < 3; ++k)
  {
    this->Axes[k] = new QSlider(Qt::Horizontal, editBox);
    this->Axes[k]->setObjectName(QString("axis%1").arg(k));
    this->Axes[k]->setRange(-30, 30); // tenths of the axis' standard deviation
    this->Axes[k]->setToolTip(tr("Move along principal axis %1 of the design space").arg(k + 1));
    editForm->addRow(tr("Axis %1").arg(k + 1), this->Axes[k]);
    QObject::connect(
      this->Axes[k], &QSlider::sliderReleased, this, &pqDDGDesignGalleryDock::axesReleased);
  }
  this->LockBox = new QWidget(editBox);
  this->LockBox->setObjectName("locks");
  new QHBoxLayout(this->LockBox);
  this->LockBox->layout()->setContentsMargins(0, 0, 0, 0);
  editForm->addRow(tr("Lock"), this->LockBox);
  layout->addWidget(editBox);

  // archive strip and navigation
  auto* pinBox = new QGroupBox(tr("Pinned designs"), contents);
  pinBox->setObjectName("pinBox");
  auto* pinLayout = new QVBoxLayout(pinBox);
  this->Pins = new QListWidget(pinBox);
  this->Pins->setObjectName("pins");
  this->Pins->setViewMode(QListView::IconMode);
  this->Pins->setFlow(QListView::LeftToRight);
  this->Pins->setWrapping(false);
  this->Pins->setIconSize(QSize(48, 48));
  this->Pins->setFixedHeight(72);
  this->Pins->setSelectionMode(QAbstractItemView::ExtendedSelection);
  this->Pad = new pqDDGNavigationPad(pinBox);
  this->Pad->setObjectName("pad");
  auto* pinRow = new QHBoxLayout();
  auto* unpinButton = new QPushButton(tr("Unpin"), pinBox);
  unpinButton->setObjectName("unpin");
  this->Frames = new QSpinBox(pinBox);
  this->Frames->setObjectName("frames");
  this->Frames->setRange(2, 1000);
  this->Frames->setValue(30);
  this->Frames->setSuffix(tr(" frames"));
  auto* animateButton = new QPushButton(tr("Animate to PNG..."), pinBox);
  animateButton->setObjectName("animate");
  animateButton->setToolTip(tr("Render ParaView frames moving through the pinned designs"));
  pinRow->addWidget(unpinButton);
  pinRow->addStretch(1);
  pinRow->addWidget(this->Frames);
  pinRow->addWidget(animateButton);
  pinLayout->addWidget(this->Pins);
  pinLayout->addWidget(this->Pad);
  pinLayout->addLayout(pinRow);
  layout->addWidget(pinBox);

  scroll->setWidget(contents);
  this->setWidget(scroll);
  this->setAcceptDrops(true);

  this->NavigateTimer = new QTimer(this);
  this->NavigateTimer->setSingleShot(true);
  this->NavigateTimer->setInterval(150);
  this->BoxTimer = new QTimer(this);
  this->BoxTimer->setSingleShot(true);
  this->BoxTimer->setInterval(400);

  QObject::connect(
    this->ModelPath, &QLineEdit::returnPressed, this, &pqDDGDesignGalleryDock::loadModel);
  QObject::connect(browseModel, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::browseModel);
  QObject::connect(buildModel, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::buildModel);
  QObject::connect(
    this->CancelButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::cancel);
  QObject::connect(backButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::back);
  QObject::connect(resampleButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::resample);
  QObject::connect(refreshButton, &QPushButton::clicked, this,
    [this]()
    {
      this->ThumbnailsAtCamera = true;
      this->refreshThumbnails();
    });
  QObject::connect(
    this->Outline, &pqDDGOutlineView::rowClicked, this, &pqDDGDesignGalleryDock::pickRow);
  QObject::connect(
    this->Outline, &pqDDGOutlineView::drillIn, this, &pqDDGDesignGalleryDock::drillIn);
  QObject::connect(
    this->Outline, &pqDDGOutlineView::boxChanged, this->BoxTimer, QOverload<>::of(&QTimer::start));
  QObject::connect(this->BoxTimer, &QTimer::timeout, this,
    [this]()
    {
      if (!this->Boxes.isEmpty())
      {
        this->Boxes.last() = this->Outline->box();
        this->refreshThumbnails();
      }
    });
  QObject::connect(browseQuery, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::browseQuery);
  QObject::connect(runQuery, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::runQuery);
  QObject::connect(
    this->QueryPath, &QLineEdit::returnPressed, this, &pqDDGDesignGalleryDock::runQuery);
  QObject::connect(pasteQuery, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::pasteQuery);
  auto* paste = new QShortcut(QKeySequence::Paste, this->Outline);
  QObject::connect(paste, &QShortcut::activated, this, &pqDDGDesignGalleryDock::pasteQuery);
  QObject::connect(applyButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::apply);
  QObject::connect(pinButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::pin);
  QObject::connect(unpinButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::unpin);
  QObject::connect(
    this->Pins, &QListWidget::itemSelectionChanged, this, &pqDDGDesignGalleryDock::updatePad);
  QObject::connect(
    this->Pad, &pqDDGNavigationPad::moved, this->NavigateTimer, QOverload<>::of(&QTimer::start));
  QObject::connect(this->NavigateTimer, &QTimer::timeout, this, &pqDDGDesignGalleryDock::navigate);
  QObject::connect(recolourButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::recolour);
  QObject::connect(moreButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::moreVisible);
  QObject::connect(lessButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::lessVisible);
  QObject::connect(
    exportPreset, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::exportPreset);
  QObject::connect(
    exportSlicer, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::exportSlicer);
  QObject::connect(
    exportHistory, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::exportHistory);
  QObject::connect(animateButton, &QPushButton::clicked, this, &pqDDGDesignGalleryDock::animate);

  pqProgressManager* progress = pqApplicationCore::instance()->getProgressManager();
  progress->addNonBlockableObject(this->CancelButton);
  QObject::connect(progress, &pqProgressManager::progress, this,
    [this](const QString&, int value)
    {
      if (this->Busy)
        this->Progress->setValue(value);
    });
  QObject::connect(&pqActiveObjects::instance(),
    QOverload<pqPipelineSource*>::of(&pqActiveObjects::sourceChanged), this,
    &pqDDGDesignGalleryDock::setSource);
  // the data information of a new source arrives with its first update or representation
  auto retry = [this]()
  {
    if (!this->Loaded && !this->Busy)
      this->setSource(pqActiveObjects::instance().activeSource());
  };
  QObject::connect(&pqActiveObjects::instance(), &pqActiveObjects::dataUpdated, this, retry);
  QObject::connect(&pqActiveObjects::instance(),
    QOverload<pqDataRepresentation*>::of(&pqActiveObjects::representationChanged), this, retry);
  this->setSource(pqActiveObjects::instance().activeSource());
}

pqDDGDesignGalleryDock::~pqDDGDesignGalleryDock() = default;

// --- state -----------------------------------------------------------------------------------

void pqDDGDesignGalleryDock::setStatus(const QString& text, bool error)
{
  this->Status->setText(text);
  this->Status->setToolTip(QString());
  this->Status->setStyleSheet(error ? "color: #b00000;" : "");
}

void pqDDGDesignGalleryDock::setBusy(bool busy)
{
  this->Busy = busy;
  this->CancelButton->setEnabled(busy);
  this->Progress->setValue(busy ? 0 : this->Progress->value());
  if (busy)
    this->Cancelled = false;
  else
    this->Progress->setValue(100);
}

void pqDDGDesignGalleryDock::clearModel()
{
  this->GalleryProxy = this->QueryProxy = this->DesignProxy = nullptr;
  this->Loaded = false;
  this->Boxes.clear();
  this->Steps = this->Latent = this->LockSteps = QJsonArray();
  this->Preset.clear();
  this->ParaView2D.clear();
  this->Slicer.clear();
  this->PreviewImage = QImage();
  this->Preview->clear();
  this->Info->clear();
  this->ClusterBox->clear();
  this->PinList.clear();
  this->Pins->clear();
  this->Pad->setAnchors({});
  for (auto* c : this->Locks)
    delete c;
  this->Locks.clear();
  this->Outline->setPoints({});
  this->Outline->setThumbnails({}, {});
  this->Outline->setQuery(false, {}, {});
}

void pqDDGDesignGalleryDock::setSource(pqPipelineSource* source)
{
  if (source == this->Source && this->Loaded)
    return;
  if (this->Source != source)
  {
    if (this->Source)
      QObject::disconnect(this->Source, nullptr, this, nullptr);
    if (source) // the data information arrives with the first update (Apply)
      QObject::connect(source, QOverload<pqPipelineSource*>::of(&pqPipelineSource::dataUpdated),
        this,
        [this](pqPipelineSource* updated)
        {
          if (!this->Loaded && updated == this->Source)
            this->setSource(updated);
        });
  }
  this->clearModel();
  this->Source = source;
  this->Array.clear();
  if (!source)
  {
    this->setStatus(tr("Select a volume (image data) in the Pipeline Browser."));
    this->Outline->setMessage(this->Status->text());
    return;
  }
  vtkPVDataInformation* info = source->getOutputPort(0)->getDataInformation();
  const int type = info ? info->GetDataSetType() : -1;
  vtkPVArrayInformation* scalars = nullptr;
  if (info && (type == VTK_IMAGE_DATA || type == VTK_UNIFORM_GRID || type == VTK_STRUCTURED_POINTS))
  {
    vtkPVDataSetAttributesInformation* points = info->GetPointDataInformation();
    scalars = points->GetAttributeInformation(vtkDataSetAttributes::SCALARS);
    for (int i = 0; !scalars && i < points->GetNumberOfArrays(); ++i)
      if (points->GetArrayInformation(i)->GetNumberOfComponents() == 1)
        scalars = points->GetArrayInformation(i);
  }
  if (type < 0 || (info && info->GetNumberOfPoints() == 0 && type == VTK_IMAGE_DATA))
  {
    this->setStatus(
      tr("'%1' has no data yet (Apply it in the Properties panel).").arg(source->getSMName()));
    this->Outline->setMessage(this->Status->text());
    return;
  }
  if (!scalars || scalars->GetNumberOfComponents() != 1)
  {
    this->setStatus(tr("'%1' is not a volume: the Design Gallery needs image data with a "
                       "one-component point array (e.g. a .vti, .raw or DICOM volume).")
                      .arg(source->getSMName()),
      true);
    this->Outline->setMessage(this->Status->text());
    return;
  }
  this->Array = QString::fromUtf8(scalars->GetName());
  // the shipped bundle named like the volume's file, if there is one
  QString guess;
  vtkSMProxy* proxy = source->getProxy();
  if (proxy->GetProperty("FileName") &&
    vtkSMPropertyHelper(proxy, "FileName").GetNumberOfElements() > 0)
  {
    const QString stem =
      QFileInfo(vtkSMPropertyHelper(proxy, "FileName").GetAsString(0)).completeBaseName();
    const QString dir = QString(DDG_DATA_DIR) + "/Models/" + stem.toLower();
    if (!stem.isEmpty() && QFileInfo(dir + "/bundle.json").exists())
      guess = dir;
  }
  if (!guess.isEmpty())
    this->ModelPath->setText(guess);
  if (this->ModelPath->text().isEmpty())
  {
    this->setStatus(tr("No model for '%1': load a model bundle of this volume (Load...) or "
                       "build one (Build...).")
                      .arg(source->getSMName()));
    this->Outline->setMessage(this->Status->text());
    return;
  }
  this->loadModel();
}

bool pqDDGDesignGalleryDock::ready(bool needDesign)
{
  if (!this->Source || this->Array.isEmpty())
  {
    this->setStatus(tr("Select a volume first."), true);
    return false;
  }
  if (!this->Loaded)
  {
    this->setStatus(tr("Load or build a model for this volume first."), true);
    return false;
  }
  if (needDesign && this->Steps.isEmpty())
  {
    this->setStatus(tr("Pick a design on the outline or query with a picture first."), true);
    return false;
  }
  return true;
}

pqDataRepresentation* pqDDGDesignGalleryDock::representation()
{
  auto* view = qobject_cast<pqRenderView*>(pqActiveObjects::instance().activeView());
  if (!view || !this->Source)
    return nullptr;
  pqDataRepresentation* repr = this->Source->getRepresentation(0, view);
  if (!repr)
  {
    vtkNew<vtkSMParaViewPipelineControllerWithRendering> controller;
    controller->Show(
      vtkSMSourceProxy::SafeDownCast(this->Source->getProxy()), 0, view->getViewProxy());
    repr = this->Source->getRepresentation(0, view);
  }
  return repr;
}

QJsonObject pqDDGDesignGalleryDock::currentView(int maxSide)
{
  auto* view = qobject_cast<pqRenderView*>(pqActiveObjects::instance().activeView());
  if (!view)
    return {};
  return ddgpanel::viewJson(
    view, this->Source ? this->Source->getRepresentation(0, view) : nullptr, maxSide);
}

QString pqDDGDesignGalleryDock::historyText(const QJsonArray& steps) const
{
  QJsonObject h;
  h["format"] = "ddg-history";
  h["version"] = 1;
  h["steps"] = steps;
  return QString::fromUtf8(QJsonDocument(h).toJson(QJsonDocument::Indented));
}

// --- model -----------------------------------------------------------------------------------

void pqDDGDesignGalleryDock::loadModel()
{
  if (!this->Source || this->Array.isEmpty())
    return;
  const QString dir = this->ModelPath->text().trimmed();
  const auto keepPath = dir;
  this->clearModel();
  this->ModelPath->setText(keepPath);
  if (dir.isEmpty())
    return;
  pqServer* server = this->Source->getServer();
  auto* input = vtkSMSourceProxy::SafeDownCast(this->Source->getProxy());
  const int port = 0;
  this->GalleryProxy = ddgpanel::newFilter(server, "DDGDesignGallery", input, port);
  this->QueryProxy = ddgpanel::newFilter(server, "DDGQuery", input, port);
  this->DesignProxy = ddgpanel::newFilter(server, "DDGDesign", input, port);
  if (!this->GalleryProxy || !this->QueryProxy || !this->DesignProxy)
  {
    this->setStatus(tr("The DesignGallery plugin is not loaded on the server (Tools > Manage "
                       "Plugins: load it on the remote side too)."),
      true);
    return;
  }
  for (vtkSMSourceProxy* p :
    { this->GalleryProxy.Get(), this->QueryProxy.Get(), this->DesignProxy.Get() })
  {
    vtkSMPropertyHelper(p, "ModelDirectory").Set(dir.toUtf8().constData());
    vtkSMPropertyHelper(p, "SelectInputScalars")
      .SetInputArrayToProcess(vtkDataObject::POINT, this->Array.toUtf8().constData());
    p->UpdateVTKObjects();
  }
  this->Boxes = { QRectF() }; // the whole outline
  this->Loaded = true;
  this->refreshThumbnails();
}

void pqDDGDesignGalleryDock::browseModel()
{
  if (!this->Source)
    return;
  pqFileDialog dialog(
    this->Source->getServer(), this, tr("Model bundle directory"), this->ModelPath->text());
  dialog.setObjectName("ModelDirectoryDialog");
  dialog.setFileMode(pqFileDialog::Directory);
  if (dialog.exec() == QDialog::Accepted && !dialog.getSelectedFiles().isEmpty())
  {
    this->ModelPath->setText(dialog.getSelectedFiles().first());
    this->loadModel();
  }
}

void pqDDGDesignGalleryDock::buildModel()
{
  if (!this->Source || this->Array.isEmpty())
  {
    this->setStatus(tr("Select a volume first."), true);
    return;
  }
  pqFileDialog dialog(this->Source->getServer(), this, tr("Directory of the new model bundle"));
  dialog.setObjectName("BuildDirectoryDialog");
  dialog.setFileMode(pqFileDialog::Directory);
  if (dialog.exec() != QDialog::Accepted || dialog.getSelectedFiles().isEmpty())
    return;
  const QString dir = dialog.getSelectedFiles().first();
  this->BuildProxy = ddgpanel::newFilter(this->Source->getServer(), "DDGBuildDesignSpace",
    vtkSMSourceProxy::SafeDownCast(this->Source->getProxy()), 0);
  if (!this->BuildProxy)
  {
    this->setStatus(tr("The DesignGallery plugin is not loaded on the server."), true);
    return;
  }
  vtkSMPropertyHelper(this->BuildProxy, "OutputDirectory").Set(dir.toUtf8().constData());
  vtkSMPropertyHelper(this->BuildProxy, "SelectInputScalars")
    .SetInputArrayToProcess(vtkDataObject::POINT, this->Array.toUtf8().constData());
  this->BuildProxy->UpdateVTKObjects();
  this->setStatus(tr("Building a design space in %1 (minutes; Cancel stops it)...").arg(dir));
  this->setBusy(true);
  // cancel: the filter checks AbortExecute between steps (the algorithm is reachable here in a
  // builtin session; with a remote server the build runs to its end)
  auto* algorithm = vtkAlgorithm::SafeDownCast(this->BuildProxy->GetClientSideObject());
  vtkNew<vtkCallbackCommand> onProgress;
  onProgress->SetClientData(this);
  onProgress->SetCallback(
    [](vtkObject* caller, unsigned long, void* self, void*)
    {
      QApplication::processEvents();
      if (static_cast<pqDDGDesignGalleryDock*>(self)->Cancelled)
        static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
    });
  const unsigned long observer =
    algorithm ? algorithm->AddObserver(vtkCommand::ProgressEvent, onProgress) : 0;
  this->BuildProxy->UpdatePipeline();
  if (algorithm)
    algorithm->RemoveObserver(observer);
  this->setBusy(false);
  const QString error = ddgpanel::lastError(this->BuildProxy);
  const bool built = QFileInfo(dir + "/bundle.json").exists() || error.isEmpty();
  this->BuildProxy = nullptr;
  if (this->Cancelled || !built)
  {
    this->setStatus(
      this->Cancelled ? tr("Build cancelled.") : tr("The build failed: %1").arg(error), true);
    return;
  }
  this->ModelPath->setText(dir);
  this->loadModel();
}

void pqDDGDesignGalleryDock::cancel()
{
  this->Cancelled = true;
}

// --- outline ---------------------------------------------------------------------------------

void pqDDGDesignGalleryDock::refreshThumbnails()
{
  if (!this->ready())
    return;
  const QRectF box = this->Boxes.isEmpty() ? QRectF() : this->Boxes.last();
  const double b[4] = { box.left(), box.top(), box.right(), box.bottom() };
  vtkSMPropertyHelper(this->GalleryProxy, "Box").Set(b, 4);
  vtkSMPropertyHelper(this->GalleryProxy, "Count").Set(kThumbnails);
  vtkSMPropertyHelper(this->GalleryProxy, "ThumbnailSize").Set(kThumbnailSize);
  vtkSMPropertyHelper(this->GalleryProxy, "Seed").Set(this->Seed);
  // the volume's default view (the whole volume in sight), or the view's camera once asked for
  const QJsonObject view =
    this->ThumbnailsAtCamera ? this->currentView(kThumbnailSize) : QJsonObject();
  vtkSMPropertyHelper(this->GalleryProxy, "ViewJSON")
    .Set(view.isEmpty() ? "" : ddgpanel::jsonText(view).toUtf8().constData());
  this->GalleryProxy->UpdateVTKObjects();
  this->setBusy(true);
  this->GalleryProxy->UpdatePipeline();
  this->setBusy(false);
  pqServer* server = this->Source->getServer();
  vtkSmartPointer<vtkTable> table =
    vtkTable::SafeDownCast(ddgpanel::fetch(server, this->GalleryProxy, 1));
  auto sheet = ddgpanel::fetch(server, this->GalleryProxy, 0);
  if (!table)
  {
    const QString error = ddgpanel::lastError(this->GalleryProxy);
    this->Loaded = false;
    this->setStatus(error.contains("another volume")
        ? tr("This model belongs to another volume: %1").arg(error)
        : tr("No usable model in '%1': %2. Load a bundle of this volume or build one.")
            .arg(this->ModelPath->text(), error),
      true);
    this->Outline->setMessage(this->Status->text());
    return;
  }
  vtkDataArray* xs = vtkDataArray::SafeDownCast(table->GetColumnByName("X"));
  vtkDataArray* ys = vtkDataArray::SafeDownCast(table->GetColumnByName("Y"));
  vtkDataArray* cells = vtkDataArray::SafeDownCast(table->GetColumnByName("Thumbnail"));
  if (!xs || !ys || !cells)
    return;
  QVector<QPointF> points(static_cast<int>(table->GetNumberOfRows()));
  QVector<int> thumbRows(kThumbnails, -1);
  for (vtkIdType i = 0; i < table->GetNumberOfRows(); ++i)
  {
    points[static_cast<int>(i)] = QPointF(xs->GetTuple1(i), ys->GetTuple1(i));
    const int cell = static_cast<int>(cells->GetTuple1(i));
    if (cell >= 0 && cell < kThumbnails)
      thumbRows[cell] = static_cast<int>(i);
  }
  const QJsonArray shown = fieldArray(table, "Box");
  // thumbnails: cells of the sheet, row by row (gap 2 px)
  const QImage sheetImage = toQImage(sheet);
  QVector<int> rows;
  QVector<QImage> images;
  const int gap = 2,
            cols = sheetImage.isNull() ? 0 : (sheetImage.width() - gap) / (kThumbnailSize + gap);
  for (int k = 0; k < kThumbnails && cols > 0; ++k)
  {
    if (thumbRows[k] < 0)
      continue;
    rows.push_back(thumbRows[k]);
    images.push_back(sheetImage.copy(gap + (k % cols) * (kThumbnailSize + gap),
      gap + (k / cols) * (kThumbnailSize + gap), kThumbnailSize, kThumbnailSize));
  }
  this->Outline->setPoints(points);
  if (shown.size() == 4)
  {
    const QRectF b2(QPointF(shown[0].toDouble(), shown[1].toDouble()),
      QPointF(shown[2].toDouble(), shown[3].toDouble()));
    this->Outline->setBox(b2.normalized());
    this->Boxes.last() = b2.normalized();
  }
  this->Outline->setThumbnails(rows, images);
  this->setStatus(tr("%1 designs of '%2'; %3 thumbnails. Click one, or query with a picture.")
                    .arg(points.size())
                    .arg(this->Source->getSMName())
                    .arg(rows.size()));
}

void pqDDGDesignGalleryDock::drillIn(const QRectF& box)
{
  if (!this->ready())
    return;
  this->Boxes.push_back(box.normalized());
  this->refreshThumbnails();
}

void pqDDGDesignGalleryDock::back()
{
  if (this->Boxes.size() > 1)
    this->Boxes.pop_back();
  else if (!this->Boxes.isEmpty())
    this->Boxes.last() = QRectF(); // back out to the whole outline
  this->refreshThumbnails();
}

void pqDDGDesignGalleryDock::resample()
{
  ++this->Seed;
  this->refreshThumbnails();
}

// --- designs ---------------------------------------------------------------------------------

void pqDDGDesignGalleryDock::setSteps(const QJsonArray& steps)
{
  this->Steps = steps;
  for (auto* a : this->Axes)
  {
    a->blockSignals(true);
    a->setValue(0);
    a->blockSignals(false);
  }
  this->updateDesign();
}

void pqDDGDesignGalleryDock::pickRow(int row)
{
  if (!this->ready())
    return;
  this->setSteps(QJsonArray{ QJsonObject{ { "action", "pick" }, { "row", row } } });
}

bool pqDDGDesignGalleryDock::updateDesign()
{
  if (!this->ready(true))
    return false;
  this->DesignView = this->currentView(kPreviewSide);
  if (this->DesignView.isEmpty())
  {
    this->setStatus(tr("Open a render view first."), true);
    return false;
  }
  vtkSMPropertyHelper(this->DesignProxy, "History")
    .Set(this->historyText(this->Steps).toUtf8().constData());
  vtkSMPropertyHelper(this->DesignProxy, "ViewJSON")
    .Set(ddgpanel::jsonText(this->DesignView).toUtf8().constData());
  vtkSMPropertyHelper(this->DesignProxy, "ComputeFidelity").Set(1);
  std::vector<int> locked;
  for (int k = 0; k < this->Locks.size(); ++k)
    if (this->Locks[k]->isChecked())
      locked.push_back(k);
  vtkSMPropertyHelper(this->DesignProxy, "LockedRegions")
    .Set(locked.data(), static_cast<unsigned int>(locked.size()));
  vtkSMPropertyHelper(this->DesignProxy, "LockHistory")
    .Set(locked.empty() ? "" : this->historyText(this->LockSteps).toUtf8().constData());
  this->DesignProxy->UpdateVTKObjects();
  this->DesignProxy->UpdatePipeline();
  pqServer* server = this->Source->getServer();
  vtkSmartPointer<vtkTable> table =
    vtkTable::SafeDownCast(ddgpanel::fetch(server, this->DesignProxy, 1));
  if (!table)
  {
    this->setStatus(
      tr("The design could not be made: %1").arg(ddgpanel::lastError(this->DesignProxy)), true);
    return false;
  }
  this->PreviewImage = toQImage(ddgpanel::fetch(server, this->DesignProxy, 0));
  this->Preview->setPixmap(QPixmap::fromImage(this->PreviewImage));
  this->Latent = fieldArray(table, "Latent");
  this->Preset = fieldString(table, "Preset");
  if (this->Preset.isEmpty())
    this->Preset = fieldString(table, "TransferFunction2D");
  this->ParaView2D = fieldString(table, "ParaViewTransferFunction2D");
  this->Slicer = fieldString(table, "Slicer");
  const QJsonArray position = fieldArray(table, "Position");
  const QJsonArray fidelity = fieldArray(table, "Fidelity");
  const QJsonArray regions = fieldArray(table, "Regions");
  int row = -1;
  if (this->Steps.size() == 1 && this->Steps[0].toObject().value("action") == "pick")
    row = this->Steps[0].toObject().value("row").toInt();
  if (position.size() == 2)
    this->Outline->setSelection(row, QPointF(position[0].toDouble(), position[1].toDouble()));
  QStringList path;
  for (const auto& s : this->Steps)
    path << s.toObject().value("action").toString();
  this->Info->setText(tr("Path: %1\nFidelity (neural vs. ray cast of its TF at this camera): "
                         "PSNR %2 dB, SSIM %3")
                        .arg(path.join(QString::fromUtf8(" \u2192 ")))
                        .arg(fidelity.size() >= 2 ? fidelity[0].toDouble() : 0.0, 0, 'f', 1)
                        .arg(fidelity.size() >= 2 ? fidelity[1].toDouble() : 0.0, 0, 'f', 3));
  // colour clusters: what edits act on
  const int current = this->ClusterBox->currentIndex();
  this->ClusterBox->clear();
  vtkDataArray* share = vtkDataArray::SafeDownCast(table->GetColumnByName("Share"));
  vtkDataArray* r = vtkDataArray::SafeDownCast(table->GetColumnByName("R"));
  vtkDataArray* g = vtkDataArray::SafeDownCast(table->GetColumnByName("G"));
  vtkDataArray* b = vtkDataArray::SafeDownCast(table->GetColumnByName("B"));
  for (vtkIdType k = 0; share && r && g && b && k < table->GetNumberOfRows(); ++k)
  {
    QPixmap swatch(16, 16);
    swatch.fill(QColor::fromRgbF(r->GetTuple1(k), g->GetTuple1(k), b->GetTuple1(k)));
    this->ClusterBox->addItem(
      QIcon(swatch), tr("colour %1 (%2 %)").arg(k + 1).arg(std::lround(100 * share->GetTuple1(k))));
  }
  if (current >= 0 && current < this->ClusterBox->count())
    this->ClusterBox->setCurrentIndex(current);
  // feature locks: one per region of the model
  if (this->Locks.size() != regions.size() / 2)
  {
    for (auto* c : this->Locks)
      delete c;
    this->Locks.clear();
    for (int k = 0; k + 1 < regions.size(); k += 2)
    {
      auto* box = new QCheckBox(QString::number(k / 2 + 1), this->LockBox);
      box->setObjectName(QString("lock%1").arg(k / 2));
      box->setToolTip(tr("Keep feature region %1 (values %2 to %3) as it is now")
                        .arg(k / 2 + 1)
                        .arg(regions[k].toDouble(), 0, 'g', 4)
                        .arg(regions[k + 1].toDouble(), 0, 'g', 4));
      this->LockBox->layout()->addWidget(box);
      QObject::connect(box, &QCheckBox::toggled, this, &pqDDGDesignGalleryDock::lockChanged);
      this->Locks.push_back(box);
    }
  }
  this->setStatus(tr("Design ready: Apply writes its transfer function into the volume's maps."));
  return true;
}

void pqDDGDesignGalleryDock::browseQuery()
{
  const QString path = QFileDialog::getOpenFileName(this, tr("Query image"),
    this->QueryPath->text(), tr("Images (*.png *.jpg *.jpeg *.tif *.tiff *.bmp);;All files (*)"));
  if (!path.isEmpty())
  {
    this->QueryPath->setText(path);
    this->queryFile(path);
  }
}

void pqDDGDesignGalleryDock::runQuery()
{
  const QString path = this->QueryPath->text().trimmed();
  if (path.isEmpty())
    this->browseQuery();
  else
    this->queryFile(path);
}

void pqDDGDesignGalleryDock::pasteQuery()
{
  const QImage image = QApplication::clipboard()->image();
  if (image.isNull())
  {
    this->setStatus(tr("The clipboard holds no image."), true);
    return;
  }
  this->queryImage(image, tr("clipboard"));
}

void pqDDGDesignGalleryDock::queryFile(const QString& path)
{
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly))
  {
    this->setStatus(tr("Cannot open the query image '%1'.").arg(path), true);
    return;
  }
  const QByteArray bytes = file.readAll();
  const bool direct = bytes.startsWith("\x89PNG") || bytes.startsWith("\xff\xd8\xff") ||
    bytes.startsWith("II*") || bytes.startsWith("MM");
  if (direct && bytes.size() < 32 * 1024 * 1024)
  {
    // the file as it is: the server reads it exactly as `ddg query` reads the file
    if (!this->ready())
      return;
    vtkSMPropertyHelper(this->QueryProxy, "ImageData").Set(base64Of(bytes).toLatin1().constData());
    this->queryImage(QImage(), QFileInfo(path).fileName());
    return;
  }
  const QImage image = QImage::fromData(bytes);
  if (image.isNull())
  {
    this->setStatus(tr("'%1' is not an image this panel can read.").arg(path), true);
    return;
  }
  this->queryImage(image, QFileInfo(path).fileName());
}

void pqDDGDesignGalleryDock::queryImage(const QImage& image, const QString& name)
{
  if (!this->ready())
    return;
  if (!image.isNull())
  {
    QByteArray png;
    QBuffer buffer(&png);
    buffer.open(QIODevice::WriteOnly);
    image.save(&buffer, "PNG");
    vtkSMPropertyHelper(this->QueryProxy, "ImageData").Set(base64Of(png).toLatin1().constData());
  }
  const QJsonObject view = this->currentView(kPreviewSide);
  vtkSMPropertyHelper(this->QueryProxy, "ViewJSON")
    .Set(ddgpanel::jsonText(view).toUtf8().constData());
  vtkSMPropertyHelper(this->QueryProxy, "Neighbours").Set(5);
  this->QueryProxy->UpdateVTKObjects();
  this->QueryProxy->UpdatePipeline();
  vtkSmartPointer<vtkTable> table =
    vtkTable::SafeDownCast(ddgpanel::fetch(this->Source->getServer(), this->QueryProxy, 1));
  vtkSMPropertyHelper(this->QueryProxy, "ImageData").Set(""); // do not keep megabytes around
  this->QueryProxy->UpdateVTKObjects();
  if (!table)
  {
    this->setStatus(tr("The query failed: %1").arg(ddgpanel::lastError(this->QueryProxy)), true);
    return;
  }
  QVector<int> neighbours;
  vtkDataArray* rows = vtkDataArray::SafeDownCast(table->GetColumnByName("Row"));
  for (vtkIdType i = 0; rows && i < rows->GetNumberOfTuples(); ++i)
    neighbours.push_back(static_cast<int>(rows->GetTuple1(i)));
  const QJsonArray position = fieldArray(table, "Position");
  const QJsonArray latent = fieldArray(table, "Latent");
  if (position.size() == 2)
    this->Outline->setQuery(
      true, QPointF(position[0].toDouble(), position[1].toDouble()), neighbours);
  this->setSteps(
    QJsonArray{ QJsonObject{ { "action", "latent" }, { "latent", latent }, { "image", name } } });
}

void pqDDGDesignGalleryDock::dragEnterEvent(QDragEnterEvent* e)
{
  if (e->mimeData()->hasUrls() || e->mimeData()->hasImage())
    e->acceptProposedAction();
}

void pqDDGDesignGalleryDock::dropEvent(QDropEvent* e)
{
  if (e->mimeData()->hasUrls() && e->mimeData()->urls().first().isLocalFile())
  {
    const QString path = e->mimeData()->urls().first().toLocalFile();
    this->QueryPath->setText(path);
    this->queryFile(path);
  }
  else if (e->mimeData()->hasImage())
    this->queryImage(qvariant_cast<QImage>(e->mimeData()->imageData()), tr("dropped image"));
  e->acceptProposedAction();
}

// --- archive strip and navigation ----------------------------------------------------------

void pqDDGDesignGalleryDock::pin()
{
  if (!this->ready(true) || this->Latent.isEmpty())
    return;
  this->PinList.push_back({ this->Steps, this->Latent, this->PreviewImage });
  auto* item = new QListWidgetItem(
    QIcon(QPixmap::fromImage(this->PreviewImage)), QString::number(this->PinList.size()));
  this->Pins->addItem(item);
  this->updatePad();
}

void pqDDGDesignGalleryDock::unpin()
{
  const auto selected = this->Pins->selectedItems();
  QVector<int> rows;
  for (auto* item : selected)
    rows.push_back(this->Pins->row(item));
  std::sort(rows.begin(), rows.end(), std::greater<int>());
  for (int r : rows)
  {
    delete this->Pins->takeItem(r);
    this->PinList.removeAt(r);
  }
  this->updatePad();
}

void pqDDGDesignGalleryDock::updatePad()
{
  // the selected pins when 2-4 are selected, else the first (up to) four
  QVector<int> chosen;
  for (auto* item : this->Pins->selectedItems())
    chosen.push_back(this->Pins->row(item));
  std::sort(chosen.begin(), chosen.end());
  if (chosen.size() < 2 || chosen.size() > 4)
  {
    chosen.clear();
    for (int k = 0; k < std::min(4, static_cast<int>(this->PinList.size())); ++k)
      chosen.push_back(k);
  }
  QVector<QImage> icons;
  for (int k : chosen)
    icons.push_back(this->PinList[k].icon);
  this->Pad->setProperty("pins", QVariant::fromValue(QList<int>(chosen.begin(), chosen.end())));
  this->Pad->setAnchors(icons.size() >= 2 ? icons : QVector<QImage>());
}

void pqDDGDesignGalleryDock::navigate()
{
  const QList<int> chosen = this->Pad->property("pins").value<QList<int>>();
  if (chosen.size() < 2 || !this->ready())
    return;
  QJsonArray latents;
  for (int k : chosen)
    latents.append(this->PinList[k].latent);
  this->setSteps(QJsonArray{ QJsonObject{ { "action", "blend" }, { "latents", latents },
    { "u", this->Pad->u() }, { "v", this->Pad->v() } } });
}

// --- edits ------------------------------------------------------------------------------------

void pqDDGDesignGalleryDock::appendEdit(double hue, double visibility)
{
  if (!this->ready(true))
    return;
  if (this->ClusterBox->currentIndex() < 0)
  {
    this->setStatus(tr("This design shows no colour to edit."), true);
    return;
  }
  QJsonObject step{ { "action", "edit" }, { "view", this->DesignView },
    { "cluster", this->ClusterBox->currentIndex() }, { "clusters", 4 }, { "hue", hue },
    { "saturation", 1.0 }, { "lightness", 0.0 }, { "visibility", visibility }, { "white", false } };
  QJsonArray steps = this->Steps;
  steps.append(step);
  const QJsonArray before = this->Steps;
  this->Steps = steps;
  if (!this->updateDesign())
  {
    this->Steps = before; // the edit is dropped, the design stays
    this->updateDesign();
  }
}

void pqDDGDesignGalleryDock::recolour()
{
  this->appendEdit(this->Hue->value(), 1.0);
}

void pqDDGDesignGalleryDock::moreVisible()
{
  this->appendEdit(0.0, 1.5);
}

void pqDDGDesignGalleryDock::lessVisible()
{
  this->appendEdit(0.0, 1.0 / 1.5);
}

void pqDDGDesignGalleryDock::axesReleased()
{
  if (!this->ready(true))
    return;
  QJsonArray values;
  for (auto* a : this->Axes)
    values.append(a->value() / 10.0);
  QJsonArray steps = this->Steps;
  const QJsonObject step{ { "action", "axes" }, { "steps", values } };
  if (!steps.isEmpty() && steps.last().toObject().value("action") == "axes")
    steps.last() = step; // the sliders move one step
  else
    steps.append(step);
  this->Steps = steps;
  this->updateDesign();
}

void pqDDGDesignGalleryDock::lockChanged()
{
  bool any = false;
  for (auto* c : this->Locks)
    any = any || c->isChecked();
  if (any && this->LockSteps.isEmpty())
    this->LockSteps = this->Steps; // the regions stay as in the design shown now
  if (!any)
    this->LockSteps = QJsonArray();
  this->updateDesign();
}

// --- apply, export, animate ----------------------------------------------------------------

void pqDDGDesignGalleryDock::apply()
{
  if (!this->ready(true) || !this->updateDesign()) // the TF at the current camera
    return;
  const bool twoD = !this->ParaView2D.isEmpty();
  const QString error = twoD
    ? ddgpanel::applyTransferFunction2D(this->representation(), this->Array, this->ParaView2D,
        tr("Apply Design Gallery 2D Transfer Function"))
    : ddgpanel::applyPreset(this->representation(), this->Array, this->Preset,
        tr("Apply Design Gallery Transfer Function"));
  if (!error.isEmpty())
  {
    this->setStatus(tr("Apply failed: %1").arg(error), true);
    return;
  }
  if (auto* view = pqActiveObjects::instance().activeView())
    view->render();
  if (twoD)
  {
    const QJsonObject pv = QJsonDocument::fromJson(this->ParaView2D.toUtf8()).object();
    this->setStatus(tr("Applied to '%1' as ParaView 2D boxes (Edit > Undo takes it back; the Color "
                       "Map Editor's 2D editor shows them).")
                      .arg(this->Source->getSMName()));
    this->Status->setToolTip(
      tr("%1 Gaussian boxes fitted to the design: RMSE %2 of emission and "
         "per-sample opacity (largest opacity %3)")
        .arg(pv.value("Boxes").toArray().size() / 8)
        .arg(pv.value("Fit").toObject().value("rmse").toDouble(), 0, 'f', 4)
        .arg(pv.value("Fit").toObject().value("max_alpha").toDouble(), 0, 'f', 3));
    return;
  }
  this->setStatus(tr("Applied to '%1' (Edit > Undo takes it back; the Color Map Editor shows it).")
                    .arg(this->Source->getSMName()));
}

void pqDDGDesignGalleryDock::exportPreset()
{
  if (!this->ready(true) || this->Preset.isEmpty())
    return;
  const QString path = QFileDialog::getSaveFileName(
    this, tr("Export ParaView preset"), "design.json", tr("JSON (*.json)"));
  if (!path.isEmpty() && !writeText(path, this->Preset))
    this->setStatus(tr("Cannot write %1.").arg(path), true);
}

void pqDDGDesignGalleryDock::exportSlicer()
{
  if (!this->ready(true))
    return;
  if (this->Slicer.isEmpty())
  {
    this->setStatus(tr("3D Slicer's format holds 1D transfer functions only."), true);
    return;
  }
  const QString path = QFileDialog::getSaveFileName(
    this, tr("Export 3D Slicer volume property"), "design.vp.json", tr("JSON (*.json)"));
  if (!path.isEmpty() && !writeText(path, this->Slicer))
    this->setStatus(tr("Cannot write %1.").arg(path), true);
}

void pqDDGDesignGalleryDock::exportHistory()
{
  if (!this->ready(true))
    return;
  const QString path = QFileDialog::getSaveFileName(
    this, tr("Export design history (ddg replay)"), "history.json", tr("JSON (*.json)"));
  if (!path.isEmpty() && !writeText(path, this->historyText(this->Steps)))
    this->setStatus(tr("Cannot write %1.").arg(path), true);
}

void pqDDGDesignGalleryDock::animate()
{
  if (!this->ready() || this->PinList.size() < 2)
  {
    this->setStatus(tr("Pin at least two designs to animate between them."), true);
    return;
  }
  auto* view = qobject_cast<pqRenderView*>(pqActiveObjects::instance().activeView());
  pqDataRepresentation* repr = this->representation();
  if (!view || !repr)
  {
    this->setStatus(tr("Open a render view showing the volume first."), true);
    return;
  }
  const QString dir = QFileDialog::getExistingDirectory(this, tr("Directory of the PNG frames"));
  if (dir.isEmpty())
    return;
  const QString before = ddgpanel::currentPreset(repr);
  const QJsonArray stepsBefore = this->Steps;
  const int perLeg = this->Frames->value();
  const int legs = static_cast<int>(this->PinList.size()) - 1;
  const QSize size = view->getSize();
  this->setBusy(true);
  int written = 0;
  QString error;
  for (int leg = 0; leg < legs && error.isEmpty() && !this->Cancelled; ++leg)
    for (int f = (leg == 0 ? 0 : 1); f < perLeg && error.isEmpty() && !this->Cancelled; ++f)
    {
      const double t = perLeg > 1 ? static_cast<double>(f) / (perLeg - 1) : 1.0;
      const double eased = t * t * (3 - 2 * t); // smoothstep, as ddg animate
      this->Steps = QJsonArray{ QJsonObject{ { "action", "blend" },
        { "latents", QJsonArray{ this->PinList[leg].latent, this->PinList[leg + 1].latent } },
        { "u", eased }, { "v", 0.0 } } };
      if (!this->updateDesign())
      {
        error = this->Status->text();
        break;
      }
      error = ddgpanel::applyPreset(repr, this->Array, this->Preset, QString(), false);
      view->forceRender();
      const QString file =
        QDir(dir).filePath(QString("frame_%1.png").arg(written, 4, 10, QChar('0')));
      if (error.isEmpty() && !pqSaveScreenshotReaction::saveScreenshot(file, size, -1))
        error = tr("cannot write %1").arg(file);
      ++written;
      this->Progress->setValue(100 * written / std::max(1, legs * (perLeg - 1) + 1));
      QApplication::processEvents();
    }
  this->setBusy(false);
  // the scene as it was
  ddgpanel::applyPreset(repr, this->Array, before, QString(), false);
  view->render();
  this->Steps = stepsBefore;
  this->updateDesign();
  this->setStatus(!error.isEmpty() ? tr("Animation stopped: %1").arg(error)
      : this->Cancelled            ? tr("Animation cancelled after %1 frames.").arg(written)
                                   : tr("Wrote %1 frames to %2.").arg(written).arg(dir),
    !error.isEmpty());
}
