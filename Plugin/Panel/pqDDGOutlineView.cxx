// pqDDGOutlineView.cxx: painting and interaction of the outline.
#include "pqDDGOutlineView.h"

#include <QLabel>
#include <QMouseEvent>
#include <QPainter>
#include <QToolButton>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>
#include <limits>

namespace
{
constexpr int kMargin = 6;
}

/// Covers the outline view above its thumbnails and paints its marks; mouse events pass through.
class pqDDGOutlineMarks : public QWidget
{
public:
  explicit pqDDGOutlineMarks(pqDDGOutlineView* view)
    : QWidget(view)
    , View(view)
  {
    this->setAttribute(Qt::WA_TransparentForMouseEvents);
    this->setAttribute(Qt::WA_NoSystemBackground);
  }

protected:
  void paintEvent(QPaintEvent*) override
  {
    QPainter p(this);
    this->View->paintMarks(p);
  }

private:
  pqDDGOutlineView* View;
};

pqDDGOutlineView::pqDDGOutlineView(QWidget* parent)
  : QWidget(parent)
{
  this->setMinimumSize(240, 240);
  this->setMouseTracking(true);
  this->setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Expanding);
  this->HoverLabel = new QLabel(this);
  this->HoverLabel->setObjectName("hoverPreview");
  this->HoverLabel->setFrameShape(QFrame::Box);
  this->HoverLabel->setScaledContents(true);
  this->HoverLabel->hide();
  this->Marks = new pqDDGOutlineMarks(this);
  this->Marks->setObjectName("outlineMarks");
}

void pqDDGOutlineView::setPoints(const QVector<QPointF>& points)
{
  this->Points = points;
  this->Selected = -1;
  this->SelectedShown = false;
  this->update();
}

void pqDDGOutlineView::setThumbnails(const QVector<int>& rows, const QVector<QImage>& images)
{
  this->ThumbRows = rows;
  this->ThumbImages = images;
  this->HoverLabel->hide();
  while (this->ThumbButtons.size() > rows.size())
    delete this->ThumbButtons.takeLast();
  while (this->ThumbButtons.size() < rows.size())
  {
    const int k = static_cast<int>(this->ThumbButtons.size());
    auto* b = new QToolButton(this);
    b->setObjectName(QString("thumb%1").arg(k));
    b->setAutoRaise(true);
    b->setCheckable(true);
    b->installEventFilter(this);
    QObject::connect(b, &QToolButton::clicked, this,
      [this, k]()
      {
        if (k < this->ThumbRows.size())
          Q_EMIT this->rowClicked(this->ThumbRows[k]);
      });
    this->ThumbButtons.push_back(b);
  }
  for (int k = 0; k < rows.size(); ++k)
  {
    this->ThumbButtons[k]->setIcon(QIcon(QPixmap::fromImage(images.value(k))));
    this->ThumbButtons[k]->setToolTip(tr("design %1 of the outline").arg(rows[k]));
    this->ThumbButtons[k]->setChecked(rows[k] == this->Selected);
  }
  this->placeThumbnails();
  this->Marks->raise();
  this->HoverLabel->raise();
  this->update();
}

void pqDDGOutlineView::placeThumbnails()
{
  for (int k = 0; k < this->ThumbButtons.size(); ++k)
  {
    const QRectF r = this->thumbRect(k);
    this->ThumbButtons[k]->setVisible(!r.isEmpty() && !this->Points.isEmpty());
    this->ThumbButtons[k]->setGeometry(r.toRect());
    this->ThumbButtons[k]->setIconSize(r.size().toSize() - QSize(4, 4));
  }
}

void pqDDGOutlineView::showHover(int k)
{
  if (k < 0 || k >= this->ThumbImages.size())
  {
    this->HoverLabel->hide();
    return;
  }
  // a larger preview of the hovered thumbnail, beside it
  const QRectF r = this->thumbRect(k);
  const double side = std::min(3 * r.width(), std::min(this->width(), this->height()) * 0.6);
  QRectF big(r.right() + 4, r.top(), side, side);
  if (big.right() > this->width())
    big.moveRight(r.left() - 4);
  if (big.bottom() > this->height())
    big.moveBottom(this->height());
  big.moveTop(std::max(0.0, big.top()));
  big.moveLeft(std::max(0.0, big.left()));
  this->HoverLabel->setPixmap(QPixmap::fromImage(this->ThumbImages[k]));
  this->HoverLabel->setGeometry(big.toRect());
  this->HoverLabel->show();
  this->HoverLabel->raise();
}

