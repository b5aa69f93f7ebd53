// MatchBackground.cxx: a picture's background, uniform or ParaView's gradient (Match.h).
#include "Reconstruct/Match.h"

#include "Common/Error.h"
#include "Reconstruct/MatchParts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

namespace ddg
{

void PictureBackground::applyTo(View& view) const
{
  view.background = bottom;
  if (gradient)
    view.background2 = top;
  else
    view.background2.reset();
}

PictureBackground estimateBackground(const Image& picture)
{
  using matchparts::median;
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

// --- a reconstruction target's background ---------------------------------------------------

namespace
{
std::string colourText(const std::array<double, 3>& c)
{
  char text[64];
  std::snprintf(text, sizeof(text), "(%.3f %.3f %.3f)", c[0], c[1], c[2]);
  return text;
}

std::string backgroundText(const PictureBackground& bg)
{
  return bg.gradient
    ? "a gradient from " + colourText(bg.bottom) + " (bottom) to " + colourText(bg.top) + " (top)"
    : colourText(bg.bottom);
}

/// The largest difference per channel between two backgrounds (bottom and top rows).
double backgroundDifference(const PictureBackground& a, const PictureBackground& b)
{
  double d = 0;
  for (int c = 0; c < 3; ++c)
    d = std::max({ d, std::abs(a.bottom[c] - b.bottom[c]), std::abs(a.top[c] - b.top[c]) });
  return d;
}

PictureBackground viewBackground(const View& view)
{
  PictureBackground bg;
  bg.bottom = view.background;
  bg.gradient = view.background2.has_value();
  bg.top = view.background2 ? *view.background2 : view.background;
  return bg;
}
} // namespace

TargetBackground targetBackground(
  const Image& picture, const View& view, const std::optional<std::array<double, 3>>& given)
{
  std::optional<PictureBackground> border;
  try
  {
    border = estimateBackground(picture);
  }
  catch (const Error&)
  {
    // no one colour on the border (the object is cut by the frame): nothing to check against
  }
  TargetBackground out;
  const auto agrees = [&](const PictureBackground& stated)
  { return backgroundDifference(*border, stated) <= std::max(6.0 / 255.0, 3.0 * border->noise); };
  if (given)
  {
    out.source = "given";
    out.background.bottom = out.background.top = *given;
    if (border && !agrees(out.background))
      out.warning = "the picture's border is " + backgroundText(*border) +
        ", not the given background " + colourText(*given);
    return out;
  }
  out.background = viewBackground(view);
  out.source = "view";
  if (border && !agrees(out.background))
  {
    out.warning = "the picture's border is " + backgroundText(*border) +
      ", the view's background " + backgroundText(out.background) +
      ": the picture's is used (state the background to override)";
    out.background = *border;
    out.source = "picture";
  }
  return out;
}

} // namespace ddg
