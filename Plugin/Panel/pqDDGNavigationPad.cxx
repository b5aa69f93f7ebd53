// pqDDGNavigationPad.cxx: painting and dragging of the navigation pad.
#include "pqDDGNavigationPad.h"

#include <QMouseEvent>
#include <QPainter>

#include <algorithm>

namespace
{
constexpr double kIcon = 36;
}

pqDDGNavigationPad::pqDDGNavigationPad(QWidget* parent)
  : QWidget(parent)
{
  this->setMinimumHeight(90);
  this->setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Preferred);
}

void pqDDGNavigationPad::setAnchors(const QVector<QImage>& icons)
{
  this->Icons = icons;
  this->U = this->V = 0;
  this->setMinimumHeight(icons.size() > 2 ? 180 : 90);
  this->setEnabled(icons.size() >= 2 && icons.size() <= 4);
  this->update();
}

QRectF pqDDGNavigationPad::area() const
{
  const double m = kIcon / 2 + 4;
  if (this->Icons.size() <= 2)
    return QRectF(m, this->height() / 2.0, this->width() - 2 * m, 0);
  return QRectF(m, m, this->width() - 2 * m, this->height() - 2 * m);
}

QPointF pqDDGNavigationPad::corner(int anchor) const
{
  // anchor k sits where blendLatents reproduces it: (0,0), (1,0), (0,1), (1,1); v grows upward
  const QRectF a = this->area();
  const double u = (anchor == 1 || anchor == 3) ? 1 : 0, v = anchor >= 2 ? 1 : 0;
  return { a.left() + u * a.width(), a.bottom() - v * a.height() };
}

void pqDDGNavigationPad::setPosition(double u, double v)
{
  u = std::clamp(u, 0.0, 1.0);
  v = this->Icons.size() > 2 ? std::clamp(v, 0.0, 1.0) : 0.0;
  if (this->Icons.size() == 3 && u + v > 1)
  {
    const double excess = (u + v - 1) / 2;
    u -= excess;
    v -= excess;
  }
  this->U = u;
  this->V = v;
  this->update();
  Q_EMIT this->moved(u, v);
}

void pqDDGNavigationPad::moveTo(const QPointF& s)
{
  const QRectF a = this->area();
  const double u = (s.x() - a.left()) / std::max(1.0, a.width());
  const double v = a.height() > 0 ? (a.bottom() - s.y()) / a.height() : 0.0;
  this->setPosition(u, v);
}

void pqDDGNavigationPad::paintEvent(QPaintEvent*)
{
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  p.fillRect(this->rect(), this->palette().base());
  if (this->Icons.size() < 2 || this->Icons.size() > 4)
  {
    p.setPen(Qt::darkGray);
    p.drawText(this->rect(), Qt::AlignCenter | Qt::TextWordWrap,
      tr("Pin 2 to 4 designs to move between them."));
    return;
  }
  p.setPen(QPen(Qt::gray, 2));
  if (this->Icons.size() == 2)
    p.drawLine(this->corner(0), this->corner(1));
  else if (this->Icons.size() == 3)
    p.drawPolygon(QPolygonF({ this->corner(0), this->corner(1), this->corner(2) }));
  else
    p.drawRect(this->area());
  for (int k = 0; k < this->Icons.size(); ++k)
  {
    const QPointF c = this->corner(k);
    const QRectF r(c.x() - kIcon / 2, c.y() - kIcon / 2, kIcon, kIcon);
    p.drawImage(r, this->Icons[k]);
    p.drawRect(r);
  }
  const QRectF a = this->area();
  const QPointF h(a.left() + this->U * a.width(), a.bottom() - this->V * a.height());
  p.setPen(QPen(QColor(255, 140, 0), 3));
  p.setBrush(Qt::white);
  p.drawEllipse(h, 7, 7);
}

void pqDDGNavigationPad::mousePressEvent(QMouseEvent* e)
{
  if (this->isEnabled())
    this->moveTo(e->pos());
}

void pqDDGNavigationPad::mouseMoveEvent(QMouseEvent* e)
{
  if (this->isEnabled() && (e->buttons() & Qt::LeftButton))
    this->moveTo(e->pos());
}