bool pqDDGOutlineView::eventFilter(QObject* object, QEvent* event)
{
  const int k = static_cast<int>(this->ThumbButtons.indexOf(static_cast<QToolButton*>(object)));
  if (k >= 0 && event->type() == QEvent::Enter)
    this->showHover(k);
  else if (k >= 0 && event->type() == QEvent::Leave)
    this->showHover(-1);
  return QWidget::eventFilter(object, event);
}

void pqDDGOutlineView::resizeEvent(QResizeEvent* e)
{
  QWidget::resizeEvent(e);
  this->Marks->setGeometry(this->rect());
  this->placeThumbnails();
}

void pqDDGOutlineView::setBox(const QRectF& box)
{
  this->Box = box.normalized();
  this->placeThumbnails();
  this->update();
}

void pqDDGOutlineView::setQuery(bool shown, const QPointF& position, const QVector<int>& neighbours)
{
  this->QueryShown = shown;
  this->QueryPosition = position;
  this->Neighbours = neighbours;
  this->update();
}

void pqDDGOutlineView::setSelection(int row, const QPointF& position)
{
  this->Selected = row;
  this->SelectedPosition = position;
  this->SelectedShown = true;
  for (int k = 0; k < this->ThumbButtons.size(); ++k)
    this->ThumbButtons[k]->setChecked(this->ThumbRows.value(k) == row);
  this->update();
}

void pqDDGOutlineView::setMessage(const QString& message)
{
  this->Message = message;
  this->update();
}

QPointF pqDDGOutlineView::toScreen(const QPointF& p) const
{
  const double w = this->width() - 2 * kMargin, h = this->height() - 2 * kMargin;
  return { kMargin + (p.x() - this->Box.left()) / this->Box.width() * w,
    kMargin + (this->Box.bottom() - p.y()) / this->Box.height() * h };
}

QPointF pqDDGOutlineView::toPlane(const QPointF& s) const
{
  const double w = this->width() - 2 * kMargin, h = this->height() - 2 * kMargin;
  return { this->Box.left() + (s.x() - kMargin) / w * this->Box.width(),
    this->Box.bottom() - (s.y() - kMargin) / h * this->Box.height() };
}

QRectF pqDDGOutlineView::thumbRect(int k) const
{
  const int row = this->ThumbRows[k];
  if (row < 0 || row >= this->Points.size())
    return {};
  const double side = std::clamp(std::min(this->width(), this->height()) / 6.0, 32.0, 96.0);
  QPointF c = this->toScreen(this->Points[row]);
  c.setX(std::clamp(c.x(), side / 2, this->width() - side / 2));
  c.setY(std::clamp(c.y(), side / 2, this->height() - side / 2));
  return { c.x() - side / 2, c.y() - side / 2, side, side };
}

int pqDDGOutlineView::nearestRow(const QPointF& s) const
{
  int best = -1;
  double bestD = 12.0 * 12.0; // pixels
  for (int i = 0; i < this->Points.size(); ++i)
  {
    const QPointF d = this->toScreen(this->Points[i]) - s;
    const double dd = d.x() * d.x() + d.y() * d.y();
    if (dd < bestD)
    {
      bestD = dd;
      best = i;
    }
  }
  return best;
}

void pqDDGOutlineView::paintEvent(QPaintEvent*)
{
  QPainter p(this);
  p.fillRect(this->rect(), Qt::white);
  if (this->Points.isEmpty())
  {
    p.setPen(Qt::darkGray);
    p.drawText(this->rect().adjusted(8, 8, -8, -8), Qt::AlignCenter | Qt::TextWordWrap,
      this->Message.isEmpty() ? tr("No design space loaded.") : this->Message);
    return;
  }
  p.setPen(QPen(QColor(150, 150, 150), 1.5));
  QVector<QPointF> dots;
  dots.reserve(this->Points.size());
  const QRectF area = this->rect();
  for (const auto& q : this->Points)
  {
    const QPointF s = this->toScreen(q);
    if (area.contains(s))
      dots.push_back(s);
  }
  p.drawPoints(dots.data(), static_cast<int>(dots.size()));
} // Marks, a child over the whole view, is repainted with it

