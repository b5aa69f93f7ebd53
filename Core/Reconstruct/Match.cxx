// Match.cxx: background, masks, silhouette camera search, then the reconstruction (Match.h).
#include "Reconstruct/Match.h"

#include "Common/Error.h"
#include "Render/RayCaster.h"
#include "Volume/Volume.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <sstream>

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

void PictureBackground::applyTo(View& view) const
{
  view.background = bottom;
  if (gradient)
    view.background2 = top;
  else
    view.background2.reset();
}

namespace
{

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t)
{
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// --- small raster helpers ----------------------------------------------------------------

// A binary raster (row 0 at the top).
struct Mask
{
  int w = 0, h = 0;
  std::vector<std::uint8_t> m;
  Mask() = default;
  Mask(int width, int height)
    : w(width)
    , h(height)
    , m(static_cast<size_t>(width) * height, 0)
  {
  }
  std::uint8_t operator()(int x, int y) const { return m[static_cast<size_t>(y) * w + x]; }
  std::uint8_t& operator()(int x, int y) { return m[static_cast<size_t>(y) * w + x]; }
};

Image toImage(const Mask& mask)
{
  Image img(mask.w, mask.h, 1);
  for (size_t i = 0; i < mask.m.size(); ++i)
    img.pixels[i] = mask.m[i] ? 1.0f : 0.0f;
  return img;
}

// Dilation by a (2r+1)^2 box (separable).
Mask dilate(const Mask& in, int r)
{
  if (r <= 0)
    return in;
  Mask tmp(in.w, in.h), out(in.w, in.h);
  for (int y = 0; y < in.h; ++y)
  {
    int last = -1000000; // x of the last set pixel seen, sweeping right then left
    for (int x = 0; x < in.w; ++x)
    {
      if (in(x, y))
        last = x;
      tmp(x, y) = x - last <= r;
    }
    last = 1000000;
    for (int x = in.w - 1; x >= 0; --x)
    {
      if (in(x, y))
        last = x;
      tmp(x, y) = tmp(x, y) || last - x <= r;
    }
  }
  for (int x = 0; x < in.w; ++x)
  {
    int last = -1000000;
    for (int y = 0; y < in.h; ++y)
    {
      if (tmp(x, y))
        last = y;
      out(x, y) = y - last <= r;
    }
    last = 1000000;
    for (int y = in.h - 1; y >= 0; --y)
    {
      if (tmp(x, y))
        last = y;
      out(x, y) = out(x, y) || last - y <= r;
    }
  }
  return out;
}

// Downsampling of a mask: a coarse pixel is set when at least half of its area is.
Mask shrink(const Mask& in, int w, int h)
{
  Mask out(w, h);
  for (int y = 0; y < h; ++y)
  {
    const int y0 = y * in.h / h, y1 = std::max(y0 + 1, (y + 1) * in.h / h);
    for (int x = 0; x < w; ++x)
    {
      const int x0 = x * in.w / w, x1 = std::max(x0 + 1, (x + 1) * in.w / w);
      int count = 0;
      for (int yy = y0; yy < y1; ++yy)
        for (int xx = x0; xx < x1; ++xx)
          count += in(xx, yy);
      out(x, y) = 2 * count >= (y1 - y0) * (x1 - x0);
    }
  }
  return out;
}

// The mask with every unset region that does not reach the border set (4-neighbourhood).
Mask fillHoles(const Mask& in)
{
  Mask outside(in.w, in.h);
  std::vector<int> stack;
  auto seed = [&](int x, int y)
  {
    if (!in(x, y) && !outside(x, y))
    {
      outside(x, y) = 1;
      stack.push_back(y * in.w + x);
    }
  };
  for (int x = 0; x < in.w; ++x)
    seed(x, 0), seed(x, in.h - 1);
  for (int y = 0; y < in.h; ++y)
    seed(0, y), seed(in.w - 1, y);
  while (!stack.empty())
  {
    const int p = stack.back();
    stack.pop_back();
    const int x = p % in.w, y = p / in.w;
    if (x > 0)
      seed(x - 1, y);
    if (x + 1 < in.w)
      seed(x + 1, y);
    if (y > 0)
      seed(x, y - 1);
    if (y + 1 < in.h)
      seed(x, y + 1);
  }
  Mask out(in.w, in.h);
  for (size_t i = 0; i < out.m.size(); ++i)
    out.m[i] = !outside.m[i];
  return out;
}

// Connected parts (8-neighbourhood) of a mask: label per pixel (-1 = unset) and areas.
std::vector<int> components(const Mask& mask, std::vector<int>& area)
{
  std::vector<int> label(mask.m.size(), -1);
  area.clear();
  std::vector<int> stack;
  for (int start = 0; start < static_cast<int>(mask.m.size()); ++start)
  {
    if (!mask.m[start] || label[start] >= 0)
      continue;
    const int id = static_cast<int>(area.size());
    area.push_back(0);
    label[start] = id;
    stack.push_back(start);
    while (!stack.empty())
    {
      const int p = stack.back();
      stack.pop_back();
      ++area[id];
      const int px = p % mask.w, py = p / mask.w;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
        {
          const int qx = px + dx, qy = py + dy;
          if (qx < 0 || qy < 0 || qx >= mask.w || qy >= mask.h)
            continue;
          const int q = qy * mask.w + qx;
          if (mask.m[q] && label[q] < 0)
          {
            label[q] = id;
            stack.push_back(q);
          }
        }
    }
  }
  return label;
}

double median(std::vector<double> v)
{
  if (v.empty())
    return 0;
  const size_t k = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// --- silhouettes of the volume -------------------------------------------------------------

// The volume as blocks: per occupancy level (a value threshold), the centres of the occupied
// blocks on the surface of the occupied set; their projections (discs) make the silhouette of
// "opaque above the threshold" at any camera, far faster than ray casting.
class SilhouetteModel
{
public:
  explicit SilhouetteModel(const Volume& vol)
  {
    const auto& d = vol.dims();
    const int longest = std::max({ d[0], d[1], d[2] });
    const int bs = std::max(1, (longest + 63) / 64); // at most ~64 blocks a side
    int nb[3];
    for (int k = 0; k < 3; ++k)
      nb[k] = std::max(1, (d[k] - 1 + bs - 1) / bs);
    std::vector<float> blockMax(static_cast<size_t>(nb[0]) * nb[1] * nb[2], -1e30f);
    // a block covers the points b bs .. (b + 1) bs (inclusive): a point on a block's lower face
    // belongs to the block below as well
    auto blocksOf = [&](int i, int n)
    {
      const int hi = std::min(n - 1, i / bs);
      const int lo = (i % bs == 0 && i > 0) ? std::min(hi, i / bs - 1) : hi;
      return std::pair<int, int>(lo, hi);
    };
    for (int k = 0; k < d[2]; ++k)
    {
      const auto [bk0, bk1] = blocksOf(k, nb[2]);
      for (int j = 0; j < d[1]; ++j)
      {
        const auto [bj0, bj1] = blocksOf(j, nb[1]);
        for (int i = 0; i < d[0]; ++i)
        {
          const float v = vol.at(i, j, k);
          const auto [bi0, bi1] = blocksOf(i, nb[0]);
          for (int bk = bk0; bk <= bk1; ++bk)
            for (int bj = bj0; bj <= bj1; ++bj)
              for (int bi = bi0; bi <= bi1; ++bi)
              {
                float& m = blockMax[(static_cast<size_t>(bk) * nb[1] + bj) * nb[0] + bi];
                m = std::max(m, v);
              }
        }
      }
    }
    // levels: thresholds at which these fractions of the blocks are occupied
    std::vector<float> sorted = blockMax;
    std::sort(sorted.begin(), sorted.end());
    std::vector<float> thresholds;
    for (double f : { 0.9, 0.7, 0.5, 0.35, 0.22, 0.12, 0.06, 0.03, 0.015 })
    {
      const size_t idx = std::min(
        sorted.size() - 1, static_cast<size_t>((1.0 - f) * static_cast<double>(sorted.size())));
      const float t = sorted[idx];
      if (t > sorted.front() && (thresholds.empty() || t > thresholds.back()))
        thresholds.push_back(t);
    }
    const auto& o = vol.origin();
    const auto& s = vol.spacing();
    Eigen::Vector3d half;
    for (int k = 0; k < 3; ++k)
      half[k] = 0.5 * bs * std::abs(s[k]);
    Radius =
      half.minCoeff(); // the inscribed sphere: occupied blocks already reach past the surface
    for (float t : thresholds)
    {
      std::vector<Eigen::Vector3f> pts;
      auto occupied = [&](int bi, int bj, int bk)
      {
        if (bi < 0 || bj < 0 || bk < 0 || bi >= nb[0] || bj >= nb[1] || bk >= nb[2])
          return false;
        return blockMax[(static_cast<size_t>(bk) * nb[1] + bj) * nb[0] + bi] >= t;
      };
      for (int bk = 0; bk < nb[2]; ++bk)
        for (int bj = 0; bj < nb[1]; ++bj)
          for (int bi = 0; bi < nb[0]; ++bi)
          {
            if (!occupied(bi, bj, bk))
              continue;
            if (occupied(bi - 1, bj, bk) && occupied(bi + 1, bj, bk) && occupied(bi, bj - 1, bk) &&
              occupied(bi, bj + 1, bk) && occupied(bi, bj, bk - 1) && occupied(bi, bj, bk + 1))
              continue; // inside: hidden in any projection by its neighbours
            const int idx[3] = { bi, bj, bk };
            Eigen::Vector3f c;
            for (int k = 0; k < 3; ++k)
            {
              const double lo = idx[k] * bs, hi = std::min<double>((idx[k] + 1) * bs, d[k] - 1);
              c[k] = static_cast<float>(o[k] + s[k] * 0.5 * (lo + hi));
            }
            pts.push_back(c);
          }
      if (!pts.empty())
      {
        Points.push_back(std::move(pts));
        Thresholds.push_back(t);
      }
    }
  }

  int levels() const { return static_cast<int>(Points.size()); }
  /// The value threshold of a level (opaque at and above it).
  float threshold(int level) const { return Thresholds[static_cast<size_t>(level)]; }

  // The silhouette of level `level` at `view` in a w x h raster (the view's framing).
  void render(const View& view, int level, int w, int h, Mask& out) const
  {
    out = Mask(w, h);
    const auto& cam = view.camera;
    const Eigen::Vector3d fwd = (cam.focalPoint - cam.position).normalized();
    const Eigen::Vector3d right = fwd.cross(cam.viewUp).normalized();
    const Eigen::Vector3d up = right.cross(fwd);
    const double f = cam.parallelProjection ? 0.5 * h / cam.parallelScale
                                            : 0.5 * h / std::tan(cam.viewAngle * M_PI / 360.0);
    const Eigen::Vector3f p0 = cam.position.cast<float>();
    const Eigen::Vector3f fw = fwd.cast<float>(), rt = right.cast<float>(), u = up.cast<float>();
    for (const auto& p : Points[static_cast<size_t>(level)])
    {
      const Eigen::Vector3f q = p - p0;
      const float z = q.dot(fw);
      double scale = f;
      if (!cam.parallelProjection)
      {
        if (z <= 1e-6f)
          continue;
        scale = f / z;
      }
      const double cx = 0.5 * w + q.dot(rt) * scale, cy = 0.5 * h - q.dot(u) * scale;
      const double r = Radius * scale;
      const int x0 = std::max(0, static_cast<int>(std::ceil(cx - r - 0.5)));
      const int x1 = std::min(w - 1, static_cast<int>(std::floor(cx + r - 0.5)));
      const int y0 = std::max(0, static_cast<int>(std::ceil(cy - r - 0.5)));
      const int y1 = std::min(h - 1, static_cast<int>(std::floor(cy + r - 0.5)));
      const double r2 = r * r;
      for (int y = y0; y <= y1; ++y)
      {
        const double dy = y + 0.5 - cy;
        for (int x = x0; x <= x1; ++x)
        {
          const double dx = x + 0.5 - cx;
          if (dx * dx + dy * dy <= r2)
            out(x, y) = 1;
        }
      }
      if (x0 > x1 || y0 > y1) // smaller than a pixel: mark the pixel it falls in
      {
        const int x = static_cast<int>(std::floor(cx)), y = static_cast<int>(std::floor(cy));
        if (x >= 0 && y >= 0 && x < w && y < h)
          out(x, y) = 1;
      }
    }
  }

private:
  std::vector<std::vector<Eigen::Vector3f>> Points;
  std::vector<float> Thresholds;
  double Radius = 0;
};

// Area, centroid and principal axis of a mask's set pixels (where care is set).
struct Moments
{
  double area = 0, cx = 0, cy = 0, angle = 0, anisotropy = 1;
};

Moments moments(const Mask& m, const Mask* care = nullptr)
{
  Moments r;
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (int y = 0; y < m.h; ++y)
    for (int x = 0; x < m.w; ++x)
      if (m(x, y) && (!care || (*care)(x, y)))
      {
        const double px = x + 0.5, py = y + 0.5;
        r.area += 1;
        sx += px;
        sy += py;
        sxx += px * px;
        syy += py * py;
        sxy += px * py;
      }
  if (r.area == 0)
    return r;
  r.cx = sx / r.area;
  r.cy = sy / r.area;
  const double mxx = sxx / r.area - r.cx * r.cx, myy = syy / r.area - r.cy * r.cy,
               mxy = sxy / r.area - r.cx * r.cy;
  r.angle = 0.5 * std::atan2(2 * mxy, mxx - myy);
  const double tr = mxx + myy, det = mxx * myy - mxy * mxy;
  const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
  const double l1 = 0.5 * tr + disc, l2 = std::max(1e-12, 0.5 * tr - disc);
  r.anisotropy = std::sqrt(l1 / l2);
  return r;
}

// IoU of the target with `rendered` moved by the image-plane similarity that takes the point
// cr of the render to ct of the target, rotated by rho (pixel coordinates, y down) and scaled.
double similarityIoU(const Mask& target, const Mask& care, const Mask& rendered, double cr_x,
  double cr_y, double ct_x, double ct_y, double rho, double scale)
{
  const double c = std::cos(rho), s = std::sin(rho);
  long inter = 0, uni = 0;
  for (int y = 0; y < target.h; ++y)
    for (int x = 0; x < target.w; ++x)
    {
      if (!care(x, y))
        continue;
      const double px = x + 0.5 - ct_x, py = y + 0.5 - ct_y;
      // q = cr + Rot(-rho) p / scale
      const double qx = cr_x + (c * px + s * py) / scale, qy = cr_y + (-s * px + c * py) / scale;
      const int ix = static_cast<int>(std::floor(qx)), iy = static_cast<int>(std::floor(qy));
      const bool r = ix >= 0 && iy >= 0 && ix < rendered.w && iy < rendered.h && rendered(ix, iy);
      const bool t = target(x, y);
      inter += r && t;
      uni += r || t;
    }
  return uni ? static_cast<double>(inter) / uni : 0.0;
}

double maskIoU(const Mask& target, const Mask& care, const Mask& rendered)
{
  long inter = 0, uni = 0;
  for (size_t i = 0; i < target.m.size(); ++i)
  {
    if (!care.m[i])
      continue;
    inter += target.m[i] && rendered.m[i];
    uni += target.m[i] || rendered.m[i];
  }
  return uni ? static_cast<double>(inter) / uni : 0.0;
}

// A camera in the search's parameters (relative to the reset camera).
struct CameraParams
{
  double az = 0, el = 0, roll = 0, logZoom = 0, panX = 0, panY = 0;
  int level = 0;
  double score = 0;

  View view(const View& base) const
  {
    return cameraMove(
      base, az, std::clamp(el, -89.0, 89.0), roll, std::exp(logZoom), { panX, panY });
  }
};

// The larger of the angles (degrees) between two cameras' directions and between their view-ups.
double orientationDistance(const View& a, const View& b)
{
  auto angle = [](const Eigen::Vector3d& u, const Eigen::Vector3d& v)
  { return std::acos(std::clamp(u.normalized().dot(v.normalized()), -1.0, 1.0)) * 180.0 / M_PI; };
  const Eigen::Vector3d fa = a.camera.focalPoint - a.camera.position,
                        fb = b.camera.focalPoint - b.camera.position;
  return std::max(angle(fa, fb), angle(a.camera.viewUp, b.camera.viewUp));
}

// Nelder-Mead maximisation of f over the six camera parameters.
template <typename F>
CameraParams nelderMead(const CameraParams& start, F&& f, int evaluations, double stepScale = 1)
{
  constexpr int n = 6;
  double steps[n] = { 6, 6, 6, 0.06, 0.03, 0.03 };
  for (double& st : steps)
    st *= stepScale;
  auto toVec = [](const CameraParams& p) {
    return std::array<double, n>{ p.az, p.el, p.roll, p.logZoom, p.panX, p.panY };
  };
  auto fromVec = [&](const std::array<double, n>& v)
  {
    CameraParams p = start;
    p.az = v[0];
    p.el = std::clamp(v[1], -89.0, 89.0);
    p.roll = v[2];
    p.logZoom = std::clamp(v[3], -2.0, 2.0);
    p.panX = v[4];
    p.panY = v[5];
    return p;
  };
  std::vector<std::array<double, n>> x(n + 1, toVec(start));
  std::vector<double> fx(n + 1);
  for (int i = 0; i < n; ++i)
    x[i + 1][i] += steps[i];
  int used = 0;
  for (int i = 0; i <= n; ++i, ++used)
    fx[i] = -f(fromVec(x[i]));
  while (used < evaluations)
  {
    std::vector<int> order(n + 1);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return fx[a] < fx[b]; });
    const int best = order[0], worst = order[n], second = order[n - 1];
    std::array<double, n> centroid{};
    for (int i = 0; i <= n; ++i)
      if (i != worst)
        for (int k = 0; k < n; ++k)
          centroid[k] += x[i][k] / n;
    auto along = [&](double t)
    {
      std::array<double, n> p;
      for (int k = 0; k < n; ++k)
        p[k] = centroid[k] + t * (x[worst][k] - centroid[k]);
      return p;
    };
    const auto xr = along(-1.0);
    const double fr = -f(fromVec(xr));
    ++used;
    if (fr < fx[best])
    {
      const auto xe = along(-2.0);
      const double fe = -f(fromVec(xe));
      ++used;
      if (fe < fr)
        x[worst] = xe, fx[worst] = fe;
      else
        x[worst] = xr, fx[worst] = fr;
    }
    else if (fr < fx[second])
    {
      x[worst] = xr;
      fx[worst] = fr;
    }
    else
    {
      const auto xc = along(fr < fx[worst] ? -0.5 : 0.5);
      const double fc = -f(fromVec(xc));
      ++used;
      if (fc < std::min(fr, fx[worst]))
      {
        x[worst] = xc;
        fx[worst] = fc;
      }
      else
      {
        for (int i = 0; i <= n; ++i)
        {
          if (i == best)
            continue;
          for (int k = 0; k < n; ++k)
            x[i][k] = x[best][k] + 0.5 * (x[i][k] - x[best][k]);
          fx[i] = -f(fromVec(x[i]));
          ++used;
        }
      }
    }
  }
  const int bestIndex = static_cast<int>(std::min_element(fx.begin(), fx.end()) - fx.begin());
  CameraParams r = fromVec(x[bestIndex]);
  r.score = -fx[bestIndex];
  return r;
}

