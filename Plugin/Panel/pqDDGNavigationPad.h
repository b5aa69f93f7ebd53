// pqDDGNavigationPad.h: moving between 2-4 pinned designs: a track (two: u) or a pad (three:
// the barycentric triangle, four: the bilinear square) with the anchors at its corners.
#pragma once

#include <QImage>
#include <QVector>
#include <QWidget>

class pqDDGNavigationPad : public QWidget
{
  Q_OBJECT

public:
  explicit pqDDGNavigationPad(QWidget* parent = nullptr);
  /// The anchors' icons (2-4; fewer disables the pad). Resets (u, v) to the first anchor.
  void setAnchors(const QVector<QImage>& icons);
  int anchors() const { return static_cast<int>(Icons.size()); }
  double u() const { return U; }
  double v() const { return V; }
  /// Moves the handle (clamped to the triangle with three anchors) and emits moved().
  void setPosition(double u, double v);

Q_SIGNALS:
  /// The handle moved to (u, v) (Core's blendLatents coordinates).
  void moved(double u, double v);

protected:
  void paintEvent(QPaintEvent*) override;
  void mousePressEvent(QMouseEvent*) override;
  void mouseMoveEvent(QMouseEvent*) override;

private:
  QRectF area() const;
  QPointF corner(int anchor) const;
  void moveTo(const QPointF& s);

  QVector<QImage> Icons;
  double U = 0, V = 0;
};
