// MatchCamera.cxx: a camera moved as ParaView's mouse and vtkCamera move it, from a base view
// (Match.h's cameraMove): the picture match's camera search and its results are stated so.
#include "Reconstruct/Match.h"

#include <Eigen/Geometry>

#include <cmath>

namespace ddg
{

View cameraMove(const View& base, double azimuth, double elevation, double roll, double zoom,
  std::array<double, 2> pan)
{
  // orbit about the focal point (ViewEstimation's orbitView), inlined to stay self-contained
  View v = base;
  const Eigen::Vector3d up0 = base.camera.viewUp.normalized();
  Eigen::Vector3d offset = base.camera.position - base.camera.focalPoint;
  offset = Eigen::AngleAxisd(azimuth * M_PI / 180.0, up0) * offset;
  const Eigen::Vector3d right0 = (-offset).normalized().cross(up0).normalized();
  offset = Eigen::AngleAxisd(-elevation * M_PI / 180.0, right0) * offset;
  const Eigen::Vector3d forward = (-offset).normalized();
  Eigen::Vector3d up = forward.cross(up0).cross(forward).normalized();
  // vtkCamera::Roll: view up rotated about the direction of projection
  up = Eigen::AngleAxisd(roll * M_PI / 180.0, forward) * up;
  const double distance = offset.norm() / zoom;
  v.camera.parallelScale = base.camera.parallelScale / zoom;
  const double height = v.camera.parallelProjection
    ? 2.0 * v.camera.parallelScale
    : 2.0 * distance * std::tan(v.camera.viewAngle * M_PI / 360.0);
  const Eigen::Vector3d right = forward.cross(up).normalized();
  const Eigen::Vector3d shift = (pan[0] * right + pan[1] * up) * height;
  v.camera.focalPoint = base.camera.focalPoint + shift;
  v.camera.position = v.camera.focalPoint - forward * distance;
  v.camera.viewUp = up;
  return v;
}

} // namespace ddg
