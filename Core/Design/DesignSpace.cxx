// DesignSpace.cxx: feature regions from the histogram, the spec, exemplar sampling.
#include "Design/DesignSpace.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <random>
#include <sstream>

namespace ddg
{

namespace
{
constexpr int kBins = 256;

// The 256-bin value histogram, its log-scaled smoothed version, and the first bin above air.
struct ValueHistogram
{
  std::vector<double> hist, smooth;
  int start = 0;    // first non-air bin
  double width = 0; // bin width in data values
};

double binWidth(const std::array<double, 2>& range)
{
  if (!(range[1] > range[0]))
  {
    throw Error("feature regions: the volume is constant");
  }
  return (range[1] - range[0]) / kBins;
}

// From the counts per bin (valueCounts).
ValueHistogram valueHistogram(const std::vector<double>& counts, const std::array<double, 2>& range)
{
  if (counts.size() != static_cast<size_t>(kBins))
    throw Error("feature regions: a value histogram has " + std::to_string(kBins) + " bins");
  ValueHistogram vh;
  vh.width = binWidth(range);
  auto& hist = vh.hist;
  auto& smooth = vh.smooth;
  hist = counts;
  smooth.assign(kBins, 0.0);
  const double total = std::max(1.0, std::accumulate(hist.begin(), hist.end(), 0.0));
  // log scale (small features matter), noise floor, smoothing
  std::vector<double> h(kBins);
  for (int i = 0; i < kBins; ++i)
  {
    const double f = hist[i] / total;
    h[i] = f < 1e-4 ? 0.0 : std::log10(f / 1e-4);
  }
  for (int i = 0; i < kBins; ++i)
  {
    double s = 0, w = 0;
    for (int k = -6; k <= 6; ++k)
    {
      const int j = i + k;
      if (j < 0 || j >= kBins)
        continue;
      const double g = std::exp(-0.5 * k * k / 4.0);
      s += g * h[j];
      w += g;
    }
    smooth[i] = s / w;
  }
  // air: the most frequent value in the lowest 40 % -> exclude it and everything below, up to
  // the first valley above it
  const int mode = static_cast<int>(std::max_element(hist.begin(), hist.end()) - hist.begin());
  int start = 0;
  if (mode < 0.4 * kBins)
  {
    start = mode;
    while (start + 1 < kBins && smooth[start + 1] >= smooth[start])
      ++start; // top of the smoothed air peak
    while (start + 1 < kBins && smooth[start + 1] <= smooth[start])
      ++start; // down to the valley
  }
  vh.start = start;
  return vh;
}

ValueHistogram valueHistogram(const Volume& volume)
{
  const auto& d = volume.dims();
  return valueHistogram(
    valueCounts(volume, volume.range(), { 0, 0, 0 }, { d[0] - 1, d[1] - 1, d[2] - 1 }),
    volume.range());
}
} // namespace

std::vector<double> valueCounts(const Volume& volume, const std::array<double, 2>& range,
  const std::array<int, 3>& lo, const std::array<int, 3>& hi)
{
  const double width = binWidth(range);
  std::vector<double> hist(kBins, 0.0);
  const auto& d = volume.dims();
  volume.visit(
    [&](const auto* p)
    {
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
        {
          const auto* row = p + (static_cast<std::int64_t>(k) * d[1] + j) * d[0];
          for (int i = lo[0]; i <= hi[0]; ++i)
          {
            const float v = static_cast<float>(row[i]);
            hist[std::clamp(static_cast<int>((v - range[0]) / width), 0, kBins - 1)] += 1.0;
          }
        }
    });
  return hist;
}

std::vector<FeatureRegion> findFeatureRegions(
  const Volume& volume, int maxRegions, const std::function<bool(FeatureRegion&)>& keep)
{
  const auto& d = volume.dims();
  return findFeatureRegions(
    valueCounts(volume, volume.range(), { 0, 0, 0 }, { d[0] - 1, d[1] - 1, d[2] - 1 }),
    volume.range(), maxRegions, keep);
}

std::vector<FeatureRegion> findFeatureRegions(const std::vector<double>& counts,
  const std::array<double, 2>& range, int maxRegions,
  const std::function<bool(FeatureRegion&)>& keep)
{
  const ValueHistogram vh = valueHistogram(counts, range);
  const auto& hist = vh.hist;
  const auto& smooth = vh.smooth;
  const int start = vh.start;
  const double width = vh.width;
  // peaks and their valleys
  struct Peak
  {
    int at, lo, hi;
    double prominence;
  };
  std::vector<Peak> peaks;
  for (int i = start; i < kBins; ++i)
  {
    const bool left = i == start || smooth[i] > smooth[i - 1];
    const bool right = i == kBins - 1 || smooth[i] >= smooth[i + 1];
    if (!left || !right || smooth[i] <= 0)
      continue;
    int lo = i, hi = i;
    while (lo > start && smooth[lo - 1] <= smooth[lo])
      --lo;
    while (hi < kBins - 1 && smooth[hi + 1] <= smooth[hi])
      ++hi;
    const double prom = smooth[i] - std::max(smooth[lo], smooth[hi]);
    peaks.push_back({ i, lo, hi, prom + 1e-6 * smooth[i] });
  }
  std::sort(peaks.begin(), peaks.end(),
    [](const Peak& a, const Peak& b) { return a.prominence > b.prominence; });
  double nonAir = 0;
  for (int i = start; i < kBins; ++i)
    nonAir += hist[i];
  std::vector<FeatureRegion> regions;
  for (const auto& p : peaks)
  {
    if (static_cast<int>(regions.size()) >= maxRegions)
      break;
    double regionMass = 0;
    for (int i = p.lo; i <= p.hi; ++i)
      regionMass += hist[i];
    if (nonAir > 0 && regionMass / nonAir < 0.005)
      continue; // noise
    FeatureRegion r;
    r.lo = range[0] + p.lo * width;
    r.hi = range[0] + (p.hi + 1) * width;
    r.peak = range[0] + (p.at + 0.5) * width;
    double mass = 0;
    for (int i = p.lo; i <= p.hi; ++i)
      mass += hist[i];
    r.mass = nonAir > 0 ? mass / nonAir : 0;
    if (keep && !keep(r))
      continue;
    regions.push_back(r);
  }
  if (regions.empty())
  {
    throw Error("feature regions: no histogram peak above the air and noise level");
  }
  std::sort(regions.begin(), regions.end(),
    [](const FeatureRegion& a, const FeatureRegion& b) { return a.peak < b.peak; });
  return regions;
}

std::vector<FeatureRegion> findFeatureRegions2D(
  const Volume& volume, int maxRegions, const std::function<bool(FeatureRegion&)>& keep)
{
  constexpr int V = 128, G = 64;
  const auto range = volume.range();
  const ValueHistogram vh = valueHistogram(volume);
  const double airCut = range[0] + vh.start * vh.width;
  const auto grad = volume.gradientMagnitude();
  // gradient axis up to the 99.5th percentile (a few extreme voxels would squeeze the rest)
  std::vector<float> sorted(grad);
  const size_t q = std::min(sorted.size() - 1, static_cast<size_t>(0.995 * sorted.size()));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(q), sorted.end());
  const double gmax = std::max(1e-6, static_cast<double>(sorted[q]));
  const double dv = (range[1] - range[0]) / V, dg = gmax / G;
  std::vector<double> hist(V * G, 0.0);
  double nonAir = 0;
  for (size_t i = 0; i < grad.size(); ++i)
  {
    const float value = volume.value(static_cast<std::int64_t>(i));
    if (value < airCut)
      continue;
    const int a = std::clamp(static_cast<int>((value - range[0]) / dv), 0, V - 1);
    const int b = std::clamp(static_cast<int>(grad[i] / dg), 0, G - 1);
    hist[b * V + a] += 1.0;
    nonAir += 1.0;
  }
  if (nonAir <= 0)
    throw Error("feature regions: nothing above the air level");
  // log density over a floor of 1e-5 of the non-air voxels, smoothed (separable Gaussian)
  std::vector<double> d(V * G), tmp(V * G);
  for (int k = 0; k < V * G; ++k)
  {
    const double f = hist[k] / nonAir;
    d[k] = f < 1e-5 ? 0.0 : std::log10(f / 1e-5);
  }
  auto blur = [&](bool alongValue)
  {
    for (int b = 0; b < G; ++b)
      for (int a = 0; a < V; ++a)
      {
        double sum = 0, w = 0;
        for (int k = -4; k <= 4; ++k)
        {
          const int aa = alongValue ? a + k : a, bb = alongValue ? b : b + k;
          if (aa < 0 || aa >= V || bb < 0 || bb >= G)
            continue;
          const double g = std::exp(-0.5 * k * k / 2.25);
          sum += g * d[bb * V + aa];
          w += g;
        }
        tmp[b * V + a] = sum / w;
      }
    d.swap(tmp);
  };
  blur(true);
  blur(false);
  // local maxima, highest first
  std::vector<int> maxima;
  for (int b = 0; b < G; ++b)
    for (int a = 0; a < V; ++a)
    {
      const double c = d[b * V + a];
      bool top = c > 0;
      for (int y = -1; y <= 1 && top; ++y)
        for (int x = -1; x <= 1 && top; ++x)
        {
          const int aa = a + x, bb = b + y;
          if ((x || y) && aa >= 0 && aa < V && bb >= 0 && bb < G)
            top = c > d[bb * V + aa] || (c == d[bb * V + aa] && bb * V + aa > b * V + a);
        }
      if (top)
        maxima.push_back(b * V + a);
    }
  std::sort(maxima.begin(), maxima.end(), [&](int x, int y) { return d[x] > d[y]; });
  std::vector<int> owner(V * G, -1);
  std::vector<FeatureRegion> regions;
  int id = 0;
  for (int m : maxima)
  {
    if (static_cast<int>(regions.size()) >= maxRegions)
      break;
    if (owner[m] >= 0)
      continue; // inside an earlier region: the same feature
    // grow over connected bins within one decade of the maximum
    const double floor = d[m] - 1.0;
    std::vector<int> stack{ m }, members;
    owner[m] = id;
    while (!stack.empty())
    {
      const int k = stack.back();
      stack.pop_back();
      members.push_back(k);
      const int a = k % V, b = k / V;
      const int nb[4][2] = { { a - 1, b }, { a + 1, b }, { a, b - 1 }, { a, b + 1 } };
      for (const auto& n : nb)
      {
        if (n[0] < 0 || n[0] >= V || n[1] < 0 || n[1] >= G)
          continue;
        const int j = n[1] * V + n[0];
        if (owner[j] < 0 && d[j] >= floor && d[j] > 0)
        {
          owner[j] = id;
          stack.push_back(j);
        }
      }
    }
    ++id;
    // extent: +- 2 standard deviations of its voxels (within its bins), so that the base
    // primitive's stddev, (hi - lo) / 4, is theirs; a long boundary arc is not a box
    double mass = 0, ma = 0, mb = 0;
    int a0 = V, a1 = -1, b0 = G, b1 = -1;
    for (int k : members)
    {
      a0 = std::min(a0, k % V);
      a1 = std::max(a1, k % V);
      b0 = std::min(b0, k / V);
      b1 = std::max(b1, k / V);
      mass += hist[k];
      ma += hist[k] * (k % V + 0.5);
      mb += hist[k] * (k / V + 0.5);
    }
    if (mass / nonAir < 0.005)
      continue; // noise
    ma /= mass;
    mb /= mass;
    double va = 0, vb = 0;
    for (int k : members)
    {
      va += hist[k] * (k % V + 0.5 - ma) * (k % V + 0.5 - ma) / mass;
      vb += hist[k] * (k / V + 0.5 - mb) * (k / V + 0.5 - mb) / mass;
    }
    const double sa = std::max(0.5, std::sqrt(va)), sb = std::max(0.5, std::sqrt(vb));
    FeatureRegion r;
    r.lo = range[0] + std::max(static_cast<double>(a0), ma - 2 * sa) * dv;
    r.hi = range[0] + std::min(a1 + 1.0, ma + 2 * sa) * dv;
    r.peak = std::clamp(range[0] + (m % V + 0.5) * dv, r.lo, r.hi);
    r.gradientLo = std::max(static_cast<double>(b0), mb - 2 * sb) * dg;
    r.gradientHi = std::min(b1 + 1.0, mb + 2 * sb) * dg;
    r.gradientPeak = std::clamp((m / V + 0.5) * dg, r.gradientLo, r.gradientHi);
    r.mass = mass / nonAir;
    if (keep && !keep(r))
      continue;
    regions.push_back(r);
  }
  if (regions.empty())
    throw Error("feature regions: no 2D histogram peak above the air and noise level");
  std::sort(regions.begin(), regions.end(),
    [](const FeatureRegion& a, const FeatureRegion& b)
    { return a.peak < b.peak || (a.peak == b.peak && a.gradientPeak < b.gradientPeak); });
  return regions;
}

