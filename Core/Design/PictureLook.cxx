// PictureLook.cxx: users' pictures drawn from a design's render — frame, camera moves,
// background, overlays, JPEG.
#include "Design/PictureLook.h"

#include "Common/Error.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace ddg
{
namespace
{
// ParaView 5.11's palette background and its default gradient's top (Background2)
constexpr std::array<double, 3> kPalette{ 0.32, 0.34, 0.43 };
constexpr std::array<double, 3> kPaletteTop{ 0.0, 0.0, 0.16 };

using Colour = std::array<double, 3>;

// Pixels drawn on an RGB image (values in [0, 1]); outside the image: nothing.
class Canvas
{
public:
  explicit Canvas(Image& image)
    : Img(image)
  {
  }

  void put(int x, int y, const Colour& c)
  {
    if (x < 0 || y < 0 || x >= Img.width || y >= Img.height)
      return;
    for (int k = 0; k < 3; ++k)
      Img.at(x, y, k) = static_cast<float>(c[k]);
  }

  void square(int x, int y, int side, const Colour& c)
  {
    for (int dy = 0; dy < side; ++dy)
      for (int dx = 0; dx < side; ++dx)
        put(x - side / 2 + dx, y - side / 2 + dy, c);
  }

  void line(double x0, double y0, double x1, double y1, int thick, const Colour& c)
  {
    const int steps = std::max(1, static_cast<int>(std::ceil(std::hypot(x1 - x0, y1 - y0) * 2)));
    for (int s = 0; s <= steps; ++s)
    {
      const double t = static_cast<double>(s) / steps;
      square(static_cast<int>(std::lround(x0 + t * (x1 - x0))),
        static_cast<int>(std::lround(y0 + t * (y1 - y0))), thick, c);
    }
  }

  // A glyph: a 3 x 5 cell pattern (about half the cells on), cells of `cell` pixels, its top
  // left at (x, y). Returns the advance.
  int glyph(int x, int y, int cell, const Colour& c, std::mt19937_64& rng)
  {
    std::uint32_t bits = static_cast<std::uint32_t>(rng()) & 0x7FFF;
    if (bits == 0)
      bits = 0x5A5A;
    for (int r = 0; r < 5; ++r)
      for (int q = 0; q < 3; ++q)
        if (bits & (1u << (3 * r + q)))
          for (int dy = 0; dy < cell; ++dy)
            for (int dx = 0; dx < cell; ++dx)
              put(x + q * cell + dx, y + r * cell + dy, c);
    return 4 * cell;
  }

  void text(int x, int y, int glyphs, int cell, const Colour& c, std::mt19937_64& rng)
  {
    for (int g = 0; g < glyphs; ++g)
      x += (rng() % 7 == 0) ? 4 * cell : glyph(x, y, cell, c, rng); // some spaces
  }

private:
  Image& Img;
};

Colour legendAt(const std::vector<Colour>& legend, double t)
{
  static const std::vector<Colour> coolWarm{ { 0.23, 0.30, 0.75 }, { 0.87, 0.87, 0.87 },
    { 0.71, 0.02, 0.15 } };
  const auto& l = legend.empty() ? coolWarm : legend;
  if (l.size() == 1)
    return l[0];
  const double x = std::clamp(t, 0.0, 1.0) * (l.size() - 1);
  const size_t i = std::min(static_cast<size_t>(x), l.size() - 2);
  const double f = x - i;
  Colour c;
  for (int k = 0; k < 3; ++k)
    c[k] = l[i][k] + f * (l[i + 1][k] - l[i][k]);
  return c;
}
} // namespace

PictureLook samplePictureLook(std::mt19937_64& rng, int size)
{
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto in = [&](double lo, double hi) { return lo + (hi - lo) * u(rng); };
  PictureLook k;
  k.height = 2 * size;
  const double pick = u(rng);
  const double aspect = pick < 0.15 ? 1.0 : pick < 0.6 ? 4.0 / 3 : pick < 0.8 ? 1.6 : 16.0 / 9;
  k.width = static_cast<int>(std::lround(k.height * aspect));
  k.roll = in(-30, 30);
  k.panRight = in(-0.08, 0.08);
  k.panUp = in(-0.08, 0.08);
  k.zoom = in(0.8, 1.25);
  auto colour = [&] { return Colour{ u(rng), u(rng), u(rng) }; };
  const double b = u(rng);
  if (b < 0.25)
    k.background = kPalette;
  else if (b < 0.4)
    k.background = { 0, 0, 0 };
  else if (b < 0.55)
    k.background = { 1, 1, 1 };
  else if (b < 0.75)
    k.background = colour();
  else if (u(rng) < 0.5)
  {
    k.background = kPalette;
    k.background2 = kPaletteTop;
  }
  else
  {
    k.background = colour();
    k.background2 = colour();
  }
  k.axes = u(rng) < 0.5;
  k.scalarBar = u(rng) < 0.3;
  k.text = u(rng) < 0.3;
  k.jpegQuality = u(rng) < 0.5 ? static_cast<int>(std::lround(in(50, 95))) : 0;
  k.seed = rng();
  return k;
}

View pictureView(const View& orbit, const PictureLook& look)
{
  View v = orbit;
  v.width = look.width;
  v.height = look.height;
  v.background = look.background;
  v.background2 = look.background2;
  Camera& c = v.camera;
  Eigen::Vector3d dir = c.focalPoint - c.position;
  double dist = dir.norm();
  dir /= dist;
  Eigen::Vector3d up = (c.viewUp - c.viewUp.dot(dir) * dir).normalized();
  Eigen::Vector3d right = dir.cross(up);
  const double r = look.roll * M_PI / 180;
  up = std::cos(r) * up + std::sin(r) * right;
  right = dir.cross(up);
  dist /= look.zoom;
  c.parallelScale /= look.zoom;
  const double half =
    c.parallelProjection ? c.parallelScale : dist * std::tan(0.5 * c.viewAngle * M_PI / 180);
  c.focalPoint += 2 * half * (look.panRight * right + look.panUp * up);
  c.position = c.focalPoint - dist * dir;
  c.viewUp = up;
  v.validate();
  return v;
}

Image drawPicture(
  const Image& render, const View& view, const PictureLook& look, const std::vector<Colour>& legend)
{
  if (render.width != view.width || render.height != view.height)
    throw Error("drawPicture: the render is not the picture view's size");
  Image img = look.background2 ? compositeOverBackground(render, look.background, *look.background2)
                               : compositeOverBackground(render, look.background);
  Canvas canvas(img);
  std::mt19937_64 rng(look.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int h = img.height, w = img.width;
  const double unit = h / 600.0; // ParaView's sizes, measured at a 600-pixel-high view
  const int cell = std::max(1, static_cast<int>(std::lround(2.5 * unit)));
  const Colour white{ 1, 1, 1 };
  if (look.axes)
  {
    // the orientation axes: X red, Y yellow, Z green from a point in the lower left, each along
    // its world axis as the camera projects it, the farthest drawn first
    const RayGenerator rays(view);
    const double ox = (70 + 20 * u(rng)) * unit, oy = h - (70 + 20 * u(rng)) * unit;
    const double length = (26 + 12 * u(rng)) * unit;
    const int thick = std::max(1, static_cast<int>(std::lround(2 * unit)));
    const Colour colours[3] = { { 0.9, 0.1, 0.1 }, { 0.9, 0.9, 0.1 }, { 0.0, 0.5, 0.0 } };
    int order[3] = { 0, 1, 2 };
    std::sort(
      order, order + 3, [&](int a, int b) { return rays.forward()[a] > rays.forward()[b]; });
    for (int a : order)
    {
      const double ex = ox + length * rays.right()[a], ey = oy - length * rays.up()[a];
      canvas.line(ox, oy, ex, ey, thick, colours[a]);
      canvas.square(static_cast<int>(ex), static_cast<int>(ey), 3 * thick, colours[a]);
      canvas.glyph(
        static_cast<int>(ex) + 2 * thick, static_cast<int>(ey) - 5 * cell, cell, white, rng);
    }
  }
  const Colour ink = u(rng) < 0.8 ? white : Colour{ 0, 0, 0 };
  if (look.scalarBar)
  {
    // a vertical legend on the right, low values at the bottom; a title and three labels
    const int bw = std::max(2, static_cast<int>(std::lround(0.03 * h)));
    const int bh = static_cast<int>(std::lround(0.33 * h));
    const int x0 = w - static_cast<int>(std::lround((0.12 + 0.06 * u(rng)) * h)) - bw;
    const int y0 = h - static_cast<int>(std::lround((0.05 + 0.15 * u(rng)) * h)) - bh;
    for (int y = 0; y < bh; ++y)
    {
      const Colour c = legendAt(legend, 1.0 - (y + 0.5) / bh);
      for (int x = 0; x < bw; ++x)
        canvas.put(x0 + x, y0 + y, c);
    }
    canvas.text(x0 - 2 * cell, y0 - 8 * cell, 5, cell, ink, rng);
    for (int l = 0; l < 3; ++l)
      canvas.text(x0 + bw + 2 * cell, y0 + l * (bh - 5 * cell) / 2, 3, cell, ink, rng);
  }
  if (look.text)
  {
    // one or two lines at the top, left or centred
    const int lines = 1 + static_cast<int>(u(rng) < 0.4);
    for (int l = 0; l < lines; ++l)
    {
      const int glyphs = 4 + static_cast<int>(rng() % 11);
      const int x = u(rng) < 0.5 ? 3 * cell : (w - glyphs * 4 * cell) / 2;
      canvas.text(x, 3 * cell + l * 7 * cell, glyphs, cell, ink, rng);
    }
  }
  return look.jpegQuality > 0 ? jpegRoundTrip(img, look.jpegQuality) : img;
}

std::string pictureLookToJson(const PictureLook& k)
{
  nlohmann::json j = { { "width", k.width }, { "height", k.height }, { "roll", k.roll },
    { "pan", { k.panRight, k.panUp } }, { "zoom", k.zoom }, { "background", k.background },
    { "axes", k.axes }, { "scalar_bar", k.scalarBar }, { "text", k.text },
    { "jpeg_quality", k.jpegQuality }, { "seed", k.seed } };
  if (k.background2)
    j["background2"] = *k.background2;
  return j.dump();
}

PictureLook parsePictureLook(const std::string& text, const std::string& origin)
{
  try
  {
    const auto j = nlohmann::json::parse(text);
    PictureLook k;
    k.width = j.at("width").get<int>();
    k.height = j.at("height").get<int>();
    k.roll = j.at("roll").get<double>();
    const auto pan = j.at("pan").get<std::array<double, 2>>();
    k.panRight = pan[0];
    k.panUp = pan[1];
    k.zoom = j.at("zoom").get<double>();
    k.background = j.at("background").get<Colour>();
    if (j.contains("background2"))
      k.background2 = j.at("background2").get<Colour>();
    k.axes = j.at("axes").get<bool>();
    k.scalarBar = j.at("scalar_bar").get<bool>();
    k.text = j.at("text").get<bool>();
    k.jpegQuality = j.at("jpeg_quality").get<int>();
    k.seed = j.at("seed").get<std::uint64_t>();
    if (k.width < 8 || k.height < 8 || !(k.zoom > 0) || k.jpegQuality < 0 || k.jpegQuality > 100)
      throw Error("out of range");
    return k;
  }
  catch (const std::exception& e)
  {
    throw Error(origin + ": a picture look is malformed: " + e.what());
  }
}

} // namespace ddg
