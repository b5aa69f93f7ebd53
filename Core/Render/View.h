// View.h: the view contract — camera exactly as ParaView states it, image size, background,
// opacity unit distance — and the rays it casts.
#pragma once

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>

namespace ddg
{

class Volume;

/// A camera in ParaView's terms (vtkCamera): world coordinates of the volume.
struct Camera
{
  Eigen::Vector3d position{ 0, 0, 1 };
  Eigen::Vector3d focalPoint{ 0, 0, 0 };
  Eigen::Vector3d viewUp{ 0, 1, 0 };
  double viewAngle = 30.0; ///< vertical full angle in degrees (perspective)
  bool parallelProjection = false;
  double parallelScale = 1.0; ///< half the viewport height in world units (parallel)
};

/// ParaView's volume lighting: the Volume representation's Shade, Ambient, Diffuse, Specular and
/// SpecularPower, lit by the render view's default light kit (which follows the camera).
/// Defaults are ParaView 5.11's: Shade off, Ambient 0, Diffuse 1, Specular 0, SpecularPower 100.
struct Lighting
{
  bool shade = false;
  double ambient = 0.0;
  double diffuse = 1.0;
  double specular = 0.0;
  double specularPower = 100.0;

  bool operator==(const Lighting& o) const
  {
    return shade == o.shade && ambient == o.ambient && diffuse == o.diffuse &&
      specular == o.specular && specularPower == o.specularPower;
  }
  bool operator!=(const Lighting& o) const { return !(*this == o); }
  /// Throws ddg::Error for a coefficient outside ParaView's range (ambient, diffuse, specular in
  /// [0, 1], specular_power in [0, 100]).
  void validate() const;
};

/// A view JSON's "lighting" object (JSON text): every key optional (ParaView's default), no other
/// key; range-checked. Throws ddg::Error naming `origin`. parseView reads "lighting" with it.
Lighting parseLighting(const std::string& jsonText, const std::string& origin = "lighting");
/// The "lighting" object of a view JSON, as viewToJson writes it (compact JSON text).
std::string lightingToJson(const Lighting& lighting);
/// The lighting of a view JSON (text) whose other keys are not read (a camera need not be there:
/// the carried look takes only a view's lighting); no "lighting": unlit. Throws ddg::Error naming
/// `origin` for text that is not a JSON object or a "lighting" parseLighting refuses.
Lighting viewLighting(const std::string& viewJsonText, const std::string& origin = "view");

/// What to render and how: the view JSON
///   { "camera": { "position": [x,y,z], "focal_point": [x,y,z], "view_up": [x,y,z],
///                 "view_angle": 30, "parallel_projection": false, "parallel_scale": 1 },
///     "size": [width, height], "background": [r, g, b],
///     "background2": [r, g, b],             (optional: ParaView's gradient background)
///     "opacity_unit_distance": d,           (optional: ParaView's default for the volume)
///     "lighting": { "shade": true, "ambient": 0, "diffuse": 1, "specular": 0,
///                   "specular_power": 100 } }   (optional, each key optional: ParaView's)
/// Defaults: view_angle 30, parallel_projection false, parallel_scale 1, size [512, 512],
/// background [0.329, 0.349, 0.427] (pvpython's). position, focal_point, view_up are required.
struct View
{
  Camera camera;
  int width = 512;
  int height = 512;
  std::array<double, 3> background{ 0.329, 0.349, 0.427 };
  /// ParaView's gradient background (the view's Background2): the colour of the top row, with
  /// `background` that of the bottom row, linear in between. Unset: one colour.
  std::optional<std::array<double, 3>> background2;
  std::optional<double> opacityUnitDistance;
  Lighting lighting;

  /// The background colour of image row `row` (0 = top row, as images are stored).
  std::array<double, 3> backgroundAt(int row) const;

  /// Throws ddg::Error for a degenerate camera (position == focal point, view_up parallel to
  /// the view direction or zero, view angle outside (0, 180), parallel scale <= 0, anything
  /// non-finite), an image size outside [1, 16384] per side or above 64 Mpixel, a background
  /// (or background2) outside [0, 1], an opacity unit distance <= 0, or lighting coefficients
  /// outside ParaView's ranges (ambient, diffuse, specular in [0, 1], specular power in [0, 100]).
  void validate() const;
};

/// Largest image side and pixel count accepted by View::validate.
constexpr int kMaxImageSide = 16384;
constexpr long long kMaxImagePixels = 64LL * 1024 * 1024;

View parseView(const std::string& jsonText, const std::string& origin = "view");
View readView(const std::string& path);
std::string viewToJson(const View& view);
void writeView(const View& view, const std::string& path);

/// The camera ParaView's "Reset Camera" gives when looking down -z with +y up at a volume
/// (vtkRenderer::ResetCamera: distance = radius / sin(view_angle / 2), radius = half diagonal).
View defaultView(const Volume& volume, int width = 512, int height = 512);
/// The same for a volume's bounds (xmin, xmax, ymin, ...): a whole volume split into pieces.
View defaultView(const std::array<double, 6>& bounds, int width, int height);
/// ParaView's Reset Camera in a view of any shape: defaultView's, and in a view taller than wide
/// (vtkRenderer::ResetCamera's vertical window) the distance that fits the horizontal angle,
/// 2 atan(tan(view_angle / 2) width / height), and a parallel scale of radius height / width.
/// (defaultView, which the match and the carried look start from, keeps the vertical angle.)
View resetCameraView(const std::array<double, 6>& bounds, int width, int height);
/// `view`'s camera for a render view of `width` x `height` that shows all `view` shows: in a view
/// narrower than `view` (width / height under its) the view angle (perspective) or the parallel
/// scale is widened so that `view`'s width fills the view's; otherwise the camera as it is (VTK's
/// vertical angle: a wider view shows more on the sides). How a picture's camera is put into a
/// render view of another shape (vtkSMDDGScene::FitToView, the panel's Apply).
Camera cameraForShape(const View& view, int width, int height);

/// ParaView's sample distance for a volume of `dims` points at `spacing`: mean spacing / 2, times
/// 0.01 + 0.99 n / 100 when n = ((nx-1)(ny-1)(nz-1))^0.333 < 100.
double defaultSampleDistance(const std::array<double, 3>& spacing, const std::array<int, 3>& dims);

/// Orthonormal camera frame and projection of a View, to generate one ray per pixel centre.
/// Pixel (x, y) has x to the right and y DOWN from the top row (image order); ParaView's
/// window coordinates count rows from the bottom.
class RayGenerator
{
public:
  explicit RayGenerator(const View& view);
  /// Origin and unit direction of the ray through the centre of pixel (x, y).
  void ray(int x, int y, Eigen::Vector3d& origin, Eigen::Vector3d& direction) const;

  const Eigen::Vector3d& forward() const { return Forward; }
  const Eigen::Vector3d& right() const { return Right; }
  const Eigen::Vector3d& up() const { return Up; }

private:
  View V;
  Eigen::Vector3d Forward, Right, Up;
  double HalfHeight = 1; ///< tan(angle/2) (perspective) or parallel scale
  double Aspect = 1;
};

} // namespace ddg