Image renderDesign(const RayCaster& caster, const std::vector<GaussianPrimitive>& tf,
  int dimensions, const std::array<double, 2>& gradientRange, const View& view,
  const RenderOptions& options)
{
  if (tf.empty())
    return Image(view.width, view.height, 4, 0.0f);
  return renderTable(
    caster, designTable(tf, dimensions, caster.dataRange(), gradientRange), view, options);
}

Image renderTable(
  const RayCaster& caster, const DesignTable& table, const View& view, const RenderOptions& options)
{
  return table.dimensions == 2 ? caster.render(table.twoD, view, options)
                               : caster.render(table.oneD, view, options);
}

DesignTable designTable(const std::vector<GaussianPrimitive>& tf, int dimensions,
  const std::array<double, 2>& range, const std::array<double, 2>& gradientRange)
{
  DesignTable t;
  t.dimensions = dimensions;
  if (dimensions == 2)
    t.twoD = rasterize2D(tf, range, gradientRange, 256, 64);
  else
    t.oneD = rasterize1D(tf, range[0], range[1], 256);
  return t;
}

GaussianPrimitive basePrimitive(const FeatureRegion& r)
{
  GaussianPrimitive g;
  g.mean = { r.peak, r.gradientPeak };
  g.stddev = { std::max(1e-6, (r.hi - r.lo) / 4.0),
    r.twoD() ? std::max(1e-6, (r.gradientHi - r.gradientLo) / 4.0) : 1.0 };
  g.rgb = { 0.8, 0.8, 0.8 };
  g.opacity = 0.5;
  return g;
}

