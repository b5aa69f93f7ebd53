// CarryLook.cxx: another volume's picture -> this volume's TF with its look (CarryLook.h).
#include "Reconstruct/CarryLook.h"

#include "Common/Error.h"
#include "Image/ImageMetrics.h"
#include "Reconstruct/MatchParts.h"
#include "Render/PieceExchange.h"
#include "TransferFunction/ColorSpace.h"
#include "Volume/VolumeBrick.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>

namespace ddg
{
namespace
{
using Lab = std::array<double, 3>;

// k-means of Lab colours into k clusters started at lightness quantiles; returns the centres
// ordered by lightness and each one's share of the colours; `member` gets each colour's
// cluster (in that order).
std::vector<std::pair<Lab, double>> lightnessClusters(
  const std::vector<Lab>& colours, int k, std::vector<int>& member)
{
  std::vector<Lab> sorted = colours;
  std::sort(sorted.begin(), sorted.end(), [](const Lab& a, const Lab& b) { return a[0] < b[0]; });
  std::vector<Lab> centre(static_cast<size_t>(k));
  for (int c = 0; c < k; ++c)
    centre[static_cast<size_t>(c)] = sorted[std::min(
      sorted.size() - 1, static_cast<size_t>((c + 0.5) / k * static_cast<double>(sorted.size())))];
  member.assign(colours.size(), 0);
  for (int round = 0; round < 20; ++round)
  {
    for (size_t i = 0; i < colours.size(); ++i)
    {
      double best = 1e300;
      for (int c = 0; c < k; ++c)
      {
        double d = 0;
        for (int a = 0; a < 3; ++a)
          d += (colours[i][a] - centre[static_cast<size_t>(c)][a]) *
            (colours[i][a] - centre[static_cast<size_t>(c)][a]);
        if (d < best)
        {
          best = d;
          member[i] = c;
        }
      }
    }
    std::vector<Lab> sum(static_cast<size_t>(k), Lab{ 0, 0, 0 });
    std::vector<double> count(static_cast<size_t>(k), 0);
    for (size_t i = 0; i < colours.size(); ++i)
    {
      for (int a = 0; a < 3; ++a)
        sum[static_cast<size_t>(member[i])][a] += colours[i][a];
      count[static_cast<size_t>(member[i])] += 1;
    }
    for (int c = 0; c < k; ++c)
      if (count[static_cast<size_t>(c)] > 0)
        for (int a = 0; a < 3; ++a)
          centre[static_cast<size_t>(c)][a] =
            sum[static_cast<size_t>(c)][a] / count[static_cast<size_t>(c)];
  }
  std::vector<int> order(static_cast<size_t>(k));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
    [&](int a, int b)
    { return centre[static_cast<size_t>(a)][0] < centre[static_cast<size_t>(b)][0]; });
  std::vector<int> rank(static_cast<size_t>(k));
  std::vector<std::pair<Lab, double>> out;
  for (int r = 0; r < k; ++r)
  {
    const int c = order[static_cast<size_t>(r)];
    rank[static_cast<size_t>(c)] = r;
    out.push_back({ centre[static_cast<size_t>(c)],
      static_cast<double>(std::count(member.begin(), member.end(), c)) / colours.size() });
  }
  for (int& m : member)
    m = rank[static_cast<size_t>(m)];
  return out;
}

// A cluster's material colour: its pixels are the material over the background at various
// opacities (c = a m + (1 - a) b), so the colour is taken along the mean direction away from
// the background, as far as the cluster's 90th percentile of distance reaches (RGB).
RGB unmixed(const std::vector<std::array<double, 6>>& pixels)
{
  if (pixels.empty())
    return { 0.5, 0.5, 0.5 };
  std::array<double, 3> c{ 0, 0, 0 }, b{ 0, 0, 0 };
  std::vector<double> d;
  double mean = 0;
  for (const auto& p : pixels)
  {
    double dd = 0;
    for (int a = 0; a < 3; ++a)
    {
      c[a] += p[a] / pixels.size();
      b[a] += p[3 + a] / pixels.size();
      dd += (p[a] - p[3 + a]) * (p[a] - p[3 + a]);
    }
    d.push_back(std::sqrt(dd));
    mean += d.back() / pixels.size();
  }
  std::nth_element(d.begin(), d.begin() + static_cast<long>(0.9 * (d.size() - 1)), d.end());
  const double far = d[static_cast<size_t>(0.9 * (d.size() - 1))];
  const double scale = mean > 1e-6 ? std::max(1.0, far / mean) : 1.0;
  RGB m;
  for (int a = 0; a < 3; ++a)
    m[a] = std::clamp(b[a] + scale * (c[a] - b[a]), 0.0, 1.0);
  return m;
}

// The volume's feature regions (findFeatureRegions); over pieces of a volume, from the whole's
// histogram: each piece counts the points it owns once (the shared planes of neighbours go to
// the piece above, the whole's last plane to the piece that reaches it), the counts are summed.
std::vector<FeatureRegion> featureRegionsOf(const DifferentiableRenderer& renderer, int maxRegions)
{
  const VolumeBrick* brick = renderer.brick();
  if (!brick)
    return findFeatureRegions(renderer.caster().volume(), maxRegions);
  const auto range = renderer.dataRange();
  std::vector<double> counts(256, 0.0);
  if (!brick->ownsNothing())
  {
    std::array<int, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = brick->ownedMin[a] - brick->offset[a];
      hi[a] = (brick->ownedMax[a] == brick->wholeDims[a] - 1 ? brick->ownedMax[a]
                                                             : brick->ownedMax[a] - 1) -
        brick->offset[a];
    }
    counts = valueCounts(renderer.caster().volume(), range, lo, hi);
  }
  const PieceExchange& exchange = *renderer.exchange();
  // counts exact in float up to 2^24 per bin: larger pieces send the high and low parts
  std::vector<float> mine(2 * counts.size());
  for (size_t b = 0; b < counts.size(); ++b)
  {
    const double high = std::floor(counts[b] / 16777216.0);
    mine[2 * b] = static_cast<float>(high);
    mine[2 * b + 1] = static_cast<float>(counts[b] - high * 16777216.0);
  }
  std::vector<float> all(mine.size() * static_cast<size_t>(exchange.pieces()));
  exchange.allGather(mine.data(), static_cast<std::int64_t>(mine.size()), all.data());
  std::fill(counts.begin(), counts.end(), 0.0);
  for (int p = 0; p < exchange.pieces(); ++p)
    for (size_t b = 0; b < counts.size(); ++b)
    {
      const float* q = all.data() + static_cast<size_t>(p) * mine.size() + 2 * b;
      counts[b] += static_cast<double>(q[0]) * 16777216.0 + static_cast<double>(q[1]);
    }
  return findFeatureRegions(counts, range, maxRegions);
}

