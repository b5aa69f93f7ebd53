// MatchParts.cxx: binary rasters, their moments and overlaps, and a picture's letterbox
// (MatchParts.h).
#include "Reconstruct/MatchParts.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

namespace ddg
{
namespace matchparts
{

Image toImage(const Mask& mask)
{
  Image img(mask.w, mask.h, 1);
  for (size_t i = 0; i < mask.m.size(); ++i)
    img.pixels[i] = mask.m[i] ? 1.0f : 0.0f;
  return img;
}

// Dilation by a (2r+1)^2 box (separable).
Mask foregroundOf(const Image& rgb, const View& view, double noise)
{
  const int W = rgb.width, H = rgb.height;
  const double tol = std::max(3.5 / 255.0, 4.0 * noise);
  Mask foreground(W, H);
  for (int y = 0; y < H; ++y)
  {
    const auto bgc = view.backgroundAt(y);
    for (int x = 0; x < W; ++x)
    {
      const float* p = &rgb.pixels[3 * (static_cast<size_t>(y) * W + x)];
      double d = 0;
      for (int c = 0; c < 3; ++c)
        d = std::max(d, std::abs(p[c] - bgc[static_cast<size_t>(c)]));
      foreground(x, y) = d > tol;
    }
  }
  return foreground;
}

std::vector<char> smallParts(const std::vector<int>& area, double fraction)
{
  std::vector<char> small(area.size(), 0);
  if (area.empty())
    return small;
  const int largest = *std::max_element(area.begin(), area.end());
  for (size_t k = 0; k < area.size(); ++k)
    small[k] = area[k] < fraction * largest;
  return small;
}

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

double tailLoss(const ReconstructionResult& r)
{
  const size_t tail = std::min<size_t>(10, r.loss.size());
  double loss = 0;
  for (size_t k = r.loss.size() - tail; k < r.loss.size(); ++k)
    loss += r.loss[k] / static_cast<double>(tail);
  return loss;
}

// --- silhouettes of the volume -------------------------------------------------------------

Moments moments(const Mask& m, const Mask* care)
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

std::vector<double> alignmentTurns(const Moments& mt, const Moments& mr)
{
  std::vector<double> rhos{ mt.angle - mr.angle, mt.angle - mr.angle + M_PI };
  if (mt.anisotropy < 1.3 || mr.anisotropy < 1.3)
    for (int k = 0; k < 12; ++k)
      rhos.push_back(k * M_PI / 6);
  return rhos;
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

namespace
{
// Regions of smoothly varying colour in an RGB picture: 4-neighbours whose colours differ by at
// most `tol` in every channel are joined (a uniform background or ParaView's gradient is one
// region; text, widgets and frames split the rest): their areas and boxes {x0, y0, x1, y1}
// (inclusive).
void smoothRegions(
  const Image& rgb, double tol, std::vector<int>& area, std::vector<std::array<int, 4>>& box)
{
  const int w = rgb.width, h = rgb.height;
  std::vector<int> parent(static_cast<size_t>(w) * h);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int p)
  {
    while (parent[static_cast<size_t>(p)] != p)
      p = parent[static_cast<size_t>(p)] =
        parent[static_cast<size_t>(parent[static_cast<size_t>(p)])];
    return p;
  };
  auto near = [&](size_t a, size_t b)
  {
    for (int c = 0; c < 3; ++c)
      if (std::abs(rgb.pixels[3 * a + c] - rgb.pixels[3 * b + c]) > tol)
        return false;
    return true;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      const size_t p = static_cast<size_t>(y) * w + x;
      if (x + 1 < w && near(p, p + 1))
        parent[static_cast<size_t>(find(static_cast<int>(p)))] = find(static_cast<int>(p + 1));
      if (y + 1 < h && near(p, p + static_cast<size_t>(w)))
        parent[static_cast<size_t>(find(static_cast<int>(p)))] =
          find(static_cast<int>(p + static_cast<size_t>(w)));
    }
  std::vector<int> id(parent.size(), -1);
  area.clear();
  box.clear();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      const size_t p = static_cast<size_t>(y) * w + x;
      const auto root = static_cast<size_t>(find(static_cast<int>(p)));
      if (id[root] < 0)
      {
        id[root] = static_cast<int>(area.size());
        area.push_back(0);
        box.push_back({ x, y, x, y });
      }
      const int r = id[root];
      ++area[static_cast<size_t>(r)];
      auto& b = box[static_cast<size_t>(r)];
      b = { std::min(b[0], x), std::min(b[1], y), std::max(b[2], x), std::max(b[3], y) };
    }
}

// Whether a part of a picture over background `bg` holds a solid object.
bool holdsASolidObject(const Image& part, const PictureBackground& bg)
{
  View view;
  view.width = part.width;
  view.height = part.height;
  bg.applyTo(view);
  const Mask foreground = foregroundOf(part, view, bg.noise);
  std::vector<int> area;
  const std::vector<int> label = components(foreground, area);
  if (area.empty() || *std::max_element(area.begin(), area.end()) < 16)
    return false;
  const std::vector<char> small = smallParts(area, 0.2);
  Mask object(part.width, part.height);
  for (size_t i = 0; i < label.size(); ++i)
    object.m[i] = label[i] >= 0 && !small[static_cast<size_t>(label[i])];
  return solidShareOf(object) >= 0.25;
}

// Whether the box's border has one colour (or one gradient) and the box holds a solid object.
bool holdsARender(const Image& part)
{
  try
  {
    return holdsASolidObject(part, estimateBackground(part));
  }
  catch (const Error&)
  {
    return false;
  }
}

// Whether a filled rectangle's fill, on a page of colour `page`, is a render's background rather
// than a veil over the page (a TF that paints the air shows the volume's box as such a rectangle):
// a vertical gradient (ends 0.1 apart or more), or one colour (a gradient's mean when its ends are
// closer) within 0.06 of black, white or ParaView's palette grey-blue, and in either case at least
// 0.25 from the page (largest channel difference).
bool renderBackground(const PictureBackground& fill, const std::array<double, 3>& page)
{
  const auto apart = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::max({ std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2]) });
  };
  if (apart(fill.bottom, page) < 0.25 && apart(fill.top, page) < 0.25)
    return false;
  if (fill.gradient && apart(fill.bottom, fill.top) >= 0.1)
    return true;
  // one colour (a JPEG's shift of a few levels between top and bottom is no gradient)
  const std::array<double, 3> colour{ (fill.bottom[0] + fill.top[0]) / 2,
    (fill.bottom[1] + fill.top[1]) / 2, (fill.bottom[2] + fill.top[2]) / 2 };
  constexpr std::array<std::array<double, 3>, 3> backgrounds{ { { 0, 0, 0 }, { 1, 1, 1 },
    { 0.32, 0.34, 0.43 } } };
  return std::any_of(backgrounds.begin(), backgrounds.end(),
    [&](const std::array<double, 3>& c) { return apart(colour, c) <= 0.06; });
}