// --- spec -------------------------------------------------------------------------------------

void DesignSpaceSpec::validate() const
{
  auto unitRange = [](const std::array<double, 2>& r, const char* key)
  {
    if (!(r[0] >= 0 && r[0] <= r[1] && r[1] <= 1))
      throw Error(
        std::string("design space spec: \"") + key + "\" must be [lo, hi] with 0 <= lo <= hi <= 1");
  };
  unitRange(saturation, "saturation");
  unitRange(lightness, "lightness");
  unitRange(opacity, "opacity");
  if (maxRegions < 1 || maxRegions > 16)
    throw Error("design space spec: \"max_regions\" must be 1..16");
  if (minActive < 1 || minActive > maxRegions)
    throw Error("design space spec: \"min_active\" must be 1..max_regions");
  if (!(meanShift >= 0 && meanShift <= 2))
    throw Error("design space spec: \"mean_shift\" must be in [0, 2]");
  if (!(stddevScale[0] > 0 && stddevScale[0] <= stddevScale[1]))
    throw Error("design space spec: \"stddev_scale\" must be [lo, hi] with 0 < lo <= hi");
  if (!(elevation[0] >= -89 && elevation[0] <= elevation[1] && elevation[1] <= 89))
    throw Error("design space spec: \"elevation\" must be within [-89, 89] degrees");
  if (!(zoom[0] > 0 && zoom[0] <= zoom[1]))
    throw Error("design space spec: \"zoom\" must be [lo, hi] with 0 < lo <= hi");
  if (!(viewportOpacity > 0 && viewportOpacity <= 1))
    throw Error("design space spec: \"viewport_opacity\" must be in (0, 1]");
  if (dimensions != 1 && dimensions != 2)
    throw Error("design space spec: \"dimensions\" must be 1 or 2");
  if (!(litFraction >= 0 && litFraction <= 1))
    throw Error("design space spec: \"lit_fraction\" must be in [0, 1]");
  if (!(pictureFraction >= 0 && pictureFraction <= 1))
    throw Error("design space spec: \"picture_fraction\" must be in [0, 1]");
  try
  {
    lighting.validate();
  }
  catch (const Error& e)
  {
    throw Error(std::string("design space spec: ") + e.what());
  }
  for (const auto& r : regions)
  {
    if (!(r.lo < r.hi) || !std::isfinite(r.lo) || !std::isfinite(r.hi) || r.peak < r.lo ||
      r.peak > r.hi)
      throw Error("design space spec: every region needs lo < hi and lo <= peak <= hi");
    if (dimensions == 2 &&
      !(r.gradientLo >= 0 && r.gradientLo < r.gradientHi && std::isfinite(r.gradientHi) &&
        r.gradientPeak >= r.gradientLo && r.gradientPeak <= r.gradientHi))
      throw Error("design space spec: 2D regions need 0 <= gradient_lo < gradient_hi and "
                  "gradient_lo <= gradient_peak <= gradient_hi");
  }
}