// How well the volume's silhouettes take the shape of the picture's object (its filled
// silhouette): the best IoU over directions (elevation -60..60 by 30 x azimuth by 30, and the
// poles) and occupancy levels, each silhouette aligned with the object by moments (centroid,
// area, principal axis; 12 turns for round shapes): the camera search's first stage (Match.cxx).
double shapeAgreementOf(const DifferentiableRenderer& renderer, const matchparts::Mask& object)
{
  using namespace matchparts;
  const SilhouetteModel model(renderer);
  if (model.levels() == 0)
    return 0;
  const double sf = 128.0 / std::max(object.w, object.h);
  const int sw = std::max(8, static_cast<int>(std::lround(object.w * sf))),
            sh = std::max(8, static_cast<int>(std::lround(object.h * sf)));
  const Mask target = fillHoles(shrink(object, sw, sh));
  Mask care(sw, sh);
  std::fill(care.m.begin(), care.m.end(), std::uint8_t{ 1 });
  const Moments mt = moments(target, &care);
  if (mt.area < 4)
    return 0;
  const View start = defaultView(renderer.bounds(), sw, sh);
  std::vector<std::pair<double, double>> directions{ { 0, 89 }, { 0, -89 } };
  for (double el = -60; el <= 60; el += 30)
    for (double az = -180; az < 180; az += 30)
      directions.emplace_back(az, el);
  double best = 0;
  Mask rendered;
  for (const auto& [az, el] : directions)
    for (int level = 0; level < model.levels(); ++level)
    {
      model.render(cameraMove(start, az, el, 0, 1, { 0, 0 }), level, sw, sh, rendered);
      const Moments mr = moments(rendered);
      if (mr.area < 4)
        continue;
      const double scale = std::sqrt(mt.area / mr.area);
      for (double rho : alignmentTurns(mt, mr))
        best = std::max(
          best, similarityIoU(target, care, rendered, mr.cx, mr.cy, mt.cx, mt.cy, rho, scale));
    }
  return best;
}

