// Reconstruction.cxx: the targets and their image loss, the rendering stage, and the one
// optimisation loop (Adam, progress and cancel, early stop) over a TransferParameterisation.
#include "Reconstruct/Reconstruction.h"

#include "Common/Error.h"
#include "Image/ImageMetrics.h"
#include "Numerics/Adam.h"
#include "Reconstruct/FramedColours.h"
#include "Reconstruct/TransferParameterisation.h"
#include "Render/RayCaster.h"
#include "TransferFunction/ColorSpace.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <sstream>

namespace ddg
{
namespace
{

// --- targets and the image loss --------------------------------------------------------

// A target prepared for the loss: what each pixel should be, in the render's terms.
struct PreparedTarget
{
  const ReconstructionTarget* source = nullptr;
  bool alpha = false;          // compare premultiplied RGBA, else RGB over the background
  std::vector<float> value;    // 4 (alpha) or 3 values per pixel
  std::vector<float> weight;   // per pixel (mask), empty = 1
  std::vector<int> candidates; // pixels with weight > 0
  std::vector<std::array<double, 3>> background; // per image row (opaque targets)
  std::vector<float> empty;                      // per pixel: weight of the empty-space term
  int width = 1;
};

PreparedTarget prepare(const ReconstructionTarget& t, size_t index)
{
  std::ostringstream where;
  where << "target " << index;
  const View& v = t.view;
  v.validate();
  if (t.image.empty())
  {
    throw Error(where.str() + ": the image is empty");
  }
  if (t.image.width != v.width || t.image.height != v.height)
  {
    std::ostringstream msg;
    msg << where.str() << ": the image is " << t.image.width << " x " << t.image.height
        << " but its view is " << v.width << " x " << v.height
        << " (resample it, or set the view's size to the image's)";
    throw Error(msg.str());
  }
  if (t.image.channels != 3 && t.image.channels != 4)
  {
    throw Error(where.str() + ": the image has " + std::to_string(t.image.channels) +
      " channels; RGB or RGBA is needed");
  }
  PreparedTarget p;
  p.source = &t;
  p.alpha = t.image.channels == 4;
  p.width = v.width;
  p.background.resize(static_cast<size_t>(v.height));
  for (int y = 0; y < v.height; ++y)
  {
    p.background[static_cast<size_t>(y)] = v.backgroundAt(y);
  }
  const size_t n = static_cast<size_t>(v.width) * v.height;
  if (!t.empty.empty())
  {
    if (t.empty.width != v.width || t.empty.height != v.height)
    {
      throw Error(where.str() + ": the empty-space mask's size differs from the image's");
    }
    if (p.alpha)
    {
      throw Error(where.str() + ": an empty-space mask is for opaque (RGB) targets only");
    }
    if (!(t.emptyWeight >= 0 && std::isfinite(t.emptyWeight)))
    {
      throw Error(where.str() + ": the empty-space weight must be finite and >= 0");
    }
    p.empty.resize(n);
    for (size_t i = 0; i < n; ++i)
    {
      p.empty[i] = static_cast<float>(
        t.emptyWeight * std::clamp(t.empty.pixels[i * t.empty.channels], 0.0f, 1.0f));
    }
  }
  if (!t.mask.empty())
  {
    if (t.mask.width != v.width || t.mask.height != v.height)
    {
      throw Error(where.str() + ": the mask's size differs from the image's");
    }
    p.weight.resize(n);
    for (size_t i = 0; i < n; ++i)
    {
      p.weight[i] = std::clamp(t.mask.pixels[i * t.mask.channels], 0.0f, 1.0f);
    }
  }
  bool anything = false;
  p.value.resize(n * (p.alpha ? 4 : 3));
  for (size_t i = 0; i < n; ++i)
  {
    const float* px = &t.image.pixels[i * t.image.channels];
    for (int c = 0; c < t.image.channels; ++c)
    {
      if (!std::isfinite(px[c]))
      {
        throw Error(where.str() + ": the image holds NaN or infinite values");
      }
    }
    if (p.alpha)
    {
      const float a = std::clamp(px[3], 0.0f, 1.0f);
      for (int c = 0; c < 3; ++c)
        p.value[4 * i + c] = std::clamp(px[c], 0.0f, 1.0f) * a;
      p.value[4 * i + 3] = a;
      anything = anything || a > 1.0f / 255.0f;
    }
    else
    {
      for (int c = 0; c < 3; ++c)
      {
        p.value[3 * i + c] = std::clamp(px[c], 0.0f, 1.0f);
        anything = anything ||
          std::abs(px[c] - p.background[i / static_cast<size_t>(v.width)][c]) > 1.5 / 255.0;
      }
    }
    if (p.weight.empty() || p.weight[i] > 0)
    {
      p.candidates.push_back(static_cast<int>(i));
    }
  }
  if (!anything)
  {
    throw Error(where.str() +
      (p.alpha ? ": the image is fully transparent"
               : ": the image shows nothing but the background colour") +
      " — there is nothing to reconstruct from (is the background colour in the view right?)");
  }
  if (p.candidates.empty())
  {
    throw Error(where.str() + ": the mask excludes every pixel");
  }
  return p;
}

// Loss of one pixel and its gradient w.r.t. the rendered premultiplied RGBA (accumulated).
double pixelLoss(const PreparedTarget& t, int pixel, const float* rgba, ReconstructionLoss kind,
  double scale, float* dL_drgba)
{
  const double w = t.weight.empty() ? 1.0 : t.weight[static_cast<size_t>(pixel)];
  auto term = [&](double r, double& d)
  {
    if (kind == ReconstructionLoss::L2)
    {
      d = 2 * r;
      return r * r;
    }
    constexpr double delta = 1e-3; // Huber: smooth |r|
    if (std::abs(r) < delta)
    {
      d = r / delta;
      return 0.5 * r * r / delta;
    }
    d = r > 0 ? 1.0 : -1.0;
    return std::abs(r) - 0.5 * delta;
  };
  double L = 0;
  if (t.alpha)
  {
    const float* target = &t.value[4 * static_cast<size_t>(pixel)];
    for (int c = 0; c < 4; ++c)
    {
      double d;
      L += term(rgba[c] - target[c], d);
      dL_drgba[c] += static_cast<float>(w * scale * d);
    }
  }
  else
  {
    // out = C + (1 - A) background
    const float* target = &t.value[3 * static_cast<size_t>(pixel)];
    const auto& bg = t.background[static_cast<size_t>(pixel / t.width)];
    for (int c = 0; c < 3; ++c)
    {
      const double out = rgba[c] + (1.0 - rgba[3]) * bg[c];
      double d;
      L += term(out - target[c], d);
      dL_drgba[c] += static_cast<float>(w * scale * d);
      dL_drgba[3] -= static_cast<float>(w * scale * d * bg[c]);
    }
    // empty space: the premultiplied RGBA itself is pulled to 0 (3 of the 4 channels' share)
    const double e = t.empty.empty() ? 0.0 : t.empty[static_cast<size_t>(pixel)];
    if (e > 0)
    {
      for (int c = 0; c < 4; ++c)
      {
        double d;
        L += 0.75 * e * term(rgba[c], d);
        dL_drgba[c] += static_cast<float>(0.75 * e * w * scale * d);
      }
    }
  }
  return w * scale * L;
}

// --- the rendering stage: TF entries -> the renderer's table, forward and adjoint ----------

// 1D: the render table (ParaView's width) as a linear function of the bins.
struct BinsToTable
{
  int bins = 0, width = 0;
  std::vector<int> index;
  std::vector<double> frac;