DesignSpaceSpec parseDesignSpaceSpec(const std::string& text, const std::string& origin)
{
  using nlohmann::json;
  json j;
  try
  {
    j = json::parse(text);
  }
  catch (const json::parse_error& e)
  {
    throw Error(origin + " is not valid JSON: " + e.what());
  }
  if (!j.is_object())
    throw Error(origin + ": expected a JSON object");
  DesignSpaceSpec s;
  static const char* known[] = { "regions", "dimensions", "max_regions", "min_active", "saturation",
    "lightness", "opacity", "mean_shift", "stddev_scale", "elevation", "zoom", "viewport_opacity",
    "lighting", "lit_fraction", "picture_fraction" };
  for (auto it = j.begin(); it != j.end(); ++it)
  {
    if (std::find_if(std::begin(known), std::end(known),
          [&](const char* k) { return it.key() == k; }) == std::end(known))
      throw Error(origin + ": unknown key \"" + it.key() + "\"");
  }
  try
  {
    auto pair = [&](const char* key, std::array<double, 2>& out)
    {
      if (!j.contains(key))
        return;
      const auto v = j[key].get<std::vector<double>>();
      if (v.size() != 2)
        throw Error(origin + ": \"" + key + "\" must be [lo, hi]");
      out = { v[0], v[1] };
    };
    pair("saturation", s.saturation);
    pair("lightness", s.lightness);
    pair("opacity", s.opacity);
    pair("stddev_scale", s.stddevScale);
    pair("elevation", s.elevation);
    pair("zoom", s.zoom);
    s.dimensions = j.value("dimensions", s.dimensions);
    s.maxRegions = j.value("max_regions", s.maxRegions);
    s.minActive = j.value("min_active", s.minActive);
    s.meanShift = j.value("mean_shift", s.meanShift);
    s.viewportOpacity = j.value("viewport_opacity", s.viewportOpacity);
    s.litFraction = j.value("lit_fraction", s.litFraction);
    s.pictureFraction = j.value("picture_fraction", s.pictureFraction);
    if (j.contains("lighting"))
      s.lighting = parseLighting(j["lighting"].dump(), origin);
    if (j.contains("regions"))
    {
      for (const auto& r : j["regions"])
      {
        FeatureRegion fr;
        fr.lo = r.at("lo").get<double>();
        fr.hi = r.at("hi").get<double>();
        fr.peak = r.value("peak", 0.5 * (fr.lo + fr.hi));
        if (s.dimensions == 2)
        {
          fr.gradientLo = r.at("gradient_lo").get<double>();
          fr.gradientHi = r.at("gradient_hi").get<double>();
          fr.gradientPeak = r.value("gradient_peak", 0.5 * (fr.gradientLo + fr.gradientHi));
        }
        s.regions.push_back(fr);
      }
    }
  }
  catch (const json::exception& e)
  {
    throw Error(origin + ": " + e.what());
  }
  try
  {
    s.validate();
  }
  catch (const Error& e)
  {
    throw Error(origin + ": " + e.what());
  }
  return s;
}