// The colour distance of the TF `start` describes (its initialPrimitives, or its initial1D for
// free bins) over the targets (fixed directions: comparable figures).
double distanceOf(const DifferentiableRenderer& renderer, const std::vector<ColourTarget>& targets,
  ReconstructionOptions start)
{
  start.iterations = 1;
  start.learningRate = 1e-12;
  start.directions = 256;
  start.directionPool = 0; // fresh directions: the same measure whatever the fit drew from
  start.seed = 1;
  start.colourPlacement = 0; // the colours alone: comparable with and without placement
  return reconstructFromColours(renderer, targets, start).loss.front();
}
std::string linesOrText(double solidShare)
{
  return "the picture shows lines or text, not a rendered volume (" +
    std::to_string(static_cast<int>(std::lround(100 * solidShare))) + " % of its content is solid)";
}
} // namespace

PictureObject readPictureObject(const Image& input)
{
  using namespace matchparts;
  if (input.channels < 3 || input.width < 16 || input.height < 16)
    throw Error("the picture must be RGB or RGBA and at least 16 x 16 pixels");
  PictureObject r;
  // RGB over black, inside its letterbox and, in a window's screenshot, its render view (the
  // bands and the panels are not the picture's background: matchparts::renderedPart); a large
  // picture halved by 2 x 2 box averages until it is at most 512 on its longer side (colours,
  // not detail, count), or its shorter side under 32 (a strip stays wider than 512), without a
  // filtered resize: OpenImageIO's took 130-200 ms for an 800 x 600 or 1000 x 700 picture
  std::array<int, 4> crop{};
  const Image inside = insideRenderedPart(input, crop);
  r.picture = shrinkPicture(
    inside.channels == 4 ? compositeOverBackground(inside, { 0, 0, 0 }) : toChannels(inside, 3),
    512);
  const int W = r.picture.width, H = r.picture.height;
  r.background = estimateBackground(r.picture);
  View pv;
  pv.width = W;
  pv.height = H;
  r.background.applyTo(pv);
  const Mask foreground = foregroundOf(r.picture, pv, r.background.noise);
  std::vector<int> area;
  const std::vector<int> label = components(foreground, area);
  if (area.empty() || *std::max_element(area.begin(), area.end()) < 16)
    throw Error("the picture shows nothing but its background colour");
  const std::vector<char> small = smallParts(area, 0.2);
  r.object.assign(label.size(), 0);
  r.overlay.assign(label.size(), 0);
  long left = 0, total = 0;
  Mask objectMask(W, H);
  for (size_t i = 0; i < label.size(); ++i)
  {
    if (label[i] < 0)
      continue;
    ++total;
    const bool isOverlay = small[static_cast<size_t>(label[i])] != 0;
    r.overlay[i] = isOverlay ? 1 : 0;
    r.object[i] = objectMask.m[i] = isOverlay ? 0 : 1;
    left += isOverlay ? 1 : 0;
  }
  r.overlayShare = static_cast<double>(left) / total;
  r.solidShare = solidShareOf(objectMask);
  return r;
}

std::string checkQueryPicture(const Image& picture, double minimumSolidShare)
{
  PictureObject seen;
  try
  {
    seen = readPictureObject(picture);
  }
  catch (const Error& e)
  {
    // no one background colour (a photograph, or an object cut by the frame: a query may be of
    // a crop), or too little showing to tell: answered, with the reason
    return std::string("the picture cannot be read as a rendered volume (") + e.what() +
      "): the design is a guess";
  }
  if (seen.solidShare < minimumSolidShare)
    throw Error(linesOrText(seen.solidShare) + ": there is nothing to query with");
  return {};
}

