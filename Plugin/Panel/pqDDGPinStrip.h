// pqDDGPinStrip.h: the "Pinned designs" box of the Design Gallery panel: the strip of pinned
// designs, the navigation pad between 2-4 of them (selected pins, or the first four) and the
// animation through all of them into PNG frames rendered by ParaView. The pins themselves are
// part of the panel's state (pqDDGDesignState).
#pragma once

#include <QGroupBox>
#include <QList>

#include <memory>

class pqDDGDesignState;
class QTimer;
namespace Ui
{
class pqDDGPinStrip;
}

class pqDDGPinStrip : public QGroupBox
{
  Q_OBJECT

public:
  explicit pqDDGPinStrip(QWidget* parent = nullptr);
  ~pqDDGPinStrip() override;

  /// The state whose pins this box shows and whose designs it moves between.
  void setState(pqDDGDesignState* state);

Q_SIGNALS:
  /// Animation progress in percent.
  void progress(int percent);

private Q_SLOTS:
  void addPin();
  void unpin();
  void clear();
  void updatePad();
  void navigate();
  void animate();

private:
  std::unique_ptr<Ui::pqDDGPinStrip> Ui;
  pqDDGDesignState* State = nullptr;
  QTimer* NavigateTimer;
  QList<int> Chosen; ///< the pins at the pad's corners
};