DesignSpaceSpec readDesignSpaceSpec(const std::string& path)
{
  return parseDesignSpaceSpec(
    readTextFile(path, "design space spec"), "design space spec '" + path + "'");
}

std::string designSpaceSpecToJson(const DesignSpaceSpec& s)
{
  nlohmann::json j;
  j["dimensions"] = s.dimensions;
  j["max_regions"] = s.maxRegions;
  j["min_active"] = s.minActive;
  j["saturation"] = s.saturation;
  j["lightness"] = s.lightness;
  j["opacity"] = s.opacity;
  j["mean_shift"] = s.meanShift;
  j["stddev_scale"] = s.stddevScale;
  j["elevation"] = s.elevation;
  j["zoom"] = s.zoom;
  j["viewport_opacity"] = s.viewportOpacity;
  if (s.lighting != Lighting{})
  {
    j["lighting"] = nlohmann::json::parse(lightingToJson(s.lighting));
    j["lit_fraction"] = s.litFraction;
  }
  if (s.pictureFraction > 0)
    j["picture_fraction"] = s.pictureFraction;
  if (!s.regions.empty())
  {
    j["regions"] = nlohmann::json::array();
    for (const auto& r : s.regions)
    {
      nlohmann::json o = { { "lo", r.lo }, { "hi", r.hi }, { "peak", r.peak } };
      if (s.dimensions == 2)
      {
        o["gradient_lo"] = r.gradientLo;
        o["gradient_hi"] = r.gradientHi;
        o["gradient_peak"] = r.gradientPeak;
      }
      j["regions"].push_back(o);
    }
  }
  return j.dump(2) + "\n";
}