  void setup(int b, int w)
  {
    bins = b;
    width = w;
    index.resize(static_cast<size_t>(w));
    frac.resize(static_cast<size_t>(w));
    for (int i = 0; i < w; ++i)
    {
      const double pos = static_cast<double>(i) * (b - 1) / (w - 1);
      index[i] = std::min(static_cast<int>(pos), b - 2);
      frac[i] = pos - index[i];
    }
  }
  void forward(const std::vector<double>& v, std::vector<float>& table) const
  {
    table.resize(static_cast<size_t>(width) * 4);
    for (int i = 0; i < width; ++i)
      for (int c = 0; c < 4; ++c)
        table[4 * i + c] = static_cast<float>(
          v[4 * index[i] + c] * (1 - frac[i]) + v[4 * (index[i] + 1) + c] * frac[i]);
  }
  void backward(const std::vector<float>& dTable, std::vector<double>& dv) const
  {
    for (int i = 0; i < width; ++i)
      for (int c = 0; c < 4; ++c)
      {
        dv[4 * index[i] + c] += dTable[4 * i + c] * (1 - frac[i]);
        dv[4 * (index[i] + 1) + c] += dTable[4 * i + c] * frac[i];
      }
  }
};

// The TF entries (bins x gradientBins RGBA) as the table the renderer reads: in 1D resampled
// to ParaView's table width (BinsToTable), in 2D the entries themselves. Holds dL/dTable.
class TableStage
{
public:
  TableStage(const DifferentiableRenderer& renderer, const ReconstructionOptions& opt,
    std::array<double, 2> range, std::array<double, 2> gradientRange)
    : Renderer(renderer)
    , TwoD(opt.twoD)
    , Bins(opt.bins)
    , GradientBins(opt.twoD ? opt.gradientBins : 1)
    , Range(range)
    , GradientRange(gradientRange)
    , Render(opt.render)
  {
    Render.jitter = false;
    if (!TwoD)
    {
      // ParaView's table width for nodes every (max - min) / (B - 1)
      TransferFunction1D spacingProbe;
      spacingProbe.color = { { range[0], 0, 0, 0 },
        { range[0] + (range[1] - range[0]) / (Bins - 1), 0, 0, 0 } };
      spacingProbe.opacity = { { range[0], 0 } };
      Map.setup(Bins, paraviewTableWidth(spacingProbe, range[0], range[1]));
    }
  }