// The picture prepared for the match: RGB (alpha composited away) or RGBA, and its masks.
struct Picture
{
  Image rgb;                    // RGB in [0, 1] (working size)
  Image rgba;                   // RGBA straight, when the picture has transparency
  bool alpha = false;           // compare premultiplied RGBA (no background)
  Mask foreground;              // differs from the background
  Mask overlay;                 // foreground parts judged overlays (ignored)
  std::vector<int> label, area; // connected parts of the foreground
};

// Bands of one colour along the picture's edges, each followed by a line of another colour: a
// letterbox (or pillarbox) put around a picture. Returns the part inside {x, y, width, height}
// (the whole picture when there is none).
std::array<int, 4> letterbox(const Image& img)
{
  const int w = img.width, h = img.height, ch = img.channels;
  // a line (row or column) of one colour: 98 % of its middle half (a band on the other axis
  // may cover its ends) within 4 levels of its median
  auto lineColour = [&](bool row, int index, std::array<double, 3>& colour)
  {
    const int full = row ? w : h, first = full / 4, n = std::max(1, full / 2);
    std::vector<std::array<float, 3>> px(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
    {
      const int x = row ? first + i : index, y = row ? index : first + i;
      for (int c = 0; c < 3; ++c)
        px[static_cast<size_t>(i)][c] = img.pixels[(static_cast<size_t>(y) * w + x) * ch + c];
    }
    for (int c = 0; c < 3; ++c)
    {
      std::vector<double> v;
      v.reserve(px.size());
      for (const auto& p : px)
        v.push_back(p[c]);
      colour[c] = median(std::move(v));
    }
    int near = 0;
    for (const auto& p : px)
    {
      double d = 0;
      for (int c = 0; c < 3; ++c)
        d = std::max(d, std::abs(p[c] - colour[c]));
      near += d <= 4.0 / 255.0;
    }
    return near >= 0.98 * n;
  };
  auto distance = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::max({ std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2]) });
  };
  // the band's thickness on one side (0 when none): lines of the edge's colour, then (after at
  // most two lines of transition) a line of one other colour
  auto band = [&](bool row, bool fromStart)
  {
    const int n = row ? h : w;
    auto line = [&](int k) { return fromStart ? k : n - 1 - k; };
    std::array<double, 3> edge{}, c{};
    if (!lineColour(row, line(0), edge))
      return 0;
    int k = 1;
    while (k < n / 3 && lineColour(row, line(k), c) && distance(c, edge) <= 4.0 / 255.0)
      ++k;
    if (k < 2 || k >= n / 3)
      return 0;
    // the other colour holds for two more lines (a gradient background drifts instead)
    std::array<double, 3> next{};
    for (int t = k; t < std::min(n / 3, k + 3); ++t)
      if (lineColour(row, line(t), c) && distance(c, edge) > 8.0 / 255.0)
      {
        for (int u = t + 1; u <= t + 2; ++u)
          if (!lineColour(row, line(u), next) || distance(next, c) > 1.5 / 255.0)
            return 0;
        return t;
      }
    return 0;
  };
  const int top = band(true, true), bottom = band(true, false), left = band(false, true),
            right = band(false, false);
  return { left, top, w - left - right, h - top - bottom };
}

} // namespace