// --- exemplars --------------------------------------------------------------------------------

namespace
{

std::array<double, 3> hslToRgb(double h, double s, double l)
{
  auto f = [&](double n)
  {
    const double k = std::fmod(n + h * 12.0, 12.0);
    const double a = s * std::min(l, 1 - l);
    return l - a * std::max(-1.0, std::min({ k - 3, 9 - k, 1.0 }));
  };
  return { f(0), f(8), f(4) };
}

} // namespace

View orbitView(const Volume& volume, int size, double azimuthDeg, double elevationDeg, double zoom)
{
  return orbitView(volume.bounds(), size, azimuthDeg, elevationDeg, zoom);
}

View orbitView(const std::array<double, 6>& bounds, int size, double azimuthDeg,
  double elevationDeg, double zoom)
{
  View v = defaultView(bounds, size, size);
  const Eigen::Vector3d f = v.camera.focalPoint;
  const double dist = (v.camera.position - f).norm() / zoom;
  const double az = azimuthDeg * M_PI / 180, el = elevationDeg * M_PI / 180;
  v.camera.position = f +
    dist * Eigen::Vector3d(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
  v.camera.viewUp = { 0, 1, 0 };
  v.camera.parallelScale /= zoom;
  return v;
}

namespace
{
constexpr std::uint64_t kSeedStride = 0x9E3779B97F4A7C15ull; // Exemplar::seed = seed x it + index
}

std::uint64_t exemplarIndex(const Exemplar& exemplar, std::uint64_t seed)
{
  return exemplar.seed - seed * kSeedStride;
}

Exemplar sampleExemplar(const Volume& volume, const DesignSpaceSpec& spec,
  const std::vector<FeatureRegion>& regions, std::uint64_t seed, std::uint64_t index, int size)
{
  Exemplar e;
  e.seed = seed * kSeedStride + index;
  std::mt19937_64 rng(e.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto in = [&](const std::array<double, 2>& r) { return r[0] + (r[1] - r[0]) * u(rng); };
  const int n = static_cast<int>(regions.size());
  // a random subset of at least minActive regions
  std::vector<int> order(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  const int lo = std::min(spec.minActive, n);
  const int count = lo + static_cast<int>(u(rng) * (n - lo + 1) * 0.999999);
  e.active.assign(order.begin(), order.begin() + count);
  std::sort(e.active.begin(), e.active.end());
  for (int r : e.active)
  {
    GaussianPrimitive g = basePrimitive(regions[r]);
    const double w = regions[r].hi - regions[r].lo;
    g.mean[0] += (2 * u(rng) - 1) * spec.meanShift * w;
    g.stddev[0] *= in(spec.stddevScale);
    g.rgb = hslToRgb(u(rng), in(spec.saturation), in(spec.lightness));
    for (double& c : g.rgb)
      c = std::clamp(c, 0.0, 1.0);
    g.opacity = in(spec.opacity);
    if (regions[r].twoD())
    {
      g.mean[1] +=
        (2 * u(rng) - 1) * spec.meanShift * (regions[r].gradientHi - regions[r].gradientLo);
      g.stddev[1] *= in(spec.stddevScale);
    }
    e.primitives.push_back(g);
  }
  e.viewExp = orbitView(volume, size, 360 * u(rng), in(spec.elevation), in(spec.zoom));
  e.viewView = orbitView(volume, size, 360 * u(rng), in(spec.elevation), in(spec.zoom));
  e.background = u(rng) < 0.5 ? 0 : 1;
  e.viewExp.background = { static_cast<double>(e.background), static_cast<double>(e.background),
    static_cast<double>(e.background) };
  if (spec.lighting.shade && u(rng) < spec.litFraction)
    e.viewExp.lighting = e.viewView.lighting = spec.lighting;
  if (spec.pictureFraction > 0 && u(rng) < spec.pictureFraction)
    e.picture = samplePictureLook(rng, size);
  return e;
}

View designDefaultView(const Volume& volume, const DesignSpaceSpec& spec, int size)
{
  return designDefaultView(volume.bounds(), spec, size);
}

View designDefaultView(const std::array<double, 6>& bounds, const DesignSpaceSpec& spec, int size)
{
  View v = defaultView(bounds, size, size);
  if (spec.lighting.shade)
    v.lighting = spec.lighting;
  return v;
}

std::vector<GaussianPrimitive> auxiliaryPrimitives(
  const DesignSpaceSpec& spec, const std::vector<FeatureRegion>& regions)
{
  std::vector<GaussianPrimitive> out;
  for (const auto& r : regions)
  {
    GaussianPrimitive g = basePrimitive(r);
    g.opacity = spec.viewportOpacity;
    out.push_back(g);
  }
  return out;
}

void VolumeHash::add(const float* values, std::int64_t count)
{
  std::uint64_t h = Hash;
  for (std::int64_t i = 0; i < count; ++i)
  {
    std::uint32_t bits;
    std::memcpy(&bits, values + i, 4);
    for (int q = 0; q < 4; ++q)
    {
      h ^= (bits >> (8 * q)) & 0xFF;
      h *= 1099511628211ull;
    }
  }
  Hash = h;
}

std::string volumeFingerprint(const Volume& volume)
{
  VolumeHash hash;
  volume.visit(
    [&](const auto* p)
    {
      float chunk[4096]; // the hash of the float values, as ever
      for (std::int64_t i = 0; i < volume.voxelCount(); i += 4096)
      {
        const std::int64_t n = std::min<std::int64_t>(4096, volume.voxelCount() - i);
        for (std::int64_t k = 0; k < n; ++k)
          chunk[k] = static_cast<float>(p[i + k]);
        hash.add(chunk, n);
      }
    });
  return volumeFingerprint(volume.dims(), volume.spacing(), volume.range(), hash.value());
}

std::string volumeFingerprint(const std::array<int, 3>& d, const std::array<double, 3>& s,
  const std::array<double, 2>& range, std::uint64_t hash)
{
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%dx%dx%d spacing %.6g,%.6g,%.6g range %.6g..%.6g fnv1a %016llx",
    d[0], d[1], d[2], s[0], s[1], s[2], range[0], range[1], static_cast<unsigned long long>(hash));
  return buf;
}

std::string describeFingerprint(const std::string& fingerprint)
{
  int nx = 0, ny = 0, nz = 0;
  const auto at = fingerprint.find(" range ");
  const auto end = fingerprint.find(" fnv1a");
  if (std::sscanf(fingerprint.c_str(), "%dx%dx%d", &nx, &ny, &nz) != 3 || at == std::string::npos ||
    end == std::string::npos || end < at)
    return "an unknown volume";
  std::string range = fingerprint.substr(at + 7, end - at - 7);
  const auto dots = range.find("..", 1);
  if (dots != std::string::npos)
    range = range.substr(0, dots) + " to " + range.substr(dots + 2);
  return std::to_string(nx) + " x " + std::to_string(ny) + " x " + std::to_string(nz) +
    " voxels, values " + range;
}

} // namespace ddg
