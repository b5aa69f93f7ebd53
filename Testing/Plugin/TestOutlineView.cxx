// TestOutlineView.cxx: the Design Gallery panel's outline widget (pqDDGOutlineView) on its own,
// under Qt's offscreen platform: the query's mark is painted above a thumbnail that covers it,
// a dashed line ties each nearest design to the mark, and the marks do not take the thumbnails'
// clicks (a click on a thumbnail still picks its row).
#include "pqDDGOutlineView.h"

#include <QApplication>
#include <QImage>
#include <QTest>
#include <QToolButton>

#include <iostream>

namespace
{
int Failures = 0;

void check(bool ok, const std::string& what)
{
  std::cout << (ok ? "ok   " : "FAIL ") << what << std::endl;
  if (!ok)
    ++Failures;
}

bool isQueryRed(QRgb c)
{
  return qRed(c) > 180 && qGreen(c) < 60 && qBlue(c) < 60;
}

bool isNeighbourBlue(QRgb c)
{
  return qBlue(c) > 150 && qBlue(c) - qRed(c) > 40; // over white or the grey dots
}
} // namespace

int main(int argc, char** argv)
{
  qputenv("QT_QPA_PLATFORM", "offscreen");
  QApplication app(argc, argv);
  pqDDGOutlineView view;
  view.resize(400, 400);
  view.setBox(QRectF(0, 0, 1, 1));
  // row 3's thumbnail covers the query's mark, which lies off every dot; rows 1 and 2 are its
  // neighbours, far from it
  view.setPoints({ QPointF(0.5, 0.5), QPointF(0.1, 0.9), QPointF(0.9, 0.1), QPointF(0.2, 0.2) });
  QImage grey(64, 64, QImage::Format_RGB32);
  grey.fill(QColor(80, 80, 100));
  view.setThumbnails({ 3 }, { grey });
  view.setQuery(true, QPointF(0.25, 0.25), { 1, 2 });
  view.show();
  QApplication::processEvents();

  // the view's mapping: 6-pixel margins, y up
  auto screen = [](double x, double y) { return QPointF(6 + x * 388, 6 + (1 - y) * 388); };
  const QImage shot = view.grab().toImage();
  const QPoint mark = screen(0.25, 0.25).toPoint();
  int red = 0;
  for (int dy = -6; dy <= 6; ++dy)
    red += isQueryRed(shot.pixel(mark + QPoint(dy, dy))) ? 1 : 0;
  check(red >= 5,
    "the query's mark is drawn above the thumbnail that covers it (" + std::to_string(red) +
      " red pixels on its diagonal)");
  // the dashed line from the mark to neighbour 2 (far right): blue along its middle, well
  // outside the thumbnail and before the neighbour's circle
  int blue = 0;
  const QPointF from = screen(0.25, 0.25), to = screen(0.9, 0.1);
  for (int k = 0; k <= 40; ++k)
  {
    const QPoint q = (from + (0.3 + 0.4 * k / 40.0) * (to - from)).toPoint();
    bool found = false;
    for (int dy = -1; dy <= 1; ++dy)
      found = found || isNeighbourBlue(shot.pixel(q + QPoint(0, dy)));
    blue += found ? 1 : 0;
  }
  check(blue >= 8,
    "a dashed line ties the mark to a neighbour far from it (" + std::to_string(blue) +
      " blue points of 41)");

  int clicked = -1;
  QObject::connect(&view, &pqDDGOutlineView::rowClicked, [&](int row) { clicked = row; });
  auto* thumb = view.findChild<QToolButton*>("thumb0");
  check(thumb != nullptr, "the thumbnail is a button");
  if (thumb)
  {
    // a click on the window where the mark covers the thumbnail reaches the thumbnail (the view
    // itself, with no dot within 12 pixels, would pick nothing)
    QTest::mouseClick(view.windowHandle(), Qt::LeftButton, Qt::NoModifier, mark);
    QApplication::processEvents();
    check(clicked == 3,
      "a click on the mark over the thumbnail picks the thumbnail's row (got " +
        std::to_string(clicked) + ")");
  }
  return Failures == 0 ? 0 : 1;
}