CarryLookResult carryLook(const DifferentiableRenderer& renderer, const Image& input,
  const CarryLookOptions& opt, const ReconstructionProgress& progress)
{
  using namespace matchparts;
  const auto t0 = std::chrono::steady_clock::now();
  if (opt.size < 16 || opt.views.empty() || opt.maxRegions < 1)
    throw Error("carrying a look needs renders of at least 16 pixels, a view and a region");
  CarryLookResult result;
  // 1. background, foreground, overlays
  PictureObject seen;
  try
  {
    seen = readPictureObject(input);
  }
  catch (const Error& e)
  {
    throw Error(std::string(e.what()) + ": there is no look to carry");
  }
  const Image& picture = seen.picture;
  const int W = picture.width, H = picture.height;
  result.background = seen.background;
  result.overlayShare = seen.overlayShare;
  View pv;
  pv.width = W;
  pv.height = H;
  result.background.applyTo(pv);
  if (seen.solidShare < opt.minimumSolidShare)
    throw Error(linesOrText(seen.solidShare) + ": there is no look to carry");
  Image overlay(W, H, 1);
  Mask objectMask(W, H);
  std::vector<Lab> object;
  std::vector<std::array<double, 6>> objectRGB; // colour, background behind it
  for (size_t i = 0; i < seen.object.size(); ++i)
  {
    overlay.pixels[i] = seen.overlay[i];
    objectMask.m[i] = seen.object[i];
    if (!seen.object[i])
      continue;
    const RGB c{ picture.pixels[3 * i], picture.pixels[3 * i + 1], picture.pixels[3 * i + 2] };
    object.push_back(rgbToLab(c));
    const auto bg = pv.backgroundAt(static_cast<int>(i / static_cast<size_t>(W)));
    objectRGB.push_back({ c[0], c[1], c[2], bg[0], bg[1], bg[2] });
  }
  // 2. the picture's colours
  std::vector<float> radii;
  const auto colours = framedColours(picture, pv, overlay, &radii);
  // 3. regions by value, matched with colour clusters by lightness
  std::vector<FeatureRegion> regions = featureRegionsOf(renderer, opt.maxRegions);
  if (regions.empty())
    throw Error("the volume has no feature regions to carry a look onto");
  std::sort(regions.begin(), regions.end(),
    [](const FeatureRegion& a, const FeatureRegion& b) { return a.peak < b.peak; });
  std::vector<int> member;
  const auto clusters = lightnessClusters(object, static_cast<int>(regions.size()), member);
  std::vector<GaussianPrimitive> start;
  for (size_t k = 0; k < regions.size(); ++k)
  {
    RGB rgb = labToRgb(clusters[k].first);
    if (opt.unmix)
    {
      std::vector<std::array<double, 6>> pixels;
      for (size_t i = 0; i < member.size(); ++i)
        if (member[i] == static_cast<int>(k))
          pixels.push_back(objectRGB[i]);
      rgb = unmixed(pixels);
    }
    result.regions.push_back({ regions[k], { rgb[0], rgb[1], rgb[2] }, clusters[k].second });
    GaussianPrimitive g = basePrimitive(regions[k]);
    g.rgb = { std::clamp(rgb[0], 0.0, 1.0), std::clamp(rgb[1], 0.0, 1.0),
      std::clamp(rgb[2], 0.0, 1.0) };
    g.opacity = opt.startOpacity;
    start.push_back(g);
  }
  // 4. the fit at the volume's views over the picture's background
  std::vector<ColourTarget> targets;
  for (const auto& [azimuth, elevation] : opt.views)
  {
    ColourTarget t;
    t.view = orbitView(renderer.bounds(), opt.size, azimuth, elevation, 1.0);
    result.background.applyTo(t.view);
    t.view.lighting = opt.lighting;
    t.colours = colours;
    t.radii = radii;
    targets.push_back(std::move(t));
  }
  ReconstructionOptions fit = opt.fit;
  fit.twoD = false;
  // the volume's air (values under its lowest feature region) stays clear
  fit.transparentBelow = std::min_element(regions.begin(), regions.end(),
    [](const FeatureRegion& a, const FeatureRegion& b) {
      return a.lo < b.lo;
    })->lo;
  if (fit.initial1D) // from the caller's TF (a query's design): free bins; regions reported
  {
    fit.primitives = 0;
    fit.initialPrimitives.clear();
  }
  else
  {
    fit.primitives = static_cast<int>(start.size());
    fit.initialPrimitives = start;
  }
  result.shapeAgreement = shapeAgreementOf(renderer, objectMask);
  result.shapesAgree = result.shapeAgreement >= opt.minimumShapeAgreement;
  result.fit = reconstructFromColours(renderer, targets, fit, progress);
  result.distanceStart = distanceOf(renderer, targets, fit);
  ReconstructionOptions end = fit;
  if (fit.primitives > 0)
    end.initialPrimitives = result.fit.primitives;
  else
    end.initial1D = result.fit.table1D;
  result.distanceEnd = distanceOf(renderer, targets, end);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

void carryLookFrom(
  CarryLookOptions& options, const TransferFunction1D& tf, const std::array<double, 2>& range)
{
  options.fit.initial1D = bakeTable(tf, range[0], range[1], 1024);
}

View carriedLookView(const std::array<double, 6>& bounds, const CarryLookResult& result,
  const CarryLookOptions& options, int size)
{
  if (options.views.empty())
    throw Error("carrying a look needs a view");
  View view = orbitView(bounds, size, options.views[0][0], options.views[0][1], 1.0);
  result.background.applyTo(view);
  view.lighting = options.lighting;
  return view;
}

} // namespace ddg