// A page of one colour (`page`, read in `small`) with a render pasted on it: the pasted render's
// inside {x, y, width, height} in `small`, or {} when the picture is no such page. A JPEG's
// ringing reaches `reach` pixels of `small` beyond the rectangle's edges.
std::optional<std::array<int, 4>> pastedRender(
  const Image& small, const PictureBackground& page, int reach)
{
  View view;
  view.width = small.width;
  view.height = small.height;
  page.applyTo(view);
  std::vector<int> area;
  const std::vector<int> label = components(foregroundOf(small, view, page.noise), area);
  if (area.empty() || page.gradient)
    return std::nullopt;
  const auto largest = static_cast<int>(std::max_element(area.begin(), area.end()) - area.begin());
  std::array<int, 4> b{ small.width, small.height, -1, -1 };
  for (size_t i = 0; i < label.size(); ++i)
    if (label[i] == largest)
    {
      const int x = static_cast<int>(i % static_cast<size_t>(small.width)),
                y = static_cast<int>(i / static_cast<size_t>(small.width));
      b = { std::min(b[0], x), std::min(b[1], y), std::max(b[2], x), std::max(b[3], y) };
    }
  const auto in = [&](int x, int y)
  { return label[static_cast<size_t>(y) * static_cast<size_t>(small.width) + x] == largest; };
  // a JPEG's ringing beside the rectangle's edges (within `reach`): rows and columns of the box
  // under 90 % in the part are trimmed off
  const auto share = [&](bool row, int i)
  {
    int n = 0;
    for (int j = row ? b[0] : b[1]; j <= (row ? b[2] : b[3]); ++j)
      n += row ? in(j, i) : in(i, j);
    return static_cast<double>(n) / (row ? b[2] - b[0] + 1 : b[3] - b[1] + 1);
  };
  for (int t = 0; t < reach && b[1] < b[3] && share(true, b[1]) < 0.9; ++t)
    ++b[1];
  for (int t = 0; t < reach && b[3] > b[1] && share(true, b[3]) < 0.9; ++t)
    --b[3];
  for (int t = 0; t < reach && b[0] < b[2] && share(false, b[0]) < 0.9; ++t)
    ++b[0];
  for (int t = 0; t < reach && b[2] > b[0] && share(false, b[2]) < 0.9; ++t)
    --b[2];
  const int bw = b[2] - b[0] + 1, bh = b[3] - b[1] + 1;
  long filled = 0;
  for (int y = b[1]; y <= b[3]; ++y)
    for (int x = b[0]; x <= b[2]; ++x)
      filled += in(x, y);
  // a filled rectangle (its edge pixels mixed with the page) of a tenth of the page or more
  if (bw < 18 || bh < 18 || filled < 0.97 * bw * bh ||
    (bw >= small.width - 2 && bh >= small.height - 2) || bw * bh < 0.1 * small.width * small.height)
    return std::nullopt;
  // inside its edge (mixed with the page) and a JPEG's strongest ringing: 2 pixels in
  const std::array<int, 4> inside{ b[0] + 2, b[1] + 2, bw - 4, bh - 4 };
  const Image pasted = cropTo(small, inside);
  PictureBackground fill;
  try
  {
    fill = estimateBackground(pasted);
  }
  catch (const Error&)
  {
    return std::nullopt;
  }
  if (!renderBackground(fill, page.bottom) || !holdsASolidObject(pasted, fill))
    return std::nullopt;
  return inside;
}