  // The table of `values`; clears dL/dTable.
  void setValues(const std::vector<double>& values)
  {
    if (TwoD)
      Table.assign(values.begin(), values.end());
    else
      Map.forward(values, Table);
    DTable.assign(Table.size(), 0.0f);
  }

  // OVERWRITES rgba and records of the listed pixels.
  void forward(const View& view, const std::vector<int>& px, std::vector<float>& rgba,
    std::vector<RayRecord>& records) const
  {
    if (TwoD)
      Renderer.forward2D(
        Table.data(), Bins, GradientBins, Range, GradientRange, view, Render, px, rgba, records);
    else
      Renderer.forward(
        Table.data(), Map.width, Range[0], Range[1], view, Render, px, rgba, records);
  }

  // ACCUMULATES dL/dTable from dL/d(rgba) of the listed pixels.
  void backward(const View& view, const std::vector<int>& px, const std::vector<RayRecord>& records,
    const std::vector<float>& dL_dRGBA)
  {
    if (TwoD)
      Renderer.backward2D(Table.data(), Bins, GradientBins, Range, GradientRange, view, Render, px,
        records, dL_dRGBA, DTable);
    else
      Renderer.backward(
        Table.data(), Map.width, Range[0], Range[1], view, Render, px, records, dL_dRGBA, DTable);
  }

  // OVERWRITES dL_dValues (4 per entry) from dL/dTable.
  void pullback(std::vector<double>& dL_dValues) const
  {
    std::fill(dL_dValues.begin(), dL_dValues.end(), 0.0);
    if (TwoD)
    {
      for (size_t i = 0; i < dL_dValues.size(); ++i)
        dL_dValues[i] = DTable[i];
    }
    else
    {
      Map.backward(DTable, dL_dValues);
    }
  }

private:
  const DifferentiableRenderer& Renderer;
  bool TwoD;
  int Bins, GradientBins;
  std::array<double, 2> Range, GradientRange;
  RenderOptions Render;
  BinsToTable Map;
  std::vector<float> Table, DTable;
};

// What the optimisation loop fits: the loss of the stage's current table, its gradient
// ACCUMULATED into the stage.
class DataTerm
{
public:
  virtual ~DataTerm() = default;
  virtual double evaluate(TableStage& stage, std::mt19937& rng) = 0;
};

// The data term over all targets: per target, the pixel loss on a random subset of its
// candidate pixels (mean over pixels and channels), plus (ssimWeight > 0) (1 - SSIM) on a
// random patch; mean over targets. Draws from rng in a fixed order: target by target, the
// pixel subset, then the patch.
class ImageLoss : public DataTerm
{
public:
  ImageLoss(std::vector<PreparedTarget> targets, const ReconstructionOptions& opt)
    : Targets(std::move(targets))
    , Opt(opt)
  {
  }

