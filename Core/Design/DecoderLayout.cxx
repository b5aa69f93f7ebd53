// DecoderLayout.cxx: decoder outputs <-> Gaussian primitives, and their image loss and gradient.
#include "Design/DecoderLayout.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>

namespace ddg
{

GaussianPrimitive DecoderLayout::primitive(int r, const float* o) const
{
  const auto& reg = regions[static_cast<size_t>(r)];
  GaussianPrimitive g = basePrimitive(reg);
  g.mean[0] = reg.peak + o[1] * spec.meanShift * (reg.hi - reg.lo);
  g.stddev[0] *= spec.stddevScale[0] + o[2] * (spec.stddevScale[1] - spec.stddevScale[0]);
  g.rgb = { o[3], o[4], o[5] };
  g.opacity = spec.opacity[0] + o[6] * (spec.opacity[1] - spec.opacity[0]);
  if (twoD())
  {
    g.mean[1] = reg.gradientPeak + o[7] * spec.meanShift * (reg.gradientHi - reg.gradientLo);
    g.stddev[1] *= spec.stddevScale[0] + o[8] * (spec.stddevScale[1] - spec.stddevScale[0]);
  }
  return g;
}

std::vector<GaussianPrimitive> DecoderLayout::decodeRegions(const float* o) const
{
  std::vector<GaussianPrimitive> prims;
  for (int r = 0; r < static_cast<int>(regions.size()); ++r)
  {
    // as in training's image loss: opacity x the soft activity sigmoid(logit)
    GaussianPrimitive g = primitive(r, o + outputs() * r);
    g.opacity /= 1.0 + std::exp(-static_cast<double>(o[outputs() * r]));
    prims.push_back(g);
  }
  return prims;
}

std::vector<GaussianPrimitive> DecoderLayout::decode(const float* o) const
{
  std::vector<GaussianPrimitive> prims;
  for (const auto& g : decodeRegions(o))
    if (g.opacity >= kMinOpacity)
      prims.push_back(g);
  return prims;
}

std::vector<float> DecoderLayout::targets(const Exemplar& e) const
{
  std::vector<float> t(static_cast<size_t>(size()), 0.0f);
  for (size_t q = 0; q < e.active.size(); ++q)
  {
    const int r = e.active[q];
    if (r < 0 || r >= static_cast<int>(regions.size()) || q >= e.primitives.size())
      throw Error(
        "an exemplar uses region " + std::to_string(r) + " of " + std::to_string(regions.size()));
    const auto& reg = regions[static_cast<size_t>(r)];
    const auto base = basePrimitive(reg);
    const auto& g = e.primitives[q];
    float* o = &t[static_cast<size_t>(outputs()) * r];
    o[0] = 1.0f;
    const double ds = spec.stddevScale[1] - spec.stddevScale[0];
    auto shift = [&](double mean, double peak, double width)
    {
      const double w = spec.meanShift * width;
      return static_cast<float>(w > 0 ? std::clamp((mean - peak) / w, -1.0, 1.0) : 0.0);
    };
    auto scale = [&](double stddev, double baseStddev)
    {
      return static_cast<float>(
        ds > 0 ? std::clamp((stddev / baseStddev - spec.stddevScale[0]) / ds, 0.0, 1.0) : 0.5);
    };
    o[1] = shift(g.mean[0], reg.peak, reg.hi - reg.lo);
    o[2] = scale(g.stddev[0], base.stddev[0]);
    if (twoD())
    {
      o[7] = shift(g.mean[1], reg.gradientPeak, reg.gradientHi - reg.gradientLo);
      o[8] = scale(g.stddev[1], base.stddev[1]);
    }
    for (int c = 0; c < 3; ++c)
      o[3 + c] = static_cast<float>(g.rgb[c]);
    const double dop = spec.opacity[1] - spec.opacity[0];
    o[6] =
      static_cast<float>(dop > 0 ? std::clamp((g.opacity - spec.opacity[0]) / dop, 0.0, 1.0) : 0.5);
  }
  return t;
}

template <typename S>
double DecoderLayout::imageLoss(const DifferentiableRendererT<S>& renderer, const float* o,
  const View& view, const std::uint8_t* truth, const std::vector<int>& pixels, float* grad,
  double sampleScale) const
{
  if (pixels.empty())
    throw Error("the image loss needs at least one pixel");
  if (!(sampleScale > 0))
    throw Error("the image loss's sample scale must be positive");
  const int n = static_cast<int>(regions.size()), m = outputs();
  const auto range = renderer.caster().dataRange();
  constexpr int kWidth = 256, kHeight = 64; // as renderDesign
  const int height = twoD() ? kHeight : 1;
  std::vector<GaussianPrimitive> prims;
  std::vector<double> activity, opacity;
  for (int r = 0; r < n; ++r)
  {
    GaussianPrimitive g = primitive(r, o + m * r);
    const double act = 1.0 / (1.0 + std::exp(-static_cast<double>(o[m * r])));
    opacity.push_back(g.opacity);
    activity.push_back(act);
    g.opacity *= act;
    prims.push_back(g);
  }
  const auto rgbaTable = twoD() ? rasterize2D(prims, range, gradientRange, kWidth, kHeight).rgba
                                : rasterize1D(prims, range[0], range[1], kWidth).rgba;
  const std::vector<S> table(rgbaTable.begin(), rgbaTable.end());
  RenderOptions ropt;
  ropt.threads = 1; // callers parallelize over exemplars
  if (sampleScale != 1.0)
    ropt.sampleDistance = sampleScale * renderer.caster().defaultSampleDistance();
  std::vector<S> rgba, dRGBA(4 * pixels.size()),
    dTable(4 * static_cast<size_t>(kWidth) * height, S(0));
  std::vector<RayRecord> records;
  if (twoD())
    renderer.forward2D(
      table.data(), kWidth, kHeight, range, gradientRange, view, ropt, pixels, rgba, records);
  else
    renderer.forward(table.data(), kWidth, range[0], range[1], view, ropt, pixels, rgba, records);
  double loss = 0;
  const double norm = 1.0 / (4.0 * static_cast<double>(pixels.size()));
  for (size_t q = 0; q < pixels.size(); ++q)
    for (int c = 0; c < 4; ++c)
    {
      const double d = static_cast<double>(rgba[4 * q + c]) -
        truth[4 * static_cast<size_t>(pixels[q]) + c] / 255.0;
      loss += std::abs(d) * norm;
      dRGBA[4 * q + c] = static_cast<S>(d > 0 ? norm : (d < 0 ? -norm : 0.0));
    }
  if (twoD())
    renderer.backward2D(table.data(), kWidth, kHeight, range, gradientRange, view, ropt, pixels,
      records, dRGBA, dTable);
  else
    renderer.backward(
      table.data(), kWidth, range[0], range[1], view, ropt, pixels, records, dRGBA, dTable);
  std::vector<GaussianPrimitiveGradient> g;
  rasterizeAdjoint(prims, twoD(), range, gradientRange, kWidth, height,
    std::vector<double>(dTable.begin(), dTable.end()), g);
  const double ds = spec.stddevScale[1] - spec.stddevScale[0];
  for (int r = 0; r < n; ++r)
  {
    const auto& reg = regions[static_cast<size_t>(r)];
    const auto& gr = g[static_cast<size_t>(r)];
    const auto base = basePrimitive(reg);
    const double act = activity[static_cast<size_t>(r)];
    float* d = grad + m * r;
    d[0] = static_cast<float>(gr.opacity * opacity[static_cast<size_t>(r)] * act * (1 - act));
    d[1] = static_cast<float>(gr.mean[0] * spec.meanShift * (reg.hi - reg.lo));
    d[2] = static_cast<float>(gr.stddev[0] * base.stddev[0] * ds);
    for (int c = 0; c < 3; ++c)
      d[3 + c] = static_cast<float>(gr.rgb[c]);
    d[6] = static_cast<float>(gr.opacity * act * (spec.opacity[1] - spec.opacity[0]));
    if (twoD())
    {
      d[7] = static_cast<float>(gr.mean[1] * spec.meanShift * (reg.gradientHi - reg.gradientLo));
      d[8] = static_cast<float>(gr.stddev[1] * base.stddev[1] * ds);
    }
  }
  return loss;
}

template double DecoderLayout::imageLoss<float>(const DifferentiableRendererT<float>&, const float*,
  const View&, const std::uint8_t*, const std::vector<int>&, float*, double) const;
template double DecoderLayout::imageLoss<double>(const DifferentiableRendererT<double>&,
  const float*, const View&, const std::uint8_t*, const std::vector<int>&, float*, double) const;

} // namespace ddg
