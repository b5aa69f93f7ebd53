// vtkSMDDGScene.h: what the Design Gallery reads from and writes to a ParaView scene, on the
// client through proxies, once for the dock panel and the ddg Python package.
#pragma once

#include "DDGSceneModule.h" // export macro

#include <vtkObject.h>

#include <string>
#include <vector>

class vtkSMProxy;

/**
 * @class vtkSMDDGScene
 * @brief Static helpers over server-manager proxies, in the manner of
 * vtkSMTransferFunctionProxy's and vtkSMPVRepresentationProxy's static methods:
 *
 * - ViewJSON: a render view's camera as the DDG view JSON (README "File contracts").
 * - CheckVolume, VolumeProblem, VolumeArray: whether a source is a volume the Design Gallery
 *   works on, and which point array is the volume.
 * - DefaultModelDirectory: the shipped model bundle named like the volume's file.
 * - Apply1D, Apply2D, WriteTransferFunction2D, CurrentPreset: a design's transfer function
 *   written into (or read from) a representation's colour, opacity and 2D maps.
 * - SetCamera, SetLighting: a view JSON's camera and lighting written into a view and a
 *   representation; FitToView: a picture's camera for a view of another shape.
 * - DecodePicture, PictureFormat: a picture's pixels and format as the filters read them.
 *
 * No Qt and no undo stack: the panel wraps Apply1D/Apply2D in an undo set (and lets ParaView's
 * Color Map Editor react before writing the 2D boxes again); Python calls them as they are
 * (`from ddg_vtk import DDGScene; DDGScene.vtkSMDDGScene.ViewJSON(view.SMProxy, None, 256)`).
 * Errors are returned as text (an empty string: no error); the scene is then untouched, unless
 * said otherwise.
 */
class DDGSCENE_EXPORT vtkSMDDGScene : public vtkObject
{
public:
  static vtkSMDDGScene* New();
  vtkTypeMacro(vtkSMDDGScene, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The DDG view JSON (compact text) of render view `view`'s camera: "camera" (position,
   * focal_point, view_up, view_angle, parallel_projection, parallel_scale as ParaView states them
   * after SynchronizeCameraProperties), "size" (the view's ViewSize scaled so that its longer
   * side is at most `maxSide` pixels, never enlarged; `maxSide` <= 0: as it is), "background"
   * (the colour ParaView draws: the colour palette's Background when the view's
   * UseColorPaletteForBackground is on, as it is for a new view, else the view's Background) and,
   * when `representationOrSource` is a representation with a ScalarOpacityUnitDistance (or a source
   * shown in `view`), "opacity_unit_distance" and, with Shade on, "lighting" (Shade, Ambient,
   * Diffuse, Specular, SpecularPower). When `representationOrSource` is a source and `view` shows
   * nothing (no visible representation: pvpython's view after OpenDataFile, whose camera has
   * never looked at the data), the camera is ParaView's Reset Camera on the source's bounds at
   * the view's shape (Core's resetCameraView), as ParaView shows the source once it is shown.
   * Empty when `view` is not a render view.
   */
  static std::string ViewJSON(vtkSMProxy* view, vtkSMProxy* representationOrSource, int maxSide);

  /**
   * Sets render view `view`'s camera from a DDG view JSON's "camera" (position, focal_point,
   * view_up, view_angle, parallel_projection, parallel_scale; defaults as the view contract's)
   * through its properties (so that it is recorded on an open undo set) and pushes them, as it
   * is stated (a screenshot saved at the JSON's size then shows what the JSON's picture shows;
   * FitToView first for all of it in the view's own shape). The size and background of the JSON
   * are not used. Returns an empty string, or the reason (not a
   * render view, a view JSON Core's parseView refuses: no camera, a degenerate one, a value of
   * the wrong type) and then changes nothing. `checkOnly`: only that check, nothing is set (to
   * refuse before writing anything else).
   */
  static std::string SetCamera(vtkSMProxy* view, const char* viewJSON, bool checkOnly = false);