// A picture that is neither a page with a render pasted on it nor a window: the whole of it, or,
// for a render cut from a JPEG at (or just inside) its edge, where the blocks beside the cut ring
// with the colour cut off (a figure's page), the part inside that ringing. Read at the picture's
// own resolution, as the match reads it (a halved reading averages the ringing away): whole when
// its border has one colour, else inside the first border inset by up to a JPEG block (8 pixels)
// that has one colour and holds a render; whole when none does.
std::array<int, 4> insideJpegRinging(const Image& img)
{
  const int w = img.width, h = img.height;
  Image opaque;
  const Image& rgb = img.channels == 3 ? img : (opaque = toChannels(img, 3));
  try
  {
    estimateBackground(rgb);
    return { 0, 0, w, h };
  }
  catch (const Error&)
  {
  }
  for (int t = 1; t <= 8 && w - 2 * t >= 16 && h - 2 * t >= 16; ++t)
  {
    const std::array<int, 4> inset{ t, t, w - 2 * t, h - 2 * t };
    if (holdsARender(cropTo(rgb, inset)))
      return inset;
  }
  return { 0, 0, w, h };
}
} // namespace

Image cropTo(const Image& img, const std::array<int, 4>& part)
{
  if (part[0] == 0 && part[1] == 0 && part[2] == img.width && part[3] == img.height)
    return img;
  Image inside(part[2], part[3], img.channels);
  for (int y = 0; y < inside.height; ++y)
    std::copy_n(
      &img.pixels[(static_cast<size_t>(y + part[1]) * img.width + part[0]) * img.channels],
      static_cast<size_t>(inside.width) * img.channels,
      &inside.pixels[static_cast<size_t>(y) * inside.width * img.channels]);
  return inside;
}

