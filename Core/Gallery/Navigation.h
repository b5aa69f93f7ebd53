// Navigation.h: moving between designs in latent space — the sub-space spanned by 2-4 chosen
// designs (a grid with pan and zoom inside it) and eased paths for animation (paper §1).
#pragma once

#include <string>
#include <vector>

namespace ddg
{

using Latent = std::vector<float>;

/// The latent at (u, v) of the sub-space spanned by 2-4 anchor latents (all the same size):
///   2 anchors: (1 - u) z0 + u z1 (v is ignored);
///   3 anchors: barycentric, (1 - u - v) z0 + u z1 + v z2 (inside the triangle when u, v >= 0
///              and u + v <= 1);
///   4 anchors: bilinear, (1-u)(1-v) z0 + u(1-v) z1 + (1-u) v z2 + u v z3.
/// (u, v) = the anchors' corners reproduce them exactly. Values outside [0, 1] extrapolate.
/// Throws ddg::Error for fewer than 2 or more than 4 anchors, mismatched sizes or non-finite u, v.
Latent blendLatents(const std::vector<Latent>& anchors, double u, double v);

/// The part of the (u, v) square shown (pan and zoom inside the sub-space), u0 < u1, v0 < v1.
struct NavigationWindow
{
  double u0 = 0, v0 = 0, u1 = 1, v1 = 1;
  /// Zoom about (cu, cv) by factor (> 1 zooms in), then pan by (du, dv). Throws for factor <= 0.
  NavigationWindow zoomed(double factor, double cu, double cv) const;
  NavigationWindow panned(double du, double dv) const;
};

/// One cell of a navigation grid: its (u, v) and latent (empty for a 3-anchor cell outside the
/// triangle, which is not a blend of the three).
struct NavigationCell
{
  double u = 0, v = 0;
  Latent latent;
};

/// rows x cols cells over the window, corners included (u = u0 + (u1 - u0) c / (cols - 1); a
/// single column or row sits at the window's centre), row-major, v growing with the row. With
/// 2 anchors rows should be 1 (v is ignored). Throws ddg::Error for rows or cols < 1 or above
/// 64, or an invalid window.
std::vector<NavigationCell> navigationGrid(
  const std::vector<Latent>& anchors, int rows, int cols, const NavigationWindow& window = {});

/// Easing of an animation: "linear" t, "smoothstep" 3t^2 - 2t^3, "cosine" (1 - cos(pi t)) / 2.
/// Throws ddg::Error for another name.
double ease(double t, const std::string& easing);

/// `frames` latents from a to b (frame 0 = a, the last = b) at eased times. frames >= 2.
std::vector<Latent> latentPath(
  const Latent& a, const Latent& b, int frames, const std::string& easing = "smoothstep");

} // namespace ddg
