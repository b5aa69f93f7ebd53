// pqDDGScene.h: what the Design Gallery panel reads from and writes to the ParaView scene, on the
// client through proxies: the Qt side of vtkSMDDGScene (Plugin/Scene: the view JSON, writing a
// TF into a representation, shared with the ddg Python package) with ParaView's undo stack, and
// server-side helper filters with fetching their (small) results.
#pragma once

#include <QImage>
#include <QJsonArray>
#include <QJsonObject>
#include <QString>

#include <vtkSmartPointer.h>

class pqDataRepresentation;
class pqRenderView;
class vtkDataObject;
class vtkSMProxy;
class vtkSMSourceProxy;
class vtkTable;

namespace ddgpanel
{

/// The view JSON of the render view's camera, its background and the representation's Scalar
/// Opacity Unit Distance (when given), with the view's aspect and `maxSide` pixels on its longer
/// side (vtkSMDDGScene::ViewJSON); empty without a view.
QJsonObject viewJson(pqRenderView* view, pqDataRepresentation* repr, int maxSide);

/// The representation of `source` (port 0) in the active render view, shown there first when it
/// is not yet; nullptr without a render view or source.
pqDataRepresentation* representation(vtkSMSourceProxy* source);

/// Compact text of a JSON object.
QString jsonText(const QJsonObject& object);

/// Writes a ParaView preset (JSON text: a preset object or a list whose first element is one,
/// with "RGBPoints", "Points" and "ColorSpace") into the LookupTable and ScalarOpacityFunction
/// of `repr`, colouring it by its input's point scalars `array` and switching it to the Volume
/// representation; the LUT is set not to rescale itself and 2D rendering is turned off
/// (vtkSMDDGScene::Apply1D). Recorded on ParaView's undo stack as one step named `label` when
/// `undoable`. Returns an empty string or the reason it failed (the scene is then untouched).
QString applyPreset(pqDataRepresentation* repr, const QString& array, const QString& presetText,
  const QString& label, bool undoable = true);

/// Writes a 2D design into `repr`'s TransferFunction2D: `boxesText` is the filters'
/// "ParaViewTransferFunction2D" field ({"Boxes", "Range", "OutputDimensions"}). Switches the
/// representation to Volume coloured by `array`, turns UseTransfer2D on (gradient magnitude as
/// Y; "Ray Cast Only" becomes "Smart", the fixed-point mapper has no 2D TFs) and shows the boxes
/// in the Color Map Editor's 2D editor: vtkSMDDGScene::Apply2D, a render and the events the Color
/// Map Editor reacts with, then vtkSMDDGScene::WriteTransferFunction2D again. One undo step;
/// returns an empty string or the reason.
QString applyTransferFunction2D(pqDataRepresentation* repr, const QString& array,
  const QString& boxesText, const QString& label, bool undoable = true);

/// Sets `view`'s camera to the "camera" of a view JSON, fitted to the view's shape so that all the
/// picture shows is seen (vtkSMDDGScene::FitToView, then SetCamera). ParaView's undo
/// stack does not record camera changes: with `undoable`, an element that sets the camera back
/// (and forth on Redo) is added to the undo set open now (BEGIN_UNDO_SET), so the camera moves
/// with the rest of that step. Returns an empty string or the reason (nothing changed then).
QString setCamera(pqRenderView* view, const QJsonObject& viewJson, bool undoable);

/// The current RGBPoints and opacity Points of `repr`'s maps as a preset text (to restore them).
QString currentPreset(pqDataRepresentation* repr);

/// A new, unregistered server-side filter `name` of the "filters" group on `input`'s port, in
/// `input`'s session.
vtkSmartPointer<vtkSMSourceProxy> newFilter(const char* name, vtkSMSourceProxy* input, int port);

/// While it lives, changes to proxies stay off ParaView's undo stack. The panel's own proxies
/// (its filters, data movers) are not the user's scene, but ParaView records any proxy's change
/// outside an undo set as a step of its own ("Changed 'vtkSMProxy'"), which would then stand
/// between an Apply and the user's Undo (e.g. thumbnails redrawn after Apply changed Shade).
class NoUndo
{
public:
  NoUndo();
  ~NoUndo();
  NoUndo(const NoUndo&) = delete;
  NoUndo& operator=(const NoUndo&) = delete;

private:
  bool Was = false;
};

/// Fetches output `port` of `producer` (already updated) from the first process: a copy on the
/// client (nullptr when it is empty).
vtkSmartPointer<vtkDataObject> fetch(vtkSMSourceProxy* producer, int port);

/// The filter's LastError information property (empty when it has none).
QString lastError(vtkSMProxy* filter);

/// The "Image" array (RGB over the background) of a filter's image output as a QImage (null
/// when there is none).
QImage imageOf(vtkDataObject* data);

/// The first `count` cells of a thumbnail sheet (DDG Design Gallery's, DDG Query's strip: cells
/// of side x side, row by row, 2 pixels between and around them; the columns are what the
/// sheet's width holds), fewer when the sheet holds fewer or is null.
QVector<QImage> sheetCells(const QImage& sheet, int count, int side);

/// The numbers of field array `name` of a filter's table output (empty when it has none).
QJsonArray fieldNumbers(vtkTable* table, const char* name);

/// The first value of string field array `name` of a filter's table output (empty if none).
QString fieldText(vtkTable* table, const char* name);

} // namespace ddgpanel