  /**
   * A view JSON with a "size" (a picture's) made to show all it shows in render view `view`'s
   * shape: in a view narrower than that size the camera's view angle (and parallel scale) widened
   * so that the picture's width fills the view's (Core's cameraForShape), the size the view's; a
   * wider view keeps the camera (it shows more on the sides, as VTK does). What the panel's Apply
   * with "move the camera to the picture's" sets. The JSON as it is without a size, a camera or
   * a render view, or when it cannot be read (SetCamera then says why).
   */
  static std::string FitToView(vtkSMProxy* view, const char* viewJSON);

  /**
   * Sets representation `representation`'s lighting from a DDG view JSON's "lighting": Shade on
   * with its Ambient, Diffuse, Specular and SpecularPower (absent keys: ParaView's defaults 0, 1,
   * 0, 100) when "lighting" has "shade": true; Shade off (the coefficients left as they are)
   * when it is absent, empty or "shade": false. Through the representation's properties (so that
   * it is recorded on an open undo set). Returns an empty string, or the reason (no
   * representation with Shade, a view JSON Core's parseView refuses: unknown lighting keys,
   * coefficients out of ParaView's range) and then changes nothing. `checkOnly`: only that
   * check, nothing is set (to refuse before writing anything else).
   */
  static std::string SetLighting(
    vtkSMProxy* representation, const char* viewJSON, bool checkOnly = false);

  /// Result of CheckVolume.
  enum VolumeCheck
  {
    IS_VOLUME = 0,   ///< image data with a one-component point array
    NO_DATA = 1,     ///< no data information yet (the source was never updated) or no points
    NOT_A_VOLUME = 2 ///< anything else
  };

  /**
   * Whether output `port` (default 0) of `source` is a volume: image data (also uniform grid,
   * structured points) whose point array chosen by the volume rule has one component. The rule
   * (the one place it is written; VolumeArray names the array): the point array `representation`
   * is coloured by when it is given, visible and coloured by a point array of the data; else the
   * data's active point scalars; else, only without active scalars, the first one-component
   * point array. Judged from the data information (nothing is updated: update the source first).
   */
  static int CheckVolume(vtkSMProxy* source, vtkSMProxy* representation = nullptr, int port = 0);

  /**
   * A CheckVolume result in words, the predicate after the source's name: "has no data yet",
   * "is not a volume: the Design Gallery needs image data with a one-component point array (e.g.
   * a .vti, .raw or DICOM volume)", or "" for IS_VOLUME.
   */
  static std::string VolumeProblem(int check);

  /**
   * VolumeProblem of `source` (port `port`) with the detail when the array the rule chose has
   * more than one component: "is not a volume: its point array 'v' has 3 components (colour it
   * by, or make active, a one-component point array)". Empty for a volume.
   */
  static std::string VolumeProblemOf(
    vtkSMProxy* source, vtkSMProxy* representation = nullptr, int port = 0);

  /**
   * The point array of `source` (port `port`, default 0) that is the volume, by the rule of
   * CheckVolume (`representation` may be nullptr: the data's own scalars). Empty when CheckVolume
   * is not IS_VOLUME.
   */
  static std::string VolumeArray(
    vtkSMProxy* source, vtkSMProxy* representation = nullptr, int port = 0);

  /**
   * The shipped model bundle named like `source`'s file: `dataDirectory`/Models/<file name
   * without its last extension, lower case> (Data/Models/tooth for .../tooth.vti) when it holds
   * a bundle.json (checked on this machine); empty otherwise or without a FileName property.
   */
  static std::string DefaultModelDirectory(vtkSMProxy* source, const char* dataDirectory);

  /**
   * Writes a ParaView preset (`presetJSON`: a preset object, or a list whose first element is
   * one, with "RGBPoints" [x, r, g, b, ...], "Points" [x, alpha, midpoint, sharpness, ...] and
   * "ColorSpace" (default RGB)) into `representation`'s LookupTable and ScalarOpacityFunction:
   * UseTransfer2D off, the Volume representation, coloured by point array `array`, the LUT set
   * never to rescale itself (AutomaticRescaleRangeMode Never). The values are the data values of
   * the preset (no rescaling). A preset ParaView cannot draw is refused, nothing written: not 4
   * numbers a node, a ColorSpace ParaView does not know, or against Core's rules for a 1D TF
   * (finite, increasing x; colours, opacities, midpoints, sharpnesses in [0, 1]; a node at the
   * x of the one before replaces it, as ParaView's maps do). `checkOnly`: only that check.
   */
  static std::string Apply1D(
    vtkSMProxy* representation, const char* array, const char* presetJSON, bool checkOnly = false);