std::array<int, 4> renderView(const Image& img)
{
  const int w = img.width, h = img.height;
  const std::array<int, 4> whole{ 0, 0, w, h };
  if (img.channels < 3 || w < 16 || h < 16)
    return whole;
  if (img.channels == 4) // a picture saved with transparency is a render, not a window's grab
    for (size_t i = 3; i < img.pixels.size(); i += 4)
      if (img.pixels[i] < 254.5f / 255.0f)
        return whole;
  // read at most 512 a side: a pixel (x, y) there is the average of [x 2^k, (x + 1) 2^k) here
  Image held;
  if (img.channels != 3)
    held = shrinkPicture(toChannels(img, 3), 512);
  const Image& small = img.channels == 3 ? shrinkPicture(img, 512, held) : held;
  int k = 0;
  while ((w >> k) > small.width)
    ++k;
  // a pixel of `small`'s box mapped back to the picture's pixels it was halved from
  const auto full = [&](const std::array<int, 4>& b)
  {
    return std::array<int, 4>{ b[0] << k, b[1] << k, std::min(b[2] << k, w - (b[0] << k)),
      std::min(b[3] << k, h - (b[1] << k)) };
  };
  std::optional<PictureBackground> page;
  try
  {
    page = estimateBackground(small);
  }
  catch (const Error&)
  {
  }
  if (page)
  {
    // one background colour: the picture is the render, or a figure: a page with a render
    // pasted on it (when that is a letterbox's inside, letterbox finds it to the pixel)
    // a JPEG rings up to a block (8 pixels) from an edge
    const std::optional<std::array<int, 4>> inside =
      pastedRender(small, *page, std::max(2, 8 >> k));
    if (!inside)
      return insideJpegRinging(img);
    const std::array<int, 4> pasted = full(*inside), band = letterbox(img);
    // the reading lies 2 read pixels in, each edge's read pixel partly outside: within 4 of them
    const int slack = 4 << k;
    const bool same = std::abs(band[0] - pasted[0]) <= slack &&
      std::abs(band[1] - pasted[1]) <= slack &&
      std::abs(band[0] + band[2] - pasted[0] - pasted[2]) <= slack &&
      std::abs(band[1] + band[3] - pasted[1] - pasted[3]) <= slack;
    return same ? whole : pasted;
  }
  const int sw = small.width, sh = small.height;
  std::vector<int> area;
  std::vector<std::array<int, 4>> box;
  smoothRegions(small, 3.0 / 255.0, area, box);
  long best = 0;
  std::array<int, 4> view = whole;
  for (size_t r = 0; r < area.size(); ++r)
  {
    const auto& b = box[r];
    const int bw = b[2] - b[0] + 1, bh = b[3] - b[1] + 1;
    // a window's render view lies inside its panels and frame: a region reaching the picture's
    // edge is the picture's own (a render cut by the frame, its haze over the volume's box)
    if (area[r] <= best || area[r] < 0.02 * sw * sh || area[r] < 0.3 * bw * bh || bw < 16 ||
      bh < 16 || b[0] == 0 || b[1] == 0 || b[2] == sw - 1 || b[3] == sh - 1)
      continue;
    if (!holdsARender(cropTo(small, { b[0], b[1], bw, bh })))
      continue;
    best = area[r];
    view = full({ b[0], b[1], bw, bh });
  }
  return best > 0 ? view : insideJpegRinging(img);
}

std::array<int, 4> renderedPart(const Image& img)
{
  // a window's panels and status bar can pass for a letterbox's bands: its view is looked for
  // first
  const std::array<int, 4> view = renderView(img);
  return view[2] < img.width || view[3] < img.height ? view : letterbox(img);
}

Image insideRenderedPart(const Image& img, std::array<int, 4>& crop)
{
  crop = renderedPart(img);
  return cropTo(img, crop);
}

double solidShareOf(const Mask& object)
{
  int x0 = object.w, y0 = object.h, x1 = -1, y1 = -1;
  long count = 0;
  for (int y = 0; y < object.h; ++y)
    for (int x = 0; x < object.w; ++x)
      if (object(x, y))
      {
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        ++count;
      }
  if (count == 0)
    return 0;
  const int r = static_cast<int>(std::lround(0.02 * std::max(x1 - x0 + 1, y1 - y0 + 1)));
  if (r < 1)
    return 1;
  Mask outside(object.w, object.h);
  for (size_t i = 0; i < object.m.size(); ++i)
    outside.m[i] = !object.m[i];
  const Mask near = dilate(outside, r);
  long deep = 0;
  for (size_t i = 0; i < object.m.size(); ++i)
    deep += object.m[i] && !near.m[i];
  return static_cast<double>(deep) / count;
}

} // namespace matchparts
} // namespace ddg
