// TestCameraRays.cxx: Core's per-pixel rays against VTK's own camera matrices.
//
// Compared: ddg::RayGenerator::ray(x, y) vs the ray VTK defines for the same pixel centre: the
// inverse of vtkCamera's composite projection (view + projection at the window aspect)
// applied to NDC points on the near and far planes, window rows counted from the bottom.
// Perspective and parallel cameras, non-orthogonal view up, non-square windows.
// Tolerance: 1e-9 on unit directions, 1e-7 relative on parallel ray origins (in the view plane).
#include "Render/View.h"

#include <vtkCamera.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>

#include <cmath>
#include <cstdio>

namespace
{
int failures = 0;
void check(bool ok, const char* what, double value)
{
  if (!ok)
  {
    std::printf("FAIL %s (%g)\n", what, value);
    ++failures;
  }
}
} // namespace

int main()
{
  struct Case
  {
    double pos[3], focal[3], up[3], angle;
    bool parallel;
    double scale;
    int w, h;
  };
  const Case cases[] = {
    { { 10, 20, 30 }, { 1, 2, 3 }, { 0, 1, 0.2 }, 30, false, 1, 400, 320 },
    { { -50, 5, 8 }, { 3, 4, 5 }, { 0.1, 0.3, 1 }, 47, false, 1, 128, 256 },
    { { 10, 20, 30 }, { 1, 2, 3 }, { 0, 1, 0.2 }, 30, true, 17.5, 300, 200 },
  };
  for (const Case& c : cases)
  {
    vtkNew<vtkCamera> cam;
    cam->SetPosition(c.pos);
    cam->SetFocalPoint(c.focal);
    cam->SetViewUp(c.up);
    cam->SetViewAngle(c.angle);
    cam->SetParallelProjection(c.parallel);
    cam->SetParallelScale(c.scale);
    cam->SetClippingRange(0.1, 1000);
    const double aspect = static_cast<double>(c.w) / c.h;
    vtkNew<vtkMatrix4x4> inv;
    inv->DeepCopy(cam->GetCompositeProjectionTransformMatrix(aspect, -1, 1));
    inv->Invert();

    ddg::View view;
    view.camera.position = { c.pos[0], c.pos[1], c.pos[2] };
    view.camera.focalPoint = { c.focal[0], c.focal[1], c.focal[2] };
    view.camera.viewUp = { c.up[0], c.up[1], c.up[2] };
    view.camera.viewAngle = c.angle;
    view.camera.parallelProjection = c.parallel;
    view.camera.parallelScale = c.scale;
    view.width = c.w;
    view.height = c.h;
    const ddg::RayGenerator rays(view);

    for (int y : { 0, c.h / 3, c.h - 1 })
    {
      for (int x : { 0, c.w / 2, c.w - 1 })
      {
        const int yUp = c.h - 1 - y; // VTK window rows go up
        const double ndc[2] = { 2.0 * (x + 0.5) / c.w - 1.0, 2.0 * (yUp + 0.5) / c.h - 1.0 };
        double pts[2][3];
        for (int p = 0; p < 2; ++p)
        {
          double in[4] = { ndc[0], ndc[1], p == 0 ? -1.0 : 1.0, 1.0 }, out[4];
          inv->MultiplyPoint(in, out);
          for (int a = 0; a < 3; ++a)
            pts[p][a] = out[a] / out[3];
        }
        Eigen::Vector3d vtkDir(pts[1][0] - pts[0][0], pts[1][1] - pts[0][1], pts[1][2] - pts[0][2]);
        vtkDir.normalize();
        Eigen::Vector3d o, d;
        rays.ray(x, y, o, d);
        check((d - vtkDir).norm() < 1e-9, "direction", (d - vtkDir).norm());
        if (c.parallel)
        {
          // Our origin lies on the ray VTK defines: distance of o from the VTK ray.
          const Eigen::Vector3d near(pts[0][0], pts[0][1], pts[0][2]);
          const double off = ((o - near) - (o - near).dot(vtkDir) * vtkDir).norm();
          check(off < 1e-7 * (1 + near.norm()), "parallel origin", off);
        }
      }
    }
  }
  std::printf(failures ? "%d failures\n" : "all rays match VTK's camera\n", failures);
  return failures ? 1 : 0;
}