  /**
   * Writes a 2D design into `representation`'s TransferFunction2D: `boxesJSON` is the DDG
   * filters' "ParaViewTransferFunction2D" field ({"Boxes": 8 numbers per box, "Range": 4,
   * "OutputDimensions": 2}). UseTransfer2D on with the gradient magnitude as Y
   * (UseGradientForTransfer2D), the Volume representation coloured by `array`, the LUT never
   * rescaled, VolumeRenderingMode "Ray Cast Only" turned to "Smart" (the fixed-point mapper has
   * no 2D TFs), then WriteTransferFunction2D. `checkOnly`: only the boxes' check, nothing written.
   */
  static std::string Apply2D(
    vtkSMProxy* representation, const char* array, const char* boxesJSON, bool checkOnly = false);

  /**
   * Only the 2D part of Apply2D: UseGradientForTransfer2D, the rendering mode and the
   * TransferFunction2D's Range, OutputDimensions and Boxes. In the GUI the Color Map Editor sets
   * the TF's Range and OutputDimensions from its own histogram after UseTransfer2D changes (after
   * a render): call this again then.
   */
  static std::string WriteTransferFunction2D(vtkSMProxy* representation, const char* boxesJSON);

  /**
   * The other volumes an Apply to `representation` colouring by point array `array` would
   * recolour too: ParaView keeps one colour map per array name, shared by every representation
   * coloured by that array unless it has UseSeparateColorMap. Names (in the "sources" group) of the
   * other sources with a visible representation in any view that shares it, one per line, sorted;
   * empty when there are none or `representation` has its own map.
   */
  static std::string SharedColorMapUsers(vtkSMProxy* representation, const char* array);

  /**
   * Gives `representation` its own colour and opacity maps for point array `array` (ParaView's
   * "Use Separate Color Map"), started as copies of the shared ones, so that an Apply changes
   * this volume only. Returns an empty string or the reason.
   */
  static std::string UseSeparateColorMap(vtkSMProxy* representation, const char* array);

  /**
   * The RGBPoints, Points and ColorSpace of `representation`'s LookupTable and
   * ScalarOpacityFunction as a ParaView preset (JSON text, "Name": "before the design gallery"),
   * to restore them with Apply1D. Empty when it has no such maps.
   */
  static std::string CurrentPreset(vtkSMProxy* representation);

  /**
   * The "Name" of a preset exported to `path` (Core's exportName): "DDG <volume> <origin>
   * <stem> <date> <time>", unique per file so that ParaView imports every exported preset.
   * `volume`: the source's name or file (extension dropped); `origin`: what made the TF, or a
   * design history's last action ("pick" becomes "outline design", see DesignOrigin).
   */
  static std::string ExportName(const char* volume, const char* origin, const char* path);

  /// What a design history's last step `action` says of the design's origin ("pick": "outline
  /// design", "latent": "design", "axes": "edit", others as they are; Core's designOrigin).
  static std::string DesignOrigin(const char* action);

  /**
   * A picture's bytes as the filters read them (Core's decodeImage: PNG, JPEG, TIFF, BMP, GIF or
   * WebP by their first bytes; grey spread to red, green and blue, alpha dropped) as 8-bit RGB,
   * rows top first, `width` x `height`; empty (and 0 x 0) when they are none of those. For the
   * panel to draw a picture its Qt has no reader for (Debian's Qt 5 has no WebP plugin).
   */
  VTK_WRAPEXCLUDE static std::vector<unsigned char> DecodePicture(
    const std::string& bytes, int& width, int& height);

  /// The format DecodePicture (and the filters) read a picture's bytes as, told by its first
  /// bytes (Core's imageFormat): ".png", ".jpg", ".tif", ".bmp", ".gif" or ".webp"; empty for
  /// anything else. The first 16 bytes are enough.
  VTK_WRAPEXCLUDE static std::string PictureFormat(const std::string& firstBytes);

protected:
  vtkSMDDGScene() = default;
  ~vtkSMDDGScene() override = default;

private:
  vtkSMDDGScene(const vtkSMDDGScene&) = delete;
  void operator=(const vtkSMDDGScene&) = delete;
};
