// Reconstruction.cxx: Adam on logit-parameterised TF bins, losses, prior, convergence.
#include "Reconstruct/Reconstruction.h"

#include "Common/Error.h"
#include "Image/ImageMetrics.h"
#include "Render/RayCaster.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <sstream>

namespace ddg
{
namespace
{

double sigmoid(double x)
{
  return 1.0 / (1.0 + std::exp(-x));
}
double logit(double p)
{
  p = std::clamp(p, 1e-6, 1.0 - 1e-6);
  return std::log(p / (1.0 - p));
}

// A target prepared for the loss: what each pixel should be, in the render's terms.
struct PreparedTarget
{
  const ReconstructionTarget* source = nullptr;
  bool alpha = false;          // compare premultiplied RGBA, else RGB over the background
  std::vector<float> value;    // 4 (alpha) or 3 values per pixel
  std::vector<float> weight;   // per pixel (mask), empty = 1
  std::vector<int> candidates; // pixels with weight > 0
  std::array<double, 3> background{ 0, 0, 0 };
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
  p.background = v.background;
  const size_t n = static_cast<size_t>(v.width) * v.height;
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
        anything = anything || std::abs(px[c] - p.background[c]) > 1.5 / 255.0;
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
    for (int c = 0; c < 3; ++c)
    {
      const double out = rgba[c] + (1.0 - rgba[3]) * t.background[c];
      double d;
      L += term(out - target[c], d);
      dL_drgba[c] += static_cast<float>(w * scale * d);
      dL_drgba[3] -= static_cast<float>(w * scale * d * t.background[c]);
    }
  }
  return w * scale * L;
}

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

// The parametric fit: K Gaussian primitives of 8 unconstrained numbers each: mean and log width
// per axis in units of that axis' range, then colour and peak-opacity logits.
struct PrimitiveParameters
{
  static constexpr int kPer = 8;
  bool twoD = false;
  std::array<double, 2> lo{ 0, 0 }, span{ 1, 1 };

  void initialise(int count, std::vector<double>& theta) const
  {
    theta.assign(static_cast<size_t>(count) * kPer, 0.0);
    for (int k = 0; k < count; ++k)
    {
      double* t = &theta[static_cast<size_t>(k) * kPer];
      t[0] = (k + 0.5) / count;
      t[1] = 0.5;
      t[2] = std::log(0.5 / count);
      t[3] = std::log(0.5);
      t[4] = t[5] = t[6] = logit(0.5);
      t[7] = logit(0.05);
    }
  }
  std::vector<GaussianPrimitive> decode(const std::vector<double>& theta) const
  {
    std::vector<GaussianPrimitive> out(theta.size() / kPer);
    for (size_t k = 0; k < out.size(); ++k)
    {
      const double* t = &theta[k * kPer];
      for (int a = 0; a < 2; ++a)
      {
        out[k].mean[a] = lo[a] + t[a] * span[a];
        out[k].stddev[a] = std::exp(std::clamp(t[2 + a], -12.0, 3.0)) * span[a];
      }
      for (int c = 0; c < 3; ++c)
        out[k].rgb[c] = sigmoid(t[4 + c]);
      out[k].opacity = sigmoid(t[7]);
    }
    return out;
  }
  // dL/dtheta from dL/d(primitive parameters).
  void chain(const std::vector<GaussianPrimitive>& p,
    const std::vector<GaussianPrimitiveGradient>& g, std::vector<double>& dTheta) const
  {
    for (size_t k = 0; k < p.size(); ++k)
    {
      double* d = &dTheta[k * kPer];
      for (int a = 0; a < (twoD ? 2 : 1); ++a)
      {
        d[a] = g[k].mean[a] * span[a];
        d[2 + a] = g[k].stddev[a] * p[k].stddev[a];
      }
      for (int c = 0; c < 3; ++c)
        d[4 + c] = g[k].rgb[c] * p[k].rgb[c] * (1 - p[k].rgb[c]);
      d[7] = g[k].opacity * p[k].opacity * (1 - p[k].opacity);
    }
  }
  // Adam step of each slot relative to the learning rate: positions and widths move in units
  // of the range, so more slowly than logits.
  static double stepScale(size_t i)
  {
    const size_t slot = i % kPer;
    return slot < 2 ? 0.1 : slot < 4 ? 0.25 : 1.0;
  }
};

} // namespace