  double evaluate(TableStage& stage, std::mt19937& rng) override
  {
    double loss = 0;
    for (auto& t : Targets)
    {
      // random subset of the candidate pixels
      const size_t want = Opt.raysPerIteration > 0
        ? std::min(t.candidates.size(), static_cast<size_t>(Opt.raysPerIteration))
        : t.candidates.size();
      if (want < t.candidates.size())
      {
        for (size_t i = 0; i < want; ++i)
        {
          std::uniform_int_distribution<size_t> pick(i, t.candidates.size() - 1);
          std::swap(t.candidates[i], t.candidates[pick(rng)]);
        }
      }
      Pixels.assign(t.candidates.begin(), t.candidates.begin() + static_cast<std::ptrdiff_t>(want));
      std::sort(Pixels.begin(), Pixels.end()); // neighbouring rays together: cache locality
      const View& view = t.source->view;
      stage.forward(view, Pixels, RGBA, Records);
      DRGBA.assign(RGBA.size(), 0.0f);
      const double scale = 1.0 / (static_cast<double>(want) * (t.alpha ? 4 : 3) * Targets.size());
      for (size_t q = 0; q < Pixels.size(); ++q)
      {
        loss += pixelLoss(t, Pixels[q], &RGBA[4 * q], Opt.loss, scale, &DRGBA[4 * q]);
      }
      stage.backward(view, Pixels, Records, DRGBA);
      if (Opt.ssimWeight > 0)
      {
        loss += ssimPatchTerm(stage, t, rng);
      }
    }
    return loss;
  }

private:
  // (1 - SSIM) on a random patch of a target, rendered in full; adds its gradient to the stage.
  double ssimPatchTerm(TableStage& stage, const PreparedTarget& t, std::mt19937& gen) const
  {
    const View& view = t.source->view;
    const int pw = std::min(Opt.ssimPatch, view.width), ph = std::min(Opt.ssimPatch, view.height);
    std::uniform_int_distribution<int> px(0, view.width - pw), py(0, view.height - ph);
    const int x0 = px(gen), y0 = py(gen);
    std::vector<int> patch;
    for (int y = y0; y < y0 + ph; ++y)
      for (int x = x0; x < x0 + pw; ++x)
        patch.push_back(y * view.width + x);
    std::vector<float> prgba, pd;
    std::vector<RayRecord> prec;
    stage.forward(view, patch, prgba, prec);
    // the images SSIM compares: over the background (opaque targets) or premultiplied rgb
    std::vector<float> ours(patch.size() * 3), theirs(patch.size() * 3);
    for (size_t q = 0; q < patch.size(); ++q)
      for (int c = 0; c < 3; ++c)
      {
        ours[3 * q + c] = t.alpha
          ? prgba[4 * q + c]
          : static_cast<float>(prgba[4 * q + c] +
              (1 - prgba[4 * q + 3]) * t.background[static_cast<size_t>(patch[q] / t.width)][c]);
        theirs[3 * q + c] = t.value[(t.alpha ? 4 : 3) * static_cast<size_t>(patch[q]) + c];
      }
    std::vector<double> dS(ours.size());
    const double sVal = ssimWithGradient(ours.data(), theirs.data(), pw, ph, dS.data());
    const double k = Opt.ssimWeight / static_cast<double>(Targets.size());
    pd.assign(prgba.size(), 0.0f);
    for (size_t q = 0; q < patch.size(); ++q)
      for (int c = 0; c < 3; ++c)
      {
        const double g = -k * dS[3 * q + c]; // d(k (1 - S)) / d(image)
        pd[4 * q + c] += static_cast<float>(g);
        if (!t.alpha)
          pd[4 * q + 3] -=
            static_cast<float>(g * t.background[static_cast<size_t>(patch[q] / t.width)][c]);
      }
    stage.backward(view, patch, prec, pd);
    return k * (1.0 - sVal);
  }

