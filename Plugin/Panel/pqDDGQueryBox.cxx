// pqDDGQueryBox.cxx: reading the query image of the Design Gallery panel, and the strip of the
// query's nearest designs under it.
#include "pqDDGQueryBox.h"
#include "ui_pqDDGQueryBox.h"

#include "pqDDGDesignState.h"

#include <QApplication>
#include <QBuffer>
#include <QClipboard>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QImage>
#include <QImageReader>
#include <QPixmap>
#include <QToolButton>
#include <vtkSMDDGScene.h>

#include <algorithm>
#include <cmath>
#include <limits>

pqDDGQueryBox::pqDDGQueryBox(QWidget* parent)
  : QGroupBox(parent)
  , Ui(new Ui::pqDDGQueryBox)
{
  this->Ui->setupUi(this);
  this->Ui->neighboursLabel->setWordWrap(true); // a long file name must not widen the dock
  this->Ui->neighboursLabel->setTextFormat(Qt::PlainText); // nor be read as HTML
  QObject::connect(this->Ui->browseQuery, &QPushButton::clicked, this, &pqDDGQueryBox::browse);
  QObject::connect(this->Ui->query, &QPushButton::clicked, this, &pqDDGQueryBox::run);
  QObject::connect(this->Ui->queryPath, &QLineEdit::returnPressed, this, &pqDDGQueryBox::run);
  QObject::connect(this->Ui->paste, &QPushButton::clicked, this, &pqDDGQueryBox::paste);
}

pqDDGQueryBox::~pqDDGQueryBox() = default;

void pqDDGQueryBox::setState(pqDDGDesignState* state)
{
  this->State = state;
  QObject::connect(state, &pqDDGDesignState::queried, this,
    [this](const QPointF&, const QVector<int>& rows, const QVector<QImage>& thumbnails,
      const QVector<double>& against) { this->showNeighbours(rows, thumbnails, against); });
  QObject::connect(
    state, &pqDDGDesignState::modelCleared, this, [this]() { this->showNeighbours({}, {}, {}); });
}

void pqDDGQueryBox::showNeighbours(
  const QVector<int>& rows, const QVector<QImage>& thumbnails, const QVector<double>& against)
{
  qDeleteAll(this->NeighbourButtons);
  this->NeighbourButtons.clear();
  const int shown = std::min(rows.size(), thumbnails.size());
  for (int k = 0; k < shown; ++k)
  {
    auto* button = new QToolButton(this->Ui->neighbours);
    button->setObjectName(QString("neighbour%1").arg(k));
    button->setIcon(QPixmap::fromImage(thumbnails[k]));
    button->setIconSize(thumbnails[k].size());
    button->setAutoRaise(true);
    const double figure = against.value(k, std::numeric_limits<double>::quiet_NaN());
    QString tip = tr("Nearest design %1 of the query (outline row %2)").arg(k + 1).arg(rows[k]);
    if (std::isfinite(figure)) // under the thumbnail: how close it looks to the picture
    {
      button->setText(tr("%1 dB").arg(figure, 0, 'f', 1));
      button->setToolButtonStyle(Qt::ToolButtonTextUnderIcon);
      tip += tr(", %1 dB against the picture (framed alike, as the query's design)")
               .arg(figure, 0, 'f', 1);
    }
    button->setToolTip(tip + tr(": click to show it."));
    const int row = rows[k];
    QObject::connect(button, &QToolButton::clicked, this,
      [this, row]()
      {
        if (this->State)
          this->State->pick(row);
      });
    this->Ui->neighbourRow->insertWidget(this->Ui->neighbourRow->count() - 1, button);
    this->NeighbourButtons.push_back(button);
  }
  if (this->State && shown > 0) // which picture they answer (the path field may say another)
    this->Ui->neighboursLabel->setText(
      tr("The nearest designs to '%1' (click one to show it):").arg(this->State->queryName()));
  this->Ui->neighbours->setVisible(shown > 0);
}

void pqDDGQueryBox::browse()
{
  const QString path =
    QFileDialog::getOpenFileName(this, tr("Query image"), this->Ui->queryPath->text(),
      tr("Images (*.png *.jpg *.jpeg *.tif *.tiff *.bmp *.gif *.webp);;All files (*)"));
  if (!path.isEmpty())
    this->queryPath(path);
}

void pqDDGQueryBox::run()
{
  const QString path = this->Ui->queryPath->text().trimmed();
  if (path.isEmpty())
    this->browse();
  else
    this->queryFile(path);
}

void pqDDGQueryBox::paste()
{
  const QImage image = QApplication::clipboard()->image();
  if (image.isNull())
  {
    this->State->report(tr("The clipboard holds no image."), true);
    return;
  }
  this->queryImage(image, tr("clipboard"));
}

void pqDDGQueryBox::queryPath(const QString& path)
{
  this->Ui->queryPath->setText(path);
  this->queryFile(path);
}

void pqDDGQueryBox::queryFile(const QString& path)
{
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly))
  {
    this->State->report(tr("Cannot open the query image '%1'.").arg(path), true);
    return;
  }
  // huge pictures: refused beyond what the server reads (16384 a side, 64 Mpixel), downscaled to
  // 2048 on the longer side beyond 4096 (the query and the match work at any size)
  QImageReader header(path);
  const QSize size = header.size();
  constexpr qint64 maxSide = 16384, maxPixels = 64LL * 1024 * 1024, downscaleAbove = 4096;
  if (size.isValid() &&
    (size.width() > maxSide || size.height() > maxSide ||
      static_cast<qint64>(size.width()) * size.height() > maxPixels))
  {
    this->State->report(tr("'%1' is %2 x %3 pixels: too large (at most 16384 on a side and 64 "
                           "Mpixel). Downscale it first.")
                          .arg(path)
                          .arg(size.width())
                          .arg(size.height()),
      true);
    return;
  }
  if (size.isValid() && std::max(size.width(), size.height()) > downscaleAbove)
  {
    header.setScaledSize(size.scaled(2048, 2048, Qt::KeepAspectRatio));
    const QImage scaled = header.read();
    if (!scaled.isNull())
    {
      this->queryImage(scaled, QFileInfo(path).fileName());
      return;
    }
  }
  const QByteArray bytes = file.readAll();
  // a format the server's reader (Core's decodeImage) tells by its first bytes: PNG, JPEG, TIFF,
  // BMP, GIF, WebP (this Qt may lack a WebP plugin: the server reads it all the same)
  const bool direct = !vtkSMDDGScene::PictureFormat(bytes.left(16).toStdString()).empty();
  if (direct && bytes.size() < 32 * 1024 * 1024)
  {
    // the file as it is: the server reads it exactly as `ddg query` reads the file
    this->State->query(bytes, QFileInfo(path).fileName());
    return;
  }
  const QImage image = QImage::fromData(bytes);
  if (image.isNull())
  {
    this->State->report(tr("'%1' is not an image this panel can read.").arg(path), true);
    return;
  }
  this->queryImage(image, QFileInfo(path).fileName());
}

void pqDDGQueryBox::queryImage(const QImage& image, const QString& name)
{
  if (!this->State->hasVolume())
    return;
  QByteArray png;
  if (!image.isNull())
  {
    QBuffer buffer(&png);
    buffer.open(QIODevice::WriteOnly);
    image.save(&buffer, "PNG");
  }
  this->State->query(png, name);
}
