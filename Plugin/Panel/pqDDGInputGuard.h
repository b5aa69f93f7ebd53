// pqDDGInputGuard.h: user input held back, but for the Cancel buttons, while a long filter run
// processes events (the Design Gallery panel's match and build).
#pragma once

#include <pqApplicationCore.h>
#include <pqProgressManager.h>

#include <QApplication>
#include <QEvent>
#include <QList>
#include <QObject>
#include <QWidget>

#include <initializer_list>

/// While a long filter run processes events (match, build): user input reaches only the given
/// Cancel buttons. pqProgressManager's own blocking lets "non-blockable" widgets through by the
/// receiver of the event, but a click first goes to the top-level QWindow, which it blocks, so
/// no button gets it; its blocking is lifted for the run and this filter blocks instead: input
/// to windows passes (they route it to the widget under the cursor), input to any widget but the
/// Cancel buttons, and shortcuts, are dropped (no re-entrant pipeline updates from the GUI).
class pqDDGInputGuard : public QObject
{
public:
  pqDDGInputGuard(std::initializer_list<QWidget*> allowed)
    : Allowed(allowed)
  {
    auto* progress = pqApplicationCore::instance()->getProgressManager();
    this->WasUnblocked = progress->unblockEvents(true);
    QApplication::instance()->installEventFilter(this);
  }
  ~pqDDGInputGuard() override
  {
    QApplication::instance()->removeEventFilter(this);
    pqApplicationCore::instance()->getProgressManager()->unblockEvents(this->WasUnblocked);
  }

protected:
  bool eventFilter(QObject* receiver, QEvent* event) override
  {
    switch (event->type())
    {
      case QEvent::MouseButtonPress:
      case QEvent::MouseButtonRelease:
      case QEvent::MouseButtonDblClick:
      case QEvent::KeyPress:
      case QEvent::KeyRelease:
      case QEvent::Wheel:
      case QEvent::Shortcut:
      case QEvent::ShortcutOverride:
      case QEvent::Drop:
        if (receiver->isWindowType() && event->type() != QEvent::Shortcut &&
          event->type() != QEvent::ShortcutOverride)
          return false;
        for (QWidget* w : this->Allowed)
          if (receiver == w)
            return false;
        return true;
      default:
        return false;
    }
  }

private:
  QList<QWidget*> Allowed;
  bool WasUnblocked = false;
};