  std::vector<PreparedTarget> Targets; // their candidate lists are shuffled in place, step by step
  const ReconstructionOptions& Opt;
  std::vector<int> Pixels;
  std::vector<float> RGBA, DRGBA;
  std::vector<RayRecord> Records;
};

// The colour targets' term: per target, every pixel rendered, over the view's background, cut
// to the square on its content (ColourTarget), the sliced Wasserstein distance of its CIELAB
// colours to the target's; mean over targets. Squares reaching past the image count the
// background there. Draws the directions from rng, target by target.
class ColourLoss : public DataTerm
{
public:
  static constexpr size_t kMaxTargetColours = 16384;

  ColourLoss(const std::vector<ColourTarget>& targets, const ReconstructionOptions& opt)
    : Targets(targets)
    , Opt(opt)
  {
    if (!std::isfinite(opt.colourPlacement) || opt.colourPlacement < 0)
      throw Error("colourPlacement must be a finite number >= 0");
    for (size_t i = 0; i < targets.size(); ++i)
    {
      const auto& t = targets[i];
      t.view.validate();
      if (t.colours.empty())
        throw Error("colour target " + std::to_string(i) + " has no colours");
      for (const auto& c : t.colours)
        if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
          throw Error("colour target " + std::to_string(i) + " holds non-finite colours");
      if (opt.colourPlacement > 0 && t.radii.size() != t.colours.size())
        throw Error("colour target " + std::to_string(i) +
          " needs a radius per colour to compare where colours lie");
      // a large picture's colours thinned evenly (every k-th of the framed square, in raster
      // order) to kMaxTargetColours: sorting the target's projections dominated a step, and
      // its quantiles do not need more points than a few times the render's
      const size_t n = t.colours.size(), kept = std::min(n, kMaxTargetColours);
      auto& lab = Lab.emplace_back();
      auto& placed = Placed.emplace_back();
      for (size_t j = 0; j < kept; ++j)
      {
        const size_t q = j * n / kept;
        const auto& c = t.colours[q];
        const RGB l = rgbToLab({ std::clamp<double>(c[0], 0, 1), std::clamp<double>(c[1], 0, 1),
          std::clamp<double>(c[2], 0, 1) });
        lab.push_back(
          { static_cast<float>(l[0]), static_cast<float>(l[1]), static_cast<float>(l[2]) });
        if (opt.colourPlacement > 0)
          placed.push_back({ lab.back()[0], static_cast<float>(opt.colourPlacement * t.radii[q]) });
      }
    }
    if (opt.directionPool < 0)
      throw Error("directionPool must be 0 (fresh directions) or more");
  }

  // Each target's colours sorted once along the pool (one pool for targets of equal colours),
  // at the first step: after the fit's own checks of its options.
  void sortAlongPool()
  {
    std::mt19937_64 pool(0x9e3779b97f4a7c15ULL ^ Opt.seed);
    for (size_t i = 0; i < Lab.size(); ++i)
    {
      size_t same = 0;
      while (same < i && !(Lab[same] == Lab[i] && Placed[same] == Placed[i]))
        ++same;
      if (same < i)
      {
        LabPool.push_back(LabPool[same]);
        PlacedPool.push_back(PlacedPool[same]);
        continue;
      }
      LabPool.push_back(std::make_shared<const SortedProjections<3>>(
        sortedProjections(Lab[i], Opt.directionPool, pool, Opt.render.threads)));
      PlacedPool.push_back(Placed[i].empty()
          ? nullptr
          : std::make_shared<const SortedProjections<2>>(
              sortedProjections(Placed[i], Opt.directionPool, pool, Opt.render.threads)));
    }
  }

