// pqDDGOutlineView.h: the design-space outline of the Design Gallery panel: every outline design
// as a dot on the PCA plane, thumbnails of a spread-out sample, the query and its neighbours.
// Wheel zooms, drag pans, shift-drag (or right-drag) draws a box to drill into; thumbnails are
// buttons (hovering one shows it larger, clicking selects it); a click elsewhere selects the
// nearest dot.
#pragma once

#include <QImage>
#include <QPointF>
#include <QRectF>
#include <QVector>
#include <QWidget>

class QLabel;
class QPainter;
class QToolButton;

class pqDDGOutlineView : public QWidget
{
  Q_OBJECT

public:
  explicit pqDDGOutlineView(QWidget* parent = nullptr);

  /// The outline's points (plane coordinates), one per outline row.
  void setPoints(const QVector<QPointF>& points);
  /// Thumbnails: the outline row each shows and its image.
  void setThumbnails(const QVector<int>& rows, const QVector<QImage>& images);
  /// The box of the plane shown (x0, y0, x1, y1 as a rect with y up).
  void setBox(const QRectF& box);
  QRectF box() const { return Box; }
  /// The query's place and its neighbours' rows (empty: none).
  void setQuery(bool shown, const QPointF& position, const QVector<int>& neighbours);
  /// The selected row (-1: none) or a design off the outline at `position`.
  void setSelection(int row, const QPointF& position);
  /// Shown when there is nothing to draw.
  void setMessage(const QString& message);
  int thumbnailCount() const { return static_cast<int>(ThumbRows.size()); }
  /// Outline row of thumbnail k.
  int thumbnailRow(int k) const { return ThumbRows.value(k, -1); }

Q_SIGNALS:
  /// The user picked an outline row (a thumbnail or the nearest dot).
  void rowClicked(int row);
  /// The shown box changed by zoom or pan (ask for new thumbnails).
  void boxChanged(const QRectF& box);
  /// The user drew a box to drill into.
  void drillIn(const QRectF& box);

protected:
  void paintEvent(QPaintEvent*) override;
  void wheelEvent(QWheelEvent*) override;
  void mousePressEvent(QMouseEvent*) override;
  void mouseMoveEvent(QMouseEvent*) override;
  void mouseReleaseEvent(QMouseEvent*) override;
  void leaveEvent(QEvent*) override;
  void resizeEvent(QResizeEvent*) override;
  bool eventFilter(QObject* object, QEvent* event) override;

private:
  QPointF toScreen(const QPointF& p) const;
  QPointF toPlane(const QPointF& s) const;
  QRectF thumbRect(int k) const;
  int nearestRow(const QPointF& s) const;
  void placeThumbnails();
  void showHover(int k);
  /// The query's mark, its neighbours, the selection and the band: painted by Marks, a child
  /// above the thumbnails (they would hide a mark that lies under one), under the hover preview.
  void paintMarks(QPainter& p) const;
  friend class pqDDGOutlineMarks;

  QVector<QPointF> Points;
  QVector<int> ThumbRows;
  QVector<QImage> ThumbImages;
  /// One button per thumbnail ("thumb0", "thumb1", ...: clickable, focusable, testable).
  QVector<QToolButton*> ThumbButtons;
  QLabel* HoverLabel;
  QWidget* Marks;
  QRectF Box{ 0, 0, 1, 1 };
  bool QueryShown = false;
  QPointF QueryPosition;
  QVector<int> Neighbours;
  int Selected = -1;
  QPointF SelectedPosition;
  bool SelectedShown = false;
  QString Message;
  // interaction
  bool Panning = false, Banding = false, Moved = false;
  QPointF PressAt, LastAt;
  QRectF Band;
};