void pqDDGOutlineView::paintMarks(QPainter& p) const
{
  if (this->Points.isEmpty())
    return;
  p.setRenderHint(QPainter::Antialiasing);
  p.setBrush(Qt::NoBrush);
  if (this->QueryShown) // the query's nearest designs (by the bundle's query key when it has one)
  {                     // can lie far from its mark on this plane: a line ties each to it
    p.setPen(QPen(QColor(0, 120, 255, 140), 1, Qt::DashLine));
    const QPointF q = this->toScreen(this->QueryPosition);
    for (int row : this->Neighbours)
      if (row >= 0 && row < this->Points.size())
        p.drawLine(q, this->toScreen(this->Points[row]));
  }
  p.setPen(QPen(QColor(0, 120, 255), 2));
  for (int row : this->Neighbours)
    if (row >= 0 && row < this->Points.size())
      p.drawEllipse(this->toScreen(this->Points[row]), 5, 5);
  if (this->QueryShown)
  {
    const QPointF q = this->toScreen(this->QueryPosition);
    p.setPen(QPen(QColor(220, 0, 0), 3));
    p.drawLine(q - QPointF(8, 8), q + QPointF(8, 8));
    p.drawLine(q - QPointF(8, -8), q + QPointF(8, -8));
  }
  if (this->SelectedShown)
  {
    const QPointF s = this->toScreen(this->Selected >= 0 && this->Selected < this->Points.size()
        ? this->Points[this->Selected]
        : this->SelectedPosition);
    p.setPen(QPen(QColor(255, 140, 0), 3));
    p.drawEllipse(s, 7, 7);
  }
  if (this->Banding)
  {
    p.setPen(QPen(QColor(0, 0, 0), 1, Qt::DashLine));
    p.setBrush(QColor(0, 120, 255, 40));
    p.drawRect(this->Band);
  }
}

void pqDDGOutlineView::wheelEvent(QWheelEvent* e)
{
  if (this->Points.isEmpty())
    return;
  const double factor = std::pow(1.0015, e->angleDelta().y()); // > 1 zooms in
  const QPointF c = this->toPlane(e->position());
  const double w = this->Box.width() / factor, h = this->Box.height() / factor;
  const double fx = (c.x() - this->Box.left()) / this->Box.width();
  const double fy = (c.y() - this->Box.top()) / this->Box.height();
  this->Box = QRectF(c.x() - fx * w, c.y() - fy * h, w, h);
  this->placeThumbnails();
  this->update();
  Q_EMIT this->boxChanged(this->Box);
}

void pqDDGOutlineView::mousePressEvent(QMouseEvent* e)
{
  this->PressAt = this->LastAt = e->pos();
  this->Moved = false;
  const bool band = e->button() == Qt::RightButton ||
    (e->button() == Qt::LeftButton && (e->modifiers() & Qt::ShiftModifier));
  this->Banding = band;
  this->Panning = !band && e->button() == Qt::LeftButton;
  this->Band = QRectF(this->PressAt, QSizeF());
}

void pqDDGOutlineView::mouseMoveEvent(QMouseEvent* e)
{
  const QPointF at = e->pos();
  if ((at - this->PressAt).manhattanLength() > 4)
    this->Moved = true;
  if (this->Banding)
  {
    this->Band = QRectF(this->PressAt, at).normalized();
    this->update();
  }
  else if (this->Panning && this->Moved)
  {
    const QPointF d = this->toPlane(this->LastAt) - this->toPlane(at);
    this->Box.translate(d);
    this->placeThumbnails();
    this->update();
  }
  this->LastAt = at;
}

void pqDDGOutlineView::mouseReleaseEvent(QMouseEvent* e)
{
  if (this->Banding)
  {
    this->Banding = false;
    this->update();
    if (this->Band.width() > 6 && this->Band.height() > 6)
    {
      const QPointF a = this->toPlane(this->Band.topLeft()),
                    b = this->toPlane(this->Band.bottomRight());
      Q_EMIT this->drillIn(QRectF(a, b).normalized());
    }
    return;
  }
  if (this->Panning && this->Moved)
  {
    this->Panning = false;
    Q_EMIT this->boxChanged(this->Box);
    return;
  }
  this->Panning = false;
  const int row = this->nearestRow(e->pos());
  if (row >= 0)
    Q_EMIT this->rowClicked(row);
}

void pqDDGOutlineView::leaveEvent(QEvent*)
{
  this->showHover(-1);
}