  double evaluate(TableStage& stage, std::mt19937& rng) override
  {
    if (Opt.directionPool > 0 && LabPool.empty())
      sortAlongPool();
    double loss = 0;
    for (size_t ti = 0; ti < Targets.size(); ++ti)
    {
      const View& view = Targets[ti].view;
      const int w = view.width, h = view.height;
      stage.forward(view, {}, RGBA, Records);
      // over the background, framed as framedColours frames a picture (pixel -1: the
      // background beyond the image); their Lab values and Jacobians
      Over.assign(static_cast<size_t>(w) * h * 3, 0.0f);
      for (int y = 0; y < h; ++y)
      {
        const auto bg = view.backgroundAt(y);
        for (int x = 0; x < w; ++x)
        {
          const size_t i = static_cast<size_t>(y) * w + x;
          for (int k = 0; k < 3; ++k)
            Over[3 * i + k] = static_cast<float>(
              std::clamp(RGBA[4 * i + k] + (1.0 - RGBA[4 * i + 3]) * bg[k], 0.0, 1.0));
        }
      }
      Colours.clear();
      Jacobians.clear();
      const bool placed = Opt.colourPlacement > 0;
      Pixel = framedPixels(Over.data(), w, h, view, {}, placed ? &Radii : nullptr);
      for (const int p : Pixel)
      {
        const RGB c = p >= 0 ? RGB{ Over[3 * static_cast<size_t>(p)],
          Over[3 * static_cast<size_t>(p) + 1], Over[3 * static_cast<size_t>(p) + 2] }
                             : view.background; // beyond the image: background (bottom row's)
        const RGB l = rgbToLab(c, Jacobians.emplace_back().m);
        Colours.push_back(
          { static_cast<float>(l[0]), static_cast<float>(l[1]), static_cast<float>(l[2]) });
      }
      std::mt19937_64 directions(rng());
      const double k = 1.0 / static_cast<double>(Targets.size());
      loss += k *
        (LabPool.empty() ? slicedWasserstein(Colours, Lab[ti], Opt.directions, directions,
                             &Gradient, Opt.render.threads)
                         : slicedWasserstein(Colours, *LabPool[ti], Opt.directions, directions,
                             &Gradient, Opt.render.threads));
      if (placed) // lightness with where it lies (the radius is the frame's: not differentiated)
      {
        Points.clear();
        for (size_t q = 0; q < Colours.size(); ++q)
          Points.push_back({ Colours[q][0], static_cast<float>(Opt.colourPlacement * Radii[q]) });
        loss += k *
          (PlacedPool.empty() ? slicedWasserstein(Points, Placed[ti], Opt.directions, directions,
                                  &PointGradient, Opt.render.threads)
                              : slicedWasserstein(Points, *PlacedPool[ti], Opt.directions,
                                  directions, &PointGradient, Opt.render.threads));
        for (size_t q = 0; q < PointGradient.size(); ++q)
          Gradient[q][0] += PointGradient[q][0];
      }
      // dL/d(premultiplied RGBA): out = C + (1 - A) background, Lab = f(out)
      DRGBA.assign(RGBA.size(), 0.0f);
      for (size_t q = 0; q < Colours.size(); ++q)
      {
        if (Pixel[q] < 0)
          continue;
        const size_t i = static_cast<size_t>(Pixel[q]);
        const auto bg = view.backgroundAt(Pixel[q] / w);
        for (int c = 0; c < 3; ++c)
        {
          double g = 0;
          for (int r = 0; r < 3; ++r)
            g += Jacobians[q].m[r][c] * Gradient[q][r];
          DRGBA[4 * i + c] += static_cast<float>(k * g);
          DRGBA[4 * i + 3] -= static_cast<float>(k * g * bg[c]);
        }
      }
      stage.backward(view, {}, Records, DRGBA);
    }
    return loss;
  }

private:
  const std::vector<ColourTarget>& Targets;
  const ReconstructionOptions& Opt;
  std::vector<std::vector<std::array<float, 3>>> Lab;    // the targets' colours
  std::vector<std::vector<std::array<float, 2>>> Placed; // lightness and radius (placement)
  std::vector<std::shared_ptr<const SortedProjections<3>>> LabPool;    // directionPool > 0
  std::vector<std::shared_ptr<const SortedProjections<2>>> PlacedPool; // and placement
  std::vector<std::array<float, 3>> Colours, Gradient;
  std::vector<std::array<float, 2>> Points, PointGradient;
  std::vector<float> Radii;
  std::vector<int> Pixel;
  struct Jacobian
  {
    double m[3][3];
  };
  std::vector<Jacobian> Jacobians; // d Lab / d RGB of each colour
  std::vector<float> RGBA, DRGBA, Over;
  std::vector<RayRecord> Records;
};

// --- the optimisation loop ---------------------------------------------------------------

// What a result holds of the TF: its entries as table1D or table2D, and its primitives.
struct ResultLayout
{
  bool twoD = false;
  std::array<double, 2> range{ 0, 1 }, gradientRange{ 0, 1 };
  int bins = 0, gradientBins = 1;