ReconstructionResult reconstructTransferFunction(const DifferentiableRenderer& renderer,
  const std::vector<ReconstructionTarget>& targets, const ReconstructionOptions& opt,
  const ReconstructionProgress& progress)
{
  const auto start = std::chrono::steady_clock::now();
  if (targets.empty())
  {
    throw Error("no target image");
  }
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
  std::vector<PreparedTarget> prepared;
  for (size_t i = 0; i < targets.size(); ++i)
  {
    prepared.push_back(prepare(targets[i], i));
  }

  const Volume& vol = renderer.caster().volume();
  const auto range = vol.range();
  ReconstructionResult result;
  result.twoD = opt.twoD;
  const int B = opt.bins;
  const int G = opt.twoD ? opt.gradientBins : 1;
  const size_t nBins = static_cast<size_t>(B) * G;
  const std::array<double, 2> gradientRange =
    opt.twoD ? vol.gradientMagnitudeRange() : std::array<double, 2>{ 0, 1 };

  // Parameters: logits of rgb and opacity per bin, or the primitives' parameters.
  const int K = opt.primitives;
  PrimitiveParameters prim;
  prim.twoD = opt.twoD;
  prim.lo = { range[0], gradientRange[0] };
  prim.span = { range[1] - range[0], gradientRange[1] - gradientRange[0] };
  std::vector<double> theta;
  if (K > 0)
    prim.initialise(K, theta);
  else
    theta.resize(4 * nBins);
  for (size_t b = 0; K == 0 && b < nBins; ++b)
  {
    double init[4] = { 0.5, 0.5, 0.5, 0.02 };
    if (opt.initial1D && !opt.twoD)
    {
      const double x = range[0] + (b % B) * (range[1] - range[0]) / (B - 1);
      const auto v = opt.initial1D->lookup(x);
      for (int c = 0; c < 4; ++c)
        init[c] = v[c];
    }
    for (int c = 0; c < 4; ++c)
      theta[4 * b + c] = logit(init[c]);
  }
  BinsToTable map;
  TransferFunction1D spacingProbe;
  if (!opt.twoD)
  {
    // ParaView's table width for nodes every (max - min) / (B - 1)
    spacingProbe.color = { { range[0], 0, 0, 0 },
      { range[0] + (range[1] - range[0]) / (B - 1), 0, 0, 0 } };
    spacingProbe.opacity = { { range[0], 0 } };
    map.setup(B, paraviewTableWidth(spacingProbe, range[0], range[1]));
  }

  // The current TF's bins (RGBA, uncorrected opacity): sigmoid of the parameters, or the
  // primitives rasterized.
  std::vector<GaussianPrimitive> primitives;
  auto currentValues = [&](std::vector<double>& out)
  {
    out.resize(4 * nBins);
    if (K == 0)
    {
      for (size_t i = 0; i < theta.size(); ++i)
        out[i] = sigmoid(theta[i]);
      return;
    }
    primitives = prim.decode(theta);
    const std::vector<float> raster = opt.twoD
      ? rasterize2D(primitives, { range[0], range[1] }, gradientRange, B, G).rgba
      : rasterize1D(primitives, range[0], range[1], B).rgba;
    std::copy(raster.begin(), raster.end(), out.begin());
  };

  // The current TF into result's tables.
  auto fillTables = [&](ReconstructionResult& r)
  {
    std::vector<double> v;
    currentValues(v);
    std::vector<float> current(v.begin(), v.end());
    r.primitives = primitives;
    if (opt.twoD)
    {
      r.table2D.valueRange = { range[0], range[1] };
      r.table2D.gradientRange = gradientRange;
      r.table2D.width = B;
      r.table2D.height = G;
      r.table2D.rgba = std::move(current);
    }
    else
    {
      r.table1D.min = range[0];
      r.table1D.max = range[1];
      r.table1D.width = B;
      r.table1D.rgba = std::move(current);
    }
  };

  std::vector<double> m(theta.size(), 0.0), v2(theta.size(), 0.0);
  const double beta1 = 0.9, beta2 = 0.999, eps = 1e-8;
  std::mt19937 rng(opt.seed);
  RenderOptions ropt = opt.render;
  ropt.jitter = false;

  std::vector<double> values(4 * nBins);
  std::vector<float> table, dTable;
  std::vector<double> dValues(4 * nBins), dTheta(theta.size());
  std::vector<GaussianPrimitiveGradient> dPrimitives;
  std::vector<int> pixels;
  std::vector<float> rgba, dRGBA;
  std::vector<RayRecord> records;
  double ema = 0, bestEma = std::numeric_limits<double>::infinity();
  int sinceImprovement = 0;

  // Forward and backward passes of the current table (1D through the bins map, or 2D).
  auto renderOn = [&](const View& view, const std::vector<int>& px, std::vector<float>& out,
                    std::vector<RayRecord>& rec)
  {
    if (opt.twoD)
      renderer.forward2D(
        table.data(), B, G, { range[0], range[1] }, gradientRange, view, ropt, px, out, rec);
    else
      renderer.forward(table.data(), map.width, range[0], range[1], view, ropt, px, out, rec);
  };
  auto backpropagate = [&](const View& view, const std::vector<int>& px,
                         const std::vector<RayRecord>& rec, const std::vector<float>& dOut)
  {
    if (opt.twoD)
      renderer.backward2D(table.data(), B, G, { range[0], range[1] }, gradientRange, view, ropt, px,
        rec, dOut, dTable);
    else
      renderer.backward(
        table.data(), map.width, range[0], range[1], view, ropt, px, rec, dOut, dTable);
  };

  // (1 - SSIM) on a random patch of a target, rendered in full; adds its gradient to dTable.
  auto ssimPatchTerm = [&](const PreparedTarget& t, std::mt19937& gen)
  {
    const View& view = t.source->view;
    const int pw = std::min(opt.ssimPatch, view.width), ph = std::min(opt.ssimPatch, view.height);
    std::uniform_int_distribution<int> px(0, view.width - pw), py(0, view.height - ph);
    const int x0 = px(gen), y0 = py(gen);
    std::vector<int> patch;
    for (int y = y0; y < y0 + ph; ++y)
      for (int x = x0; x < x0 + pw; ++x)
        patch.push_back(y * view.width + x);
    std::vector<float> prgba, pd;
    std::vector<RayRecord> prec;
    renderOn(view, patch, prgba, prec);
    // the images SSIM compares: over the background (opaque targets) or premultiplied rgb
    std::vector<float> ours(patch.size() * 3), theirs(patch.size() * 3);
    for (size_t q = 0; q < patch.size(); ++q)
      for (int c = 0; c < 3; ++c)
      {
        ours[3 * q + c] = t.alpha
          ? prgba[4 * q + c]
          : static_cast<float>(prgba[4 * q + c] + (1 - prgba[4 * q + 3]) * t.background[c]);
        theirs[3 * q + c] = t.value[(t.alpha ? 4 : 3) * static_cast<size_t>(patch[q]) + c];
      }
    std::vector<double> dS(ours.size());
    const double sVal = ssimWithGradient(ours.data(), theirs.data(), pw, ph, dS.data());
    const double k = opt.ssimWeight / static_cast<double>(prepared.size());
    pd.assign(prgba.size(), 0.0f);
    for (size_t q = 0; q < patch.size(); ++q)
      for (int c = 0; c < 3; ++c)
      {
        const double g = -k * dS[3 * q + c]; // d(k (1 - S)) / d(image)
        pd[4 * q + c] += static_cast<float>(g);
        if (!t.alpha)
          pd[4 * q + 3] -= static_cast<float>(g * t.background[c]);
      }
    backpropagate(view, patch, prec, pd);
    return k * (1.0 - sVal);
  };

  for (int step = 0; step < opt.iterations; ++step)
  {
    currentValues(values);
    if (opt.twoD)
    {
      table.assign(values.begin(), values.end());
    }
    else
    {
      map.forward(values, table);
    }
    dTable.assign(table.size(), 0.0f);
    double loss = 0;
    for (auto& t : prepared)
    {
      // random subset of the candidate pixels
      const size_t want = opt.raysPerIteration > 0
        ? std::min(t.candidates.size(), static_cast<size_t>(opt.raysPerIteration))
        : t.candidates.size();
      if (want < t.candidates.size())
      {
        for (size_t i = 0; i < want; ++i)
        {
          std::uniform_int_distribution<size_t> pick(i, t.candidates.size() - 1);
          std::swap(t.candidates[i], t.candidates[pick(rng)]);
        }
      }
      pixels.assign(t.candidates.begin(), t.candidates.begin() + static_cast<std::ptrdiff_t>(want));
      std::sort(pixels.begin(), pixels.end()); // neighbouring rays together: cache locality
      const View& view = t.source->view;
      renderOn(view, pixels, rgba, records);
      dRGBA.assign(rgba.size(), 0.0f);
      const double scale = 1.0 / (static_cast<double>(want) * (t.alpha ? 4 : 3) * prepared.size());
      for (size_t q = 0; q < pixels.size(); ++q)
      {
        loss += pixelLoss(t, pixels[q], &rgba[4 * q], opt.loss, scale, &dRGBA[4 * q]);
      }
      backpropagate(view, pixels, records, dRGBA);
      if (opt.ssimWeight > 0)
      {
        loss += ssimPatchTerm(t, rng);
      }
    }
    std::fill(dValues.begin(), dValues.end(), 0.0);
    if (opt.twoD)
    {
      for (size_t i = 0; i < dValues.size(); ++i)
        dValues[i] = dTable[i];
    }
    else
    {
      map.backward(dTable, dValues);
    }
    // Smoothness prior: lambda * mean over neighbour pairs of squared differences (all channels).
    if (opt.smoothness > 0 && K == 0)
    {
      std::vector<std::pair<size_t, size_t>> pairs;
      for (int g = 0; g < G; ++g)
        for (int b = 0; b < B; ++b)
        {
          const size_t i = static_cast<size_t>(g) * B + b;
          if (b + 1 < B)
            pairs.push_back({ i, i + 1 });
          if (g + 1 < G)
            pairs.push_back({ i, i + B });
        }
      const double k = opt.smoothness / static_cast<double>(pairs.size());
      for (const auto& [a, b] : pairs)
        for (int c = 0; c < 4; ++c)
        {
          const double d = values[4 * b + c] - values[4 * a + c];
          loss += k * d * d;
          dValues[4 * b + c] += 2 * k * d;
          dValues[4 * a + c] -= 2 * k * d;
        }
    }
    if (!std::isfinite(loss))
    {
      throw Error("the loss became NaN or infinite at step " + std::to_string(step) +
        " (try a smaller learning rate)");
    }
    // Adam on the unconstrained parameters (logits of the bins, or the primitives').
    if (K == 0)
    {
      for (size_t i = 0; i < theta.size(); ++i)
        dTheta[i] = dValues[i] * values[i] * (1.0 - values[i]);
    }
    else
    {
      rasterizeAdjoint(primitives, opt.twoD, { range[0], range[1] }, gradientRange, B, G, dValues,
        dPrimitives);
      prim.chain(primitives, dPrimitives, dTheta);
    }
    const double c1 = 1.0 - std::pow(beta1, step + 1), c2 = 1.0 - std::pow(beta2, step + 1);
    for (size_t i = 0; i < theta.size(); ++i)
    {
      const double g = dTheta[i];
      const double lr = K == 0 ? opt.learningRate : opt.learningRate * PrimitiveParameters::stepScale(i);
      m[i] = beta1 * m[i] + (1 - beta1) * g;
      v2[i] = beta2 * v2[i] + (1 - beta2) * g * g;
      theta[i] -= lr * (m[i] / c1) / (std::sqrt(v2[i] / c2) + eps);
    }
    result.loss.push_back(loss);
    result.iterations = step + 1;
    if (progress)
    {
      const bool snapshot = opt.snapshotEvery > 0 && (step + 1) % opt.snapshotEvery == 0;
      if (snapshot)
      {
        fillTables(result);
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

  fillTables(result);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

Image renderResult(const RayCaster& caster, const ReconstructionResult& result, const View& view,
  const RenderOptions& options)
{
  if (result.twoD)
  {
    return caster.render(result.table2D, view, options);
  }
  // Exactly what ParaView will do with the preset: nodes at the bins, its own table.
  return caster.render(
    caster.paraviewTable(tableToTransferFunction(result.table1D, 0.0)), view, options);
}

} // namespace ddg