PictureBackground estimateBackground(const Image& picture)
{
  if (picture.channels < 3)
  {
    throw Error("estimate background: an RGB picture is needed");
  }
  const int w = picture.width, h = picture.height;
  if (w < 4 || h < 4)
  {
    throw Error("estimate background: the picture is too small");
  }
  const int b = std::max(1, std::min(w, h) / 100); // border width
  auto px = [&](int x, int y, int c)
  {
    return static_cast<double>(
      picture.pixels[(static_cast<size_t>(y) * w + x) * picture.channels + c]);
  };
  // the top and bottom bands' medians, at their mean rows
  auto bandMedian = [&](int y0, int y1)
  {
    std::array<double, 3> m{};
    for (int c = 0; c < 3; ++c)
    {
      std::vector<double> v;
      for (int y = y0; y < y1; ++y)
        for (int x = 0; x < w; ++x)
          v.push_back(px(x, y, c));
      m[c] = median(std::move(v));
    }
    return m;
  };
  const auto topBand = bandMedian(0, b), bottomBand = bandMedian(h - b, h);
  PictureBackground bg;
  double spread = 0;
  for (int c = 0; c < 3; ++c)
    spread = std::max(spread, std::abs(topBand[c] - bottomBand[c]));
  // the border's pixels (top, bottom, left, right bands) and their rows
  std::vector<std::pair<int, int>> border;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (y < b || y >= h - b || x < b || x >= w - b)
        border.emplace_back(x, y);
  if (spread > 3.0 / 255.0)
  {
    // a vertical gradient: colour(t) = top + (bottom - top) t at pixel centres, t = (y+.5)/h;
    // the bands' medians sit at their mean rows
    bg.gradient = true;
    const double t0 = 0.5 * b / h, t1 = 1.0 - 0.5 * b / h;
    for (int c = 0; c < 3; ++c)
    {
      const double slope = (bottomBand[c] - topBand[c]) / (t1 - t0);
      bg.top[c] = std::clamp(topBand[c] - slope * t0, 0.0, 1.0);
      bg.bottom[c] = std::clamp(topBand[c] + slope * (1.0 - t0), 0.0, 1.0);
    }
  }
  else
  {
    for (int c = 0; c < 3; ++c)
    {
      std::vector<double> v;
      v.reserve(border.size());
      for (const auto& [x, y] : border)
        v.push_back(px(x, y, c));
      bg.bottom[c] = bg.top[c] = median(std::move(v));
    }
  }
  // noise: robust spread about the model; dominance: most border pixels near it
  View probe;
  probe.width = w;
  probe.height = h;
  bg.applyTo(probe);
  std::vector<double> dev;
  dev.reserve(border.size());
  for (const auto& [x, y] : border)
  {
    const auto m = probe.backgroundAt(y);
    double d = 0;
    for (int c = 0; c < 3; ++c)
      d = std::max(d, std::abs(px(x, y, c) - m[c]));
    dev.push_back(d);
  }
  // the noise from neighbouring border pixels (a scene's two colours do not count as noise)
  std::vector<double> steps;
  auto step = [&](int x0, int y0, int x1, int y1)
  {
    double d = 0;
    for (int c = 0; c < 3; ++c)
      d = std::max(d, std::abs(px(x0, y0, c) - px(x1, y1, c)));
    steps.push_back(d);
  };
  for (int x = 0; x + 1 < w; ++x)
  {
    step(x, 0, x + 1, 0);
    step(x, h - 1, x + 1, h - 1);
  }
  for (int y = 0; y + 1 < h; ++y)
  {
    step(0, y, 0, y + 1);
    step(w - 1, y, w - 1, y + 1);
  }
  bg.noise = 1.4826 * median(std::move(steps)) / std::sqrt(2.0);
  const double tol = std::max(4.0 / 255.0, 3.0 * bg.noise);
  const double near =
    static_cast<double>(std::count_if(dev.begin(), dev.end(), [&](double d) { return d <= tol; })) /
    static_cast<double>(dev.size());
  if (near < 0.75)
  {
    std::ostringstream msg;
    msg << "the picture has no background colour: only " << std::lround(100 * near)
        << " % of its border is near one colour (or one vertical gradient), 75 % are needed — "
           "is it cropped into the object, or a photograph?";
    throw Error(msg.str());
  }
  return bg;
}