  void store(ReconstructionResult& r, const std::vector<double>& values,
    std::vector<GaussianPrimitive> primitives) const
  {
    std::vector<float> current(values.begin(), values.end());
    r.primitives = std::move(primitives);
    if (twoD)
    {
      r.table2D.valueRange = range;
      r.table2D.gradientRange = gradientRange;
      r.table2D.width = bins;
      r.table2D.height = gradientBins;
      r.table2D.rgba = std::move(current);
    }
    else
    {
      r.table1D.min = range[0];
      r.table1D.max = range[1];
      r.table1D.width = bins;
      r.table1D.rgba = std::move(current);
    }
  }
};

// Adam on theta for at most opt.iterations steps: forward (parameters -> entries -> table),
// image loss and its adjoint, the parameterisation's prior, backward to theta, one Adam step.
// After each step: the loss is recorded, progress is called (with the current TF every
// snapshotEvery steps; false cancels: throws Cancelled), and the run stops once the smoothed
// loss (EMA 0.9) improved by less than `tolerance` (relative) for `patience` steps.
void optimise(TransferParameterisation& param, TableStage& stage, DataTerm& data,
  const ResultLayout& layout, const ReconstructionOptions& opt,
  const ReconstructionProgress& progress, ReconstructionResult& result)
{
  std::vector<double> theta = param.initial();
  const std::vector<double> rates = param.learningRates(opt.learningRate);
  Adam adam(AdamOptions{ 0.9, 0.999, 1e-8 }, theta.size());
  std::mt19937 rng(opt.seed);
  std::vector<double> values, dValues, dTheta;
  auto storeCurrent = [&]
  {
    std::vector<double> v;
    param.forward(theta, v);
    layout.store(result, v, param.primitives());
  };
  double ema = 0, bestEma = std::numeric_limits<double>::infinity();
  int sinceImprovement = 0;
  for (int step = 0; step < opt.iterations; ++step)
  {
    param.forward(theta, values);
    stage.setValues(values);
    double loss = data.evaluate(stage, rng);
    dValues.resize(values.size());
    stage.pullback(dValues);
    param.addPrior(values, loss, dValues);
    if (!std::isfinite(loss))
    {
      throw Error("the loss became NaN or infinite at step " + std::to_string(step) +
        " (try a smaller learning rate)");
    }
    param.backward(values, dValues, dTheta);
    adam.step(theta, dTheta, rates);
    result.loss.push_back(loss);
    result.iterations = step + 1;
    if (progress)
    {
      const bool snapshot = opt.snapshotEvery > 0 && (step + 1) % opt.snapshotEvery == 0;
      if (snapshot)
      {
        storeCurrent();
      }
      if (!progress(step, loss, snapshot ? &result : nullptr))
      {
        throw Cancelled();
      }
    }
    // Convergence on the smoothed minibatch loss.
    ema = step == 0 ? loss : 0.9 * ema + 0.1 * loss;
    if (ema < bestEma * (1.0 - opt.tolerance))
    {
      bestEma = ema;
      sinceImprovement = 0;
    }
    else if (++sinceImprovement >= opt.patience)
    {
      result.converged = true;
      break;
    }
  }
  storeCurrent();
}

// Checks the options, sets up what is optimised (free bins or Gaussian primitives) and runs
// the loop on `data`.
ReconstructionResult fit(const DifferentiableRenderer& renderer, DataTerm& data,
  const ReconstructionOptions& opt, const ReconstructionProgress& progress)
{
  const auto start = std::chrono::steady_clock::now();
  if (opt.bins < 2 || opt.bins > 4096 ||
    (opt.twoD && (opt.gradientBins < 2 || opt.gradientBins > 1024)))
  {
    throw Error("TF resolution must be 2..4096 bins (gradient bins 2..1024)");
  }
  if (!(opt.ssimWeight >= 0) || opt.ssimPatch < 3)
  {
    throw Error("the SSIM weight must be non-negative and the SSIM patch at least 3 pixels");
  }
  if (opt.primitives < 0 || opt.primitives > 64)
  {
    throw Error("the parametric fit takes 1..64 Gaussian primitives (0: free bins)");
  }
  if (!(opt.learningRate > 0) || opt.iterations < 1 || !(opt.smoothness >= 0) ||
    opt.raysPerIteration < 0)
  {
    throw Error("learning rate and iterations must be positive, smoothness and rays non-negative");
  }
  if (opt.directions < 1)
    throw Error("the sliced Wasserstein distance needs at least one direction");
  if (!opt.initialPrimitives.empty() &&
    static_cast<int>(opt.initialPrimitives.size()) != opt.primitives)
    throw Error("the parametric fit was given " + std::to_string(opt.initialPrimitives.size()) +
      " starting primitives for " + std::to_string(opt.primitives));

  const auto range = renderer.dataRange(); // the whole's, for a piece of a volume
  ResultLayout layout;
  layout.twoD = opt.twoD;
  layout.range = { range[0], range[1] };
  layout.gradientRange = opt.twoD ? renderer.gradientRange() : std::array<double, 2>{ 0, 1 };
  layout.bins = opt.bins;
  layout.gradientBins = opt.twoD ? opt.gradientBins : 1;

  // What is optimised: free bins (logits of every entry) or Gaussian primitives.
  std::unique_ptr<TransferParameterisation> param;
  if (opt.primitives > 0)
  {
    auto primitives = std::make_unique<GaussianPrimitiveParameters>(
      opt.primitives, opt.twoD, layout.range, layout.gradientRange, opt.bins, opt.gradientBins);
    if (!opt.initialPrimitives.empty())
      primitives->startFrom(opt.initialPrimitives);
    param = std::move(primitives);
  }
  else if (opt.twoD)
    param = std::make_unique<FreeBins>(FreeBins::twoD(opt.bins, opt.gradientBins, opt.smoothness));
  else
    param = std::make_unique<FreeBins>(
      FreeBins::oneD(opt.bins, layout.range, opt.smoothness, opt.initial1D));
  if (opt.transparentBelow && !opt.twoD)
    param = std::make_unique<OpacityFloor>(
      std::move(param), opt.bins, layout.range, *opt.transparentBelow);

  TableStage stage(renderer, opt, layout.range, layout.gradientRange);
  ReconstructionResult result;
  result.twoD = opt.twoD;
  optimise(*param, stage, data, layout, opt, progress, result);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

} // namespace

ReconstructionResult reconstructTransferFunction(const DifferentiableRenderer& renderer,
  const std::vector<ReconstructionTarget>& targets, const ReconstructionOptions& opt,
  const ReconstructionProgress& progress)
{
  if (targets.empty())
  {
    throw Error("no target image");
  }
  std::vector<PreparedTarget> prepared;
  for (size_t i = 0; i < targets.size(); ++i)
  {
    prepared.push_back(prepare(targets[i], i));
  }
  ImageLoss data(std::move(prepared), opt);
  return fit(renderer, data, opt, progress);
}

ReconstructionResult reconstructFromColours(const DifferentiableRenderer& renderer,
  const std::vector<ColourTarget>& targets, const ReconstructionOptions& opt,
  const ReconstructionProgress& progress)
{
  if (targets.empty())
    throw Error("no colour target");
  ColourLoss data(targets, opt);
  return fit(renderer, data, opt, progress);
}

TransferFunctionFile resultTransferFunction(
  const ReconstructionResult& result, const std::string& name)
{
  TransferFunctionFile f;
  f.is2D = result.twoD;
  if (f.is2D)
  {
    f.tf2D.name = name;
    f.tf2D.table = result.table2D;
  }
  else
  {
    f.tf1D = tableToTransferFunction(result.table1D, 1.0 / 512.0, name);
  }
  return f;
}

} // namespace ddg
