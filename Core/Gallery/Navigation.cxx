// Navigation.cxx: blends of anchor latents, navigation grids, eased paths.
#include "Gallery/Navigation.h"

#include "Common/Error.h"

#include <cmath>

namespace ddg
{

Latent blendLatents(const std::vector<Latent>& anchors, double u, double v)
{
  const size_t n = anchors.size();
  if (n < 2 || n > 4)
    throw Error(
      "a navigation sub-space is spanned by 2 to 4 designs (got " + std::to_string(n) + ")");
  if (!std::isfinite(u) || !std::isfinite(v))
    throw Error("navigation coordinates must be finite");
  for (const auto& a : anchors)
    if (a.size() != anchors[0].size() || a.empty())
      throw Error("the designs to navigate between have latents of different sizes");
  std::vector<double> w;
  if (n == 2)
    w = { 1 - u, u };
  else if (n == 3)
    w = { 1 - u - v, u, v };
  else
    w = { (1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v };
  Latent z(anchors[0].size(), 0.0f);
  for (size_t c = 0; c < z.size(); ++c)
  {
    double s = 0;
    for (size_t k = 0; k < n; ++k)
      s += w[k] * anchors[k][c];
    z[c] = static_cast<float>(s);
  }
  return z;
}

NavigationWindow NavigationWindow::zoomed(double factor, double cu, double cv) const
{
  if (!(factor > 0) || !std::isfinite(factor) || !std::isfinite(cu) || !std::isfinite(cv))
    throw Error("zoom needs a positive factor and a finite centre");
  return { cu + (u0 - cu) / factor, cv + (v0 - cv) / factor, cu + (u1 - cu) / factor,
    cv + (v1 - cv) / factor };
}

NavigationWindow NavigationWindow::panned(double du, double dv) const
{
  if (!std::isfinite(du) || !std::isfinite(dv))
    throw Error("pan needs finite offsets");
  return { u0 + du, v0 + dv, u1 + du, v1 + dv };
}

std::vector<NavigationCell> navigationGrid(
  const std::vector<Latent>& anchors, int rows, int cols, const NavigationWindow& w)
{
  if (rows < 1 || cols < 1 || rows > 64 || cols > 64)
    throw Error("a navigation grid has 1 to 64 rows and columns");
  if (!(w.u0 < w.u1) || !(w.v0 < w.v1) || !std::isfinite(w.u0) || !std::isfinite(w.u1) ||
    !std::isfinite(w.v0) || !std::isfinite(w.v1))
    throw Error("the navigation window must be finite with u0 < u1 and v0 < v1");
  blendLatents(anchors, 0, 0); // checks the anchors
  std::vector<NavigationCell> cells;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
    {
      NavigationCell cell;
      cell.u = cols == 1 ? 0.5 * (w.u0 + w.u1) : w.u0 + (w.u1 - w.u0) * c / (cols - 1);
      cell.v = rows == 1 ? 0.5 * (w.v0 + w.v1) : w.v0 + (w.v1 - w.v0) * r / (rows - 1);
      const bool outside =
        anchors.size() == 3 && (cell.u < -1e-9 || cell.v < -1e-9 || cell.u + cell.v > 1 + 1e-9);
      if (!outside)
        cell.latent = blendLatents(anchors, cell.u, cell.v);
      cells.push_back(std::move(cell));
    }
  return cells;
}

double ease(double t, const std::string& easing)
{
  if (easing == "linear")
    return t;
  if (easing == "smoothstep")
    return t * t * (3 - 2 * t);
  if (easing == "cosine")
    return 0.5 * (1 - std::cos(M_PI * t));
  throw Error("unknown easing '" + easing + "' (linear, smoothstep or cosine)");
}

std::vector<Latent> latentPath(
  const Latent& a, const Latent& b, int frames, const std::string& easing)
{
  if (frames < 2)
    throw Error("an animation needs at least 2 frames");
  std::vector<Latent> path;
  for (int f = 0; f < frames; ++f)
    path.push_back(blendLatents({ a, b }, ease(static_cast<double>(f) / (frames - 1), easing), 0));
  return path;
}

} // namespace ddg