MatchResult matchPicture(const DifferentiableRenderer& renderer, const Image& input,
  const MatchOptions& opt, const MatchProgress& progress)
{
  const auto t0 = Clock::now();
  auto report = [&](const std::string& stage, double fraction, const Image* preview)
  {
    if (progress && !progress(stage, fraction, preview))
      throw Cancelled();
  };
  if (input.empty() || input.width < 16 || input.height < 16)
  {
    std::ostringstream msg;
    msg << "the picture is " << input.width << " x " << input.height
        << " pixels: at least 16 x 16 are needed to match it";
    throw Error(msg.str());
  }
  if (input.channels != 3 && input.channels != 4)
  {
    throw Error("the picture has " + std::to_string(input.channels) +
      " channels: an RGB (or RGBA) picture is needed");
  }
  for (float v : input.pixels)
    if (!std::isfinite(v))
      throw Error("the picture holds NaN or infinite values");
  report("background", 0.0, nullptr);

  // the working picture: at most 1024 pixels a side (the fit samples rays; more is not better)
  MatchResult result;
  Picture pic;
  {
    // a letterbox's bands are not the picture's background: matched inside them
    result.crop = letterbox(input);
    Image inside = input;
    if (result.crop[2] != input.width || result.crop[3] != input.height)
    {
      inside = Image(result.crop[2], result.crop[3], input.channels);
      for (int y = 0; y < inside.height; ++y)
        std::copy_n(
          &input.pixels[(static_cast<size_t>(y + result.crop[1]) * input.width + result.crop[0]) *
            input.channels],
          static_cast<size_t>(inside.width) * input.channels,
          &inside.pixels[static_cast<size_t>(y) * inside.width * input.channels]);
    }
    const int longest = std::max(inside.width, inside.height);
    Image work = inside;
    if (longest > 1024)
    {
      const double f = 1024.0 / longest;
      work = resizeImage(inside, std::max(16, static_cast<int>(std::lround(inside.width * f))),
        std::max(16, static_cast<int>(std::lround(inside.height * f))));
    }
    for (auto& v : work.pixels)
      v = std::clamp(v, 0.0f, 1.0f);
    bool transparent = false;
    if (work.channels == 4)
      for (size_t i = 3; i < work.pixels.size(); i += 4)
        transparent = transparent || work.pixels[i] < 254.5f / 255.0f;
    pic.alpha = transparent;
    if (transparent)
    {
      pic.rgba = work;
    }
    pic.rgb = Image(work.width, work.height, 3);
    for (size_t i = 0, n = static_cast<size_t>(work.width) * work.height; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        pic.rgb.pixels[3 * i + c] = work.pixels[i * work.channels + c];
  }
  const int W = pic.rgb.width, H = pic.rgb.height;

  // background and foreground
  View view = opt.view ? *opt.view : defaultView(renderer.caster().volume(), W, H);
  view.width = W;
  view.height = H;
  if (opt.opacityUnitDistance)
    view.opacityUnitDistance = opt.opacityUnitDistance;
  pic.foreground = Mask(W, H);
  if (pic.alpha)
  {
    for (size_t i = 0; i < pic.foreground.m.size(); ++i)
      pic.foreground.m[i] = pic.rgba.pixels[4 * i + 3] > 1.5f / 255.0f;
  }
  else
  {
    if (opt.background)
    {
      result.background.bottom = result.background.top = *opt.background;
      result.background.noise = 0;
    }
    else
    {
      result.background = estimateBackground(pic.rgb);
    }
    result.background.applyTo(view);
    const double tol = std::max(3.5 / 255.0, 4.0 * result.background.noise);
    for (int y = 0; y < H; ++y)
    {
      const auto bgc = view.backgroundAt(y);
      for (int x = 0; x < W; ++x)
      {
        const float* p = &pic.rgb.pixels[3 * (static_cast<size_t>(y) * W + x)];
        double d = 0;
        for (int c = 0; c < 3; ++c)
          d = std::max(d, std::abs(p[c] - bgc[c]));
        pic.foreground(x, y) = d > tol;
      }
    }
  }
  pic.label = components(pic.foreground, pic.area);
  const long foregroundArea = std::accumulate(pic.area.begin(), pic.area.end(), 0L);
  if (foregroundArea < 16)
  {
    throw Error("the picture shows nothing but the background colour: there is nothing to match");
  }
  const int largest =
    static_cast<int>(std::max_element(pic.area.begin(), pic.area.end()) - pic.area.begin());
  // overlay candidates: parts much smaller than the largest (axes, text, a scalar bar)
  std::vector<char> candidate(pic.area.size(), 0);
  if (opt.maskOverlays)
    for (size_t k = 0; k < pic.area.size(); ++k)
      candidate[k] = static_cast<int>(k) != largest && pic.area[k] < 0.2 * pic.area[largest];
  result.backgroundSeconds = secondsSince(t0);
  report("camera", 0.05, nullptr);

  // --- the camera -------------------------------------------------------------------------
  const auto tCamera = Clock::now();
  const RayCaster& caster = renderer.caster();
  const Volume& volume = caster.volume();
  const SilhouetteModel model(volume);
  if (model.levels() == 0)
  {
    throw Error("the volume has no structure to match a picture with");
  }
  // search raster: ~128 pixels on the longest side
  const double sf = 128.0 / std::max(W, H);
  const int sw = std::max(8, static_cast<int>(std::lround(W * sf))),
            sh = std::max(8, static_cast<int>(std::lround(H * sf)));
  Mask targetFull(W, H), candidateFull(W, H);
  for (size_t i = 0; i < targetFull.m.size(); ++i)
  {
    const int l = pic.label[i];
    targetFull.m[i] = l >= 0 && !candidate[static_cast<size_t>(l)];
    candidateFull.m[i] = l >= 0 && candidate[static_cast<size_t>(l)];
  }
  // the object's silhouette: its foreground with the holes filled (background seen through a
  // semi-transparent object, or between structures), as the volume's silhouettes have none
  const Mask target = fillHoles(shrink(targetFull, sw, sh));
  Mask care = shrink(dilate(candidateFull, std::max(1, W / sw)), sw, sh);
  for (auto& v : care.m)
    v = !v;
  const Moments mt = moments(target, &care);
  View base = view;
  base.width = sw;
  base.height = sh;
  const View resetView = [&]
  {
    View r = defaultView(volume, sw, sh);
    r.background = base.background;
    r.background2 = base.background2;
    r.opacityUnitDistance = base.opacityUnitDistance;
    r.camera.viewAngle = base.camera.viewAngle;
    return r;
  }();
  // the search starts from ParaView's reset camera, or from the given view
  const View start = opt.view ? base : resetView;

  CameraParams best;
  std::vector<CameraParams> finalists;
  Mask scratch;
  auto exactIoU = [&](const CameraParams& p)
  {
    model.render(p.view(start), p.level, sw, sh, scratch);
    return maskIoU(target, care, scratch);
  };
  const bool search = !opt.view || opt.refineGivenView;
  if (search)
  {
    // stage 1: directions x levels, each aligned in the image plane by moments
    std::vector<CameraParams> coarse;
    std::vector<std::pair<double, double>> directions;
    const double range = opt.view ? 30.0 : 180.0; // a given view: search near it
    for (double el = -60; el <= 60; el += 30)
      for (double az = -180; az < 180; az += 30)
        if (std::abs(az) <= range && std::abs(el) <= std::max(range, 60.0))
          directions.emplace_back(az, el);
    if (!opt.view)
    {
      directions.emplace_back(0, 89);
      directions.emplace_back(0, -89);
    }
    Mask rendered;
    for (const auto& [az, el] : directions)
      for (int level = 0; level < model.levels(); ++level)
      {
        CameraParams p;
        p.az = az;
        p.el = el;
        p.level = level;
        model.render(p.view(start), level, sw, sh, rendered);
        const Moments mr = moments(rendered);
        if (mr.area < 4)
          continue;
        const double scale = std::sqrt(mt.area / mr.area);
        std::vector<double> rhos{ mt.angle - mr.angle, mt.angle - mr.angle + M_PI };
        if (mt.anisotropy < 1.3 || mr.anisotropy < 1.3)
          for (int k = 0; k < 12; ++k)
            rhos.push_back(k * M_PI / 6);
        for (double rho : rhos)
        {
          const double iou =
            similarityIoU(target, care, rendered, mr.cx, mr.cy, mt.cx, mt.cy, rho, scale);
          CameraParams q = p;
          // roll: a camera roll of +a turns the picture by -a in pixel coordinates (y down)
          q.roll = -rho * 180.0 / M_PI;
          q.logZoom = std::log(scale);
          // where the render's centroid lands after the roll and zoom about the centre, and
          // the pan that moves it onto the target's
          const double c = std::cos(rho), s = std::sin(rho);
          const double rx = mr.cx - 0.5 * sw, ry = mr.cy - 0.5 * sh;
          const double lx = 0.5 * sw + scale * (c * rx - s * ry),
                       ly = 0.5 * sh + scale * (s * rx + c * ry);
          q.panX = -(mt.cx - lx) / sh;
          q.panY = (mt.cy - ly) / sh;
          q.score = iou;
          coarse.push_back(q);
        }
      }
    std::sort(coarse.begin(), coarse.end(),
      [](const CameraParams& a, const CameraParams& b) { return a.score > b.score; });
    report("camera", 0.15, nullptr);
    // stage 2: the best distinct ones refined on exact silhouettes
    std::vector<CameraParams> seeds;
    for (const auto& c : coarse)
    {
      bool distinct = true;
      for (const auto& s : seeds)
        distinct = distinct && orientationDistance(c.view(start), s.view(start)) > 20;
      if (distinct)
        seeds.push_back(c);
      if (seeds.size() >= 12)
        break;
    }
    for (size_t i = 0; i < seeds.size(); ++i)
    {
      auto refined = nelderMead(seeds[i], exactIoU, 160);
      finalists.push_back(refined);
      report("camera", 0.15 + 0.25 * (i + 1) / seeds.size(), nullptr);
    }
    // the discs of the blocks make a silhouette a little larger than the volume's own (and the
    // search then moves the camera away): the distance corrected by the ratio of the sizes of
    // the block silhouette and a ray cast of the same level (opaque above its threshold)
    {
      RenderOptions coarse = opt.reconstruction.render;
      coarse.sampleDistance = 2.0 * caster.defaultSampleDistance();
      const auto range = volume.range();
      for (auto& f : finalists)
      {
        TransferFunction1D occupancy;
        const double t = model.threshold(f.level), eps = 1e-4 * (range[1] - range[0]);
        occupancy.color = { { range[0], 1, 1, 1 } };
        occupancy.opacity = { { range[0], 0 }, { std::max(range[0], t - eps), 0 }, { t, 1 },
          { range[1], 1 } };
        const Image cast =
          caster.render(bakeTable(occupancy, range[0], range[1], 1024), f.view(start), coarse);
        model.render(f.view(start), f.level, sw, sh, scratch);
        double castArea = 0, modelArea = 0;
        for (size_t i = 0; i < scratch.m.size(); ++i)
        {
          castArea += cast.pixels[4 * i + 3] > 0.5f;
          modelArea += scratch.m[i];
        }
        if (castArea > 4 && modelArea > 4)
          f.logZoom += 0.5 * std::log(modelArea / castArea);
      }
    }
    std::sort(finalists.begin(), finalists.end(),
      [](const CameraParams& a, const CameraParams& b) { return a.score > b.score; });
  }
  else
  {
    CameraParams given;
    double bestIoU = -1;
    for (int level = 0; level < model.levels(); ++level)
    {
      given.level = level;
      const double iou = exactIoU(given);
      if (iou > bestIoU)
        bestIoU = iou, best = given, best.score = iou;
    }
    finalists.push_back(best);
  }
  if (search && (finalists.empty() || finalists.front().score < opt.minimumOverlap))
  {
    std::ostringstream msg;
    msg << "no camera explains the picture: the best camera's silhouette overlaps the picture's "
           "object by "
        << std::lround(100 * (finalists.empty() ? 0.0 : finalists.front().score)) << " % (at least "
        << std::lround(100 * opt.minimumOverlap) << " % needed) — is it a picture of this volume?";
    throw Error(msg.str());
  }

  // stage 3: the finalists whose overlap is close to the best scored by a short reconstruction
  // (mirror views have alike silhouettes; colours tell them apart)
  const Image& workImage = pic.alpha ? pic.rgba : pic.rgb;
  Mask overlayFull(W, H);
  // overlay candidates that the best camera's silhouette covers are the object after all
  {
    const CameraParams& b = finalists.front();
    View full = b.view(start);
    full.width = W;
    full.height = H;
    Mask sil;
    model.render(full, b.level, W, H, sil);
    const Mask silWide = dilate(sil, std::max(2, W / 100));
    std::vector<long> covered(pic.area.size(), 0);
    for (size_t i = 0; i < sil.m.size(); ++i)
      if (pic.label[i] >= 0 && silWide.m[i])
        ++covered[static_cast<size_t>(pic.label[i])];
    std::vector<char> overlay(pic.area.size(), 0);
    for (size_t k = 0; k < pic.area.size(); ++k)
      overlay[k] = candidate[k] && covered[k] < 0.5 * pic.area[k];
    for (size_t i = 0; i < sil.m.size(); ++i)
      overlayFull.m[i] = pic.label[i] >= 0 && overlay[static_cast<size_t>(pic.label[i])];
    overlayFull = dilate(overlayFull, std::max(2, W / 200));
  }
  Mask emptyFull(W, H);
  if (!pic.alpha)
  {
    const Mask near = dilate(pic.foreground, std::max(2, W / 300));
    for (size_t i = 0; i < emptyFull.m.size(); ++i)
      emptyFull.m[i] = !near.m[i] && !overlayFull.m[i];
  }
  Image weightFull(W, H, 1);
  for (size_t i = 0; i < weightFull.pixels.size(); ++i)
    weightFull.pixels[i] = overlayFull.m[i] ? 0.0f : 1.0f;
  Image emptyImage = toImage(emptyFull);
  auto makeTarget = [&](const View& v, const Image& image, int w, int h)
  {
    ReconstructionTarget t;
    t.image = image;
    t.view = v;
    t.view.width = w;
    t.view.height = h;
    t.mask = w == W && h == H ? weightFull : resizeImage(weightFull, w, h);
    if (!pic.alpha && opt.emptySpaceWeight > 0)
    {
      t.empty = w == W && h == H ? emptyImage : resizeImage(emptyImage, w, h);
      for (auto& e : t.empty.pixels)
        e = e > 0.99f ? 1.0f : 0.0f;
      t.emptyWeight = opt.emptySpaceWeight;
    }
    return t;
  };
  // the camera stage's TF: the final fit starts from it
  std::optional<TransferTable1D> warm;
  if (search)
  {
    std::vector<CameraParams> scored;
    for (const auto& f : finalists)
    {
      bool distinct = true;
      for (const auto& s : scored)
        distinct = distinct && orientationDistance(f.view(start), s.view(start)) > 15;
      if (distinct && f.score >= finalists.front().score - 0.1 &&
        static_cast<int>(scored.size()) < std::max(1, opt.cameraCandidates))
        scored.push_back(f);
    }
    ReconstructionOptions sopt = opt.reconstruction;
    sopt.twoD = false;
    sopt.primitives = 0;
    sopt.iterations = 40;
    sopt.patience = 40;
    sopt.raysPerIteration = 512;
    // coarser samples: the camera stage needs the picture's look, not its last digit
    sopt.render.sampleDistance = 3.0 * caster.defaultSampleDistance();
    sopt.seed = 7;
    sopt.bins = 64;
    sopt.snapshotEvery = 0;
    sopt.ssimWeight = 0;
    // a short reconstruction at a camera: its TF and final loss (mean of the last steps)
    auto shortFit = [&](const CameraParams& c, const std::optional<TransferTable1D>& init)
    {
      ReconstructionOptions o = sopt;
      if (init)
        o.initial1D = init;
      auto r =
        reconstructTransferFunction(renderer, { makeTarget(c.view(start), workImage, W, H) }, o);
      const size_t tail = std::min<size_t>(10, r.loss.size());
      double loss = 0;
      for (size_t k = r.loss.size() - tail; k < r.loss.size(); ++k)
        loss += r.loss[k] / static_cast<double>(tail);
      return std::make_pair(std::move(r), loss);
    };
    // the image loss of a TF at a camera (the reconstruction's: L1 over the compared pixels,
    // plus the empty-space term), for the camera's photometric refinement
    // a fixed set of the picture's pixels (most on and around the object, the rest anywhere
    // compared), rendered at full resolution: the camera is refined to a fraction of a pixel
    std::vector<int> probe;
    {
      const Mask around = dilate(pic.foreground, std::max(2, std::max(W, H) / 20));
      std::vector<int> near, far;
      for (int i = 0; i < W * H; ++i)
        if (!overlayFull.m[static_cast<size_t>(i)])
          (around.m[static_cast<size_t>(i)] ? near : far).push_back(i);
      std::mt19937 rng(11);
      std::shuffle(near.begin(), near.end(), rng);
      std::shuffle(far.begin(), far.end(), rng);
      near.resize(std::min<size_t>(near.size(), 3072));
      far.resize(std::min<size_t>(far.size(), 1024));
      probe = near;
      probe.insert(probe.end(), far.begin(), far.end());
      std::sort(probe.begin(), probe.end());
    }
    const ReconstructionTarget fullTarget = makeTarget(start, workImage, W, H);
    std::vector<float> probeRGBA;
    std::vector<RayRecord> probeRecords;
    auto photometricLoss =
      [&](const ReconstructionResult& tf, const CameraParams& c, const RenderOptions& how)
    {
      View v = c.view(start);
      v.width = W;
      v.height = H;
      const auto& t = tf.table1D;
      renderer.forward(
        t.rgba.data(), t.width, t.min, t.max, v, how, probe, probeRGBA, probeRecords);
      double loss = 0;
      for (size_t q = 0; q < probe.size(); ++q)
      {
        const size_t i = static_cast<size_t>(probe[q]);
        const float* p = &probeRGBA[4 * q];
        const float* want = &workImage.pixels[i * workImage.channels];
        double l = 0;
        if (pic.alpha)
        {
          for (int k = 0; k < 3; ++k)
            l += std::abs(p[k] - want[k] * want[3]);
          l += std::abs(p[3] - want[3]);
        }
        else
        {
          const auto bgc = v.backgroundAt(static_cast<int>(i) / W);
          for (int k = 0; k < 3; ++k)
            l += std::abs(p[k] + (1 - p[3]) * bgc[k] - want[k]);
          if (!fullTarget.empty.empty() && fullTarget.empty.pixels[i] > 0)
            for (int k = 0; k < 4; ++k)
              l += 0.75 * fullTarget.emptyWeight * std::abs(p[k]);
        }
        loss += l;
      }
      return loss / static_cast<double>(probe.size());
    };
    auto refine = [&](const ReconstructionResult& tf, const CameraParams& c, int evaluations,
                    const RenderOptions& how)
    {
      CameraParams r = nelderMead(
        c, [&](const CameraParams& p) { return -photometricLoss(tf, p, how); }, evaluations, 0.3);
      r.level = c.level;
      return r;
    };
    // every candidate: a short fit; the two best: the camera refined on the picture's colours
    // with that TF, refitted, and refined once more; the lowest loss wins
    struct Scored
    {
      CameraParams camera;
      ReconstructionResult tf;
      double loss;
    };
    std::vector<Scored> fits;
    for (size_t i = 0; i < scored.size(); ++i)
    {
      auto [tf, loss] = shortFit(scored[i], std::nullopt);
      fits.push_back({ scored[i], std::move(tf), loss });
      report("camera", 0.4 + 0.1 * (i + 1) / scored.size(), nullptr);
    }
    std::sort(
      fits.begin(), fits.end(), [](const Scored& a, const Scored& b) { return a.loss < b.loss; });
    // the runner-up is refined too unless the best is clearly better
    fits.resize(fits.size() > 1 && fits[1].loss < 1.25 * fits[0].loss ? 2 : 1);
    for (size_t i = 0; i < fits.size(); ++i)
    {
      for (int round = 0; round < std::max(1, opt.cameraRounds); ++round)
      {
        fits[i].camera = refine(fits[i].tf, fits[i].camera, round == 0 ? 80 : 40, sopt.render);
        auto [tf, loss] = shortFit(fits[i].camera, fits[i].tf.table1D);
        fits[i].tf = std::move(tf);
        fits[i].loss = loss;
      }
      report("camera", 0.5 + 0.1 * (i + 1) / fits.size(), nullptr);
    }
    const auto winner = std::min_element(
      fits.begin(), fits.end(), [](const Scored& a, const Scored& b) { return a.loss < b.loss; });
    best = winner->camera;
    // a polish: a longer fit at the winner (more rays, all the bins, full sampling), the camera
    // refined with it
    {
      ReconstructionOptions o = sopt;
      o.initial1D = winner->tf.table1D;
      o.iterations = o.patience = 120;
      o.raysPerIteration = 1024;
      o.bins = opt.reconstruction.bins;
      o.render.sampleDistance = opt.reconstruction.render.sampleDistance;
      winner->tf =
        reconstructTransferFunction(renderer, { makeTarget(best.view(start), workImage, W, H) }, o);
      best = refine(winner->tf, best, 150, o.render); // fine rims need full sampling
    }
    best.score = exactIoU(best);
    if (!opt.reconstruction.twoD)
      warm = winner->tf.table1D; // started from the given initial TF, if any
  }
  result.cameraEstimated = search;
  result.overlap = best.score;
  result.orbit = { std::remainder(best.az, 360.0), best.el, std::remainder(best.roll, 360.0) };
  result.zoom = std::exp(best.logZoom);
  result.pan = { best.panX, best.panY };
  View found = best.view(start);
  found.width = W;
  found.height = H;
  result.cameraSeconds = secondsSince(tCamera);
  report("fit", 0.5, nullptr);

  // --- the fit ------------------------------------------------------------------------------
  const auto tFit = Clock::now();
  const ReconstructionTarget target0 = makeTarget(found, pic.alpha ? pic.rgba : pic.rgb, W, H);
  ReconstructionOptions ropt = opt.reconstruction;
  if (warm)
    ropt.initial1D = warm;
  View preview = found;
  preview.width = std::max(8, W / std::max(1, opt.previewDivisor));
  preview.height = std::max(8, H / std::max(1, opt.previewDivisor));
  const int iterations = std::max(1, ropt.iterations);
  result.tf = reconstructTransferFunction(renderer, { target0 }, ropt,
    [&](int step, double, const ReconstructionResult* snapshot)
    {
      Image shot;
      if (snapshot)
        shot = renderResult(caster, *snapshot, preview, ropt.render);
      report(
        "fit", 0.5 + 0.4 * std::min(1.0, (step + 1.0) / iterations), snapshot ? &shot : nullptr);
      return true;
    });

  // the fit's PSNR over the object (the picture's foreground, or what the render shows) at the
  // preview's size, overlays left out: the background, matched by construction, does not count;
  // and each object pixel's residual (largest channel difference; -1 elsewhere)
  const Image theirs =
    resizeImage(pic.alpha ? premultiplyAlpha(pic.rgba) : pic.rgb, preview.width, preview.height);
  const Image object = resizeImage(
    toImage(dilate(pic.foreground, std::max(1, W / 200))), preview.width, preview.height);
  std::vector<double> residual;
  auto assess = [&](const ReconstructionResult& tf)
  {
    const Image render = renderResult(caster, tf, preview, ropt.render);
    const Image ours = pic.alpha
      ? render
      : (preview.background2
            ? compositeOverBackground(render, preview.background, *preview.background2)
            : compositeOverBackground(render, preview.background));
    const Image weight = resizeImage(weightFull, preview.width, preview.height);
    const size_t np = static_cast<size_t>(preview.width) * preview.height;
    residual.assign(np, -1.0);
    double se = 0, n = 0;
    for (size_t i = 0; i < np; ++i)
    {
      if (weight.pixels[i] < 0.99f ||
        (object.pixels[i] < 0.01f && render.pixels[4 * i + 3] < 0.01f))
        continue;
      double largest = 0;
      for (int c = 0; c < ours.channels; ++c)
      {
        const double d =
          ours.pixels[i * ours.channels + c] - theirs.pixels[i * theirs.channels + c];
        se += d * d;
        n += 1;
        largest = std::max(largest, std::abs(d));
      }
      residual[i] = largest;
    }
    return se > 0 ? 10.0 * std::log10(n / se) : 100.0;
  };
  if (opt.reconstruction.initial1D && !opt.reconstruction.twoD)
  {
    ReconstructionResult start1D;
    start1D.table1D = *opt.reconstruction.initial1D;
    result.initialPSNR = assess(start1D);
  }
  result.fitPSNR = assess(result.tf);
  // outliers: what the fit cannot explain on the object (text, arrows or marks drawn over it):
  // residuals above 6 times the median and above 0.2, on at least 0.2 % of the object, are
  // masked as overlays and the TF refitted without them (1D)
  if (opt.maskOverlays && !result.tf.twoD)
  {
    std::vector<double> onObject;
    for (double r : residual)
      if (r >= 0)
        onObject.push_back(r);
    const double limit = std::max(0.2, 6.0 * median(onObject));
    Mask outliers(preview.width, preview.height);
    size_t count = 0;
    for (size_t i = 0; i < residual.size(); ++i)
      if (residual[i] > limit)
        outliers.m[i] = 1, ++count;
    if (count > 3 && static_cast<double>(count) >= 0.002 * static_cast<double>(onObject.size()))
    {
      const Mask wide = dilate(outliers, 1);
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
          if (wide(std::min(preview.width - 1, x * preview.width / W),
                std::min(preview.height - 1, y * preview.height / H)))
          {
            overlayFull(x, y) = 1;
            weightFull.pixels[static_cast<size_t>(y) * W + x] = 0.0f;
            emptyImage.pixels[static_cast<size_t>(y) * W + x] = 0.0f;
          }
      ReconstructionOptions again = ropt;
      again.initial1D = result.tf.table1D;
      again.iterations = std::min(ropt.iterations, 150);
      const ReconstructionTarget masked = makeTarget(found, pic.alpha ? pic.rgba : pic.rgb, W, H);
      result.tf = reconstructTransferFunction(renderer, { masked }, again,
        [&](int step, double, const ReconstructionResult*)
        {
          report("fit", 0.9 + 0.1 * std::min(1.0, (step + 1.0) / again.iterations), nullptr);
          return true;
        });
      result.fitPSNR = assess(result.tf);
    }
  }
  result.fitSeconds = secondsSince(tFit);
  if (search && result.fitPSNR < opt.minimumFitPSNR)
  {
    std::ostringstream msg;
    msg.precision(3);
    msg << "no camera explains the picture: the best match differs from it by " << result.fitPSNR
        << " dB PSNR over the object (at least " << opt.minimumFitPSNR
        << " dB needed; silhouette overlap " << std::lround(100 * result.overlap)
        << " %) — is it a picture of this volume, unlit and uncropped?";
    throw Error(msg.str());
  }
  result.view = found;
  result.view.width = result.crop[2];
  result.view.height = result.crop[3];
  result.masks.foreground = toImage(pic.foreground);
  result.masks.overlay = toImage(overlayFull);
  if (W != result.crop[2] || H != result.crop[3])
  {
    result.masks.foreground = resizeImage(result.masks.foreground, result.crop[2], result.crop[3]);
    result.masks.overlay = resizeImage(result.masks.overlay, result.crop[2], result.crop[3]);
  }
  result.seconds = secondsSince(t0);
  report("fit", 1.0, nullptr);
  return result;
}

} // namespace ddg
