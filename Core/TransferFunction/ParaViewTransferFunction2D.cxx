// ParaViewTransferFunction2D.cxx: ParaView's Gaussian boxes, their evaluation and the box fit.
#include "TransferFunction/ParaViewTransferFunction2D.h"

#include "Common/Error.h"
#include "Numerics/Adam.h"
#include "Numerics/Logistic.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ddg
{
namespace
{

// vtkPVTransferFunction2DBox: sigma = GaussianSigmaFactor (30) / 100 of the box side.
constexpr double kSigma = 0.3;
constexpr double kInvTwoSigma2 = 1.0 / (2.0 * kSigma * kSigma);

// A box by centre and size (the fit's working form).
struct Box
{
  double cx, cy, w, h;
  double rgb[3];
  double a;
};

Box fromParaView(const ParaViewBox& b)
{
  return { b.x + 0.5 * b.width, b.y + 0.5 * b.height, b.width, b.height,
    { b.rgba[0], b.rgba[1], b.rgba[2] }, b.rgba[3] };
}

ParaViewBox toParaView(const Box& b)
{
  return { b.cx - 0.5 * b.w, b.cy - 0.5 * b.h, b.w, b.h, { b.rgb[0], b.rgb[1], b.rgb[2], b.a } };
}

// Per-sample alpha of box b at (x, y); 0 outside [x0, x0 + w) x [y0, y0 + h).
double boxAlpha(const Box& b, double x, double y, double& dx, double& dy)
{
  dx = x - b.cx;
  dy = y - b.cy;
  if (dx < -0.5 * b.w || dx >= 0.5 * b.w || dy < -0.5 * b.h || dy >= 0.5 * b.h)
  {
    return -1.0; // outside: the box contributes nothing, not even its colour
  }
  return b.a * std::exp(-(dx * dx / (b.w * b.w) + dy * dy / (b.h * b.h)) * kInvTwoSigma2);
}

std::array<double, 4> composite(const std::vector<Box>& boxes, double x, double y)
{
  std::array<double, 4> c{ 0, 0, 0, 0 };
  for (const auto& b : boxes)
  {
    double dx, dy;
    const double alpha = boxAlpha(b, x, y, dx, dy);
    if (alpha < 0)
    {
      continue;
    }
    for (int k = 0; k < 3; ++k)
    {
      c[k] = b.rgb[k] + c[k] * (1 - alpha);
    }
    c[3] = alpha + c[3] * (1 - alpha);
  }
  return c;
}

// Loss (mean over grid points of |E - E*|^2 + (A - A*)^2, E = rgb * A) and, when grad is
// given, its gradient with respect to (cx, cy, w, h, r, g, b, a) of every box (overwritten).
double loss(const std::vector<Box>& boxes, const std::array<double, 4>& range, int gw, int gh,
  const std::vector<double>& target, std::vector<double>* grad)
{
  const size_t K = boxes.size();
  if (grad)
  {
    grad->assign(8 * K, 0.0);
  }
  std::vector<std::array<double, 4>> before(K); // composite before box k (the replay)
  std::vector<double> alphas(K), dxs(K), dys(K);
  const double sx = (range[1] - range[0]) / gw, sy = (range[3] - range[2]) / gh;
  const double norm = 1.0 / (static_cast<double>(gw) * gh);
  double total = 0;
  for (int j = 0; j < gh; ++j)
  {
    const double y = range[2] + (j + 0.5) * sy;
    for (int i = 0; i < gw; ++i)
    {
      const double x = range[0] + (i + 0.5) * sx;
      std::array<double, 4> c{ 0, 0, 0, 0 };
      for (size_t k = 0; k < K; ++k)
      {
        before[k] = c;
        alphas[k] = boxAlpha(boxes[k], x, y, dxs[k], dys[k]);
        if (alphas[k] < 0)
        {
          continue;
        }
        for (int q = 0; q < 3; ++q)
        {
          c[q] = boxes[k].rgb[q] + c[q] * (1 - alphas[k]);
        }
        c[3] = alphas[k] + c[3] * (1 - alphas[k]);
      }
      const double* t = &target[4 * (static_cast<size_t>(j) * gw + i)];
      double e[3];
      double l = (c[3] - t[3]) * (c[3] - t[3]);
      for (int q = 0; q < 3; ++q)
      {
        e[q] = c[q] * c[3] - t[q] * t[3];
        l += e[q] * e[q];
      }
      total += l * norm;
      if (!grad)
      {
        continue;
      }
      // L = |C A - E*|^2 + (A - A*)^2
      double gC[3], gA = 2 * (c[3] - t[3]);
      for (int q = 0; q < 3; ++q)
      {
        gC[q] = 2 * e[q] * c[3] * norm;
        gA += 2 * e[q] * c[q];
      }
      gA *= norm;
      for (size_t k = K; k-- > 0;)
      {
        const double alpha = alphas[k];
        if (alpha < 0)
        {
          continue;
        }
        const Box& b = boxes[k];
        double* g = &(*grad)[8 * k];
        // c.rgb = rgb_k + before.rgb * (1 - alpha);  c.a = alpha + before.a * (1 - alpha)
        double gAlpha = gA * (1 - before[k][3]);
        for (int q = 0; q < 3; ++q)
        {
          g[4 + q] += gC[q];
          gAlpha -= gC[q] * before[k][q];
          gC[q] *= 1 - alpha;
        }
        gA *= 1 - alpha;
        // alpha = a exp(-(dx^2 / w^2 + dy^2 / h^2) / (2 s^2)),  dx = x - cx
        const double s2 = kSigma * kSigma;
        g[0] += gAlpha * alpha * dxs[k] / (s2 * b.w * b.w);
        g[1] += gAlpha * alpha * dys[k] / (s2 * b.h * b.h);
        g[2] += gAlpha * alpha * dxs[k] * dxs[k] / (s2 * b.w * b.w * b.w);
        g[3] += gAlpha * alpha * dys[k] * dys[k] / (s2 * b.h * b.h * b.h);
        g[7] += b.a > 0 ? gAlpha * alpha / b.a
                        : gAlpha *
            std::exp(
              -(dxs[k] * dxs[k] / (b.w * b.w) + dys[k] * dys[k] / (b.h * b.h)) * kInvTwoSigma2);
      }
    }
  }
  return total;
}

void checkRange(const std::array<double, 4>& r)
{
  for (double v : r)
  {
    if (!std::isfinite(v))
    {
      throw Error("ParaView 2D transfer function: Range must be finite");
    }
  }
  if (!(r[0] < r[1]) || !(r[2] < r[3]))
  {
    throw Error("ParaView 2D transfer function: Range must be increasing on both axes");
  }
}

// Colour and opacity logits start from values clamped to [1e-4, 1 - 1e-4].
constexpr double kLogitMargin = 1e-4;

} // namespace

std::array<double, 4> ParaViewTransferFunction2D::evaluate(double x, double y) const
{
  std::vector<Box> b;
  b.reserve(boxes.size());
  for (const auto& box : boxes)
  {
    b.push_back(fromParaView(box));
  }
  return composite(b, x, y);
}

std::string ParaViewTransferFunction2D::toJson(const ParaViewBoxFitReport* report) const
{
  nlohmann::json flat = nlohmann::json::array();
  for (const auto& b : boxes)
  {
    for (double v : { b.x, b.y, b.width, b.height, b.rgba[0], b.rgba[1], b.rgba[2], b.rgba[3] })
    {
      flat.push_back(v);
    }
  }
  nlohmann::json j{ { "Boxes", flat }, { "Range", range },
    { "OutputDimensions", outputDimensions } };
  if (report)
  {
    j["Fit"] = { { "rmse", report->rmse }, { "initial_rmse", report->initialRmse },
      { "alpha_rmse", report->alphaRmse }, { "max_alpha", report->maxAlpha } };
  }
  return j.dump();
}

ParaViewTransferFunction2D ParaViewTransferFunction2D::fromJson(
  const std::string& jsonText, const std::string& origin)
{
  nlohmann::json j;
  try
  {
    j = nlohmann::json::parse(jsonText);
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error(origin + ": is not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("Boxes") || !j["Boxes"].is_array())
  {
    throw Error(origin + ": not a ParaView 2D transfer function (\"Boxes\" missing)");
  }
  ParaViewTransferFunction2D tf;
  try
  {
    const auto flat = j["Boxes"].get<std::vector<double>>();
    if (flat.empty() || flat.size() % 8 != 0)
    {
      throw Error(origin +
        ": \"Boxes\" must hold 8 numbers per box (x, y, width, height, r, g, "
        "b, a), at least one box");
    }
    for (size_t i = 0; i < flat.size(); i += 8)
    {
      const int n = static_cast<int>(i / 8);
      for (size_t k = 0; k < 8; ++k)
      {
        if (!std::isfinite(flat[i + k]))
          throw Error(origin + ": box " + std::to_string(n) + " has a non-finite number");
      }
      if (!(flat[i + 2] > 0) || !(flat[i + 3] > 0))
        throw Error(origin + ": box " + std::to_string(n) + " has no area");
      for (size_t k = 4; k < 8; ++k)
      {
        if (flat[i + k] < 0 || flat[i + k] > 1)
          throw Error(
            origin + ": box " + std::to_string(n) + " has a colour or opacity outside [0, 1]");
      }
      tf.boxes.push_back({ flat[i], flat[i + 1], flat[i + 2], flat[i + 3],
        { flat[i + 4], flat[i + 5], flat[i + 6], flat[i + 7] } });
    }
    if (j.contains("Range"))
      tf.range = j["Range"].get<std::array<double, 4>>();
    if (j.contains("OutputDimensions"))
      tf.outputDimensions = j["OutputDimensions"].get<std::array<int, 2>>();
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error(origin + ": " + e.what());
  }
  try
  {
    checkRange(tf.range);
  }
  catch (const Error& e)
  {
    throw Error(origin + ": " + e.what());
  }
  if (tf.outputDimensions[0] < 1 || tf.outputDimensions[1] < 1 || tf.outputDimensions[0] > 8192 ||
    tf.outputDimensions[1] > 8192)
  {
    throw Error(origin + ": OutputDimensions must be 1..8192 on both axes");
  }
  return tf;
}

std::vector<float> ParaViewTransferFunction2D::functionImage() const
{
  checkRange(range);
  const int W = outputDimensions[0], H = outputDimensions[1];
  std::vector<float> image(4 * static_cast<size_t>(W) * H, 0.0f);
  const double spacing[2] = { (range[1] - range[0]) / W, (range[3] - range[2]) / H };
  // vtkPVTransferFunction2DBox: a 128 x 128 unsigned char texture, colour * 255 and the
  // Gaussian amp * exp(-r^2 / (2 sigma^2)) around texel 64, sigma = 0.3 * 128, truncated.
  constexpr int kTexture = 128;
  const double sigma = 0.3 * kTexture;
  for (const auto& b : boxes)
  {
    const auto pixels = [&](double v, double lo, double hi, double step, int n)
    {
      const auto p = static_cast<std::int64_t>((v - lo) / step);
      return v <= lo ? std::int64_t(0) : v >= hi ? std::int64_t(n) : p;
    };
    if (static_cast<std::int64_t>(b.width / spacing[0]) <= 0 ||
      static_cast<std::int64_t>(b.height / spacing[1]) <= 0)
    {
      continue;
    }
    const std::int64_t x0 = pixels(b.x, range[0], range[1], spacing[0], W),
                       x1 = pixels(b.x + b.width, range[0], range[1], spacing[0], W),
                       y0 = pixels(b.y, range[2], range[3], spacing[1], H),
                       y1 = pixels(b.y + b.height, range[2], range[3], spacing[1], H);
    float rgb[3];
    for (int c = 0; c < 3; ++c)
      rgb[c] = static_cast<float>(static_cast<unsigned char>(b.rgba[c] * 255) / 255.0);
    const double amp = b.rgba[3] * 255;
    const double texel[2] = { b.width / kTexture, b.height / kTexture };
    for (std::int64_t jj = y0; jj < y1; ++jj)
    {
      const int ty = std::clamp(
        static_cast<int>((jj * spacing[1] + range[2] - b.y) / texel[1]), 0, kTexture - 1);
      for (std::int64_t ii = x0; ii < x1; ++ii)
      {
        const int tx = std::clamp(
          static_cast<int>((ii * spacing[0] + range[0] - b.x) / texel[0]), 0, kTexture - 1);
        const double r2 = (tx - kTexture / 2.0) * (tx - kTexture / 2.0) +
          (ty - kTexture / 2.0) * (ty - kTexture / 2.0);
        const auto a8 = static_cast<unsigned char>(amp * std::exp(-r2 / (2 * sigma * sigma)));
        const float a = static_cast<float>(a8 / 255.0);
        float* c = &image[4 * (static_cast<size_t>(jj) * W + static_cast<size_t>(ii))];
        for (int q = 0; q < 3; ++q)
          c[q] = rgb[q] + c[q] * (1 - a);
        c[3] = a + c[3] * (1 - a);
      }
    }
  }
  return image;
}

TransferTable2D ParaViewTransferFunction2D::table(const ParaViewTransfer2DMapping& mapping) const
{
  const auto power2 = [](int n) { return n >= 1024 && (n & (n - 1)) == 0; };
  if (!power2(outputDimensions[0]) || !power2(outputDimensions[1]))
  {
    throw Error("ParaView 2D transfer function: OutputDimensions " +
      std::to_string(outputDimensions[0]) + " x " + std::to_string(outputDimensions[1]) +
      " are resampled by ParaView's mapper (a Lanczos filter ddg does not reproduce): use a "
      "power of two of at least 1024 on both axes, e.g. [1024, 1024]");
  }
  if (!(mapping.gradientScale > 0) || !(mapping.gradientMax > 0) ||
    !(mapping.opacityExponent > 0) || !(mapping.valueRange[1] > mapping.valueRange[0]))
  {
    throw Error("ParaView 2D transfer function: the volume's mapping is empty");
  }
  TransferTable2D t;
  t.valueRange = mapping.valueRange;
  t.gradientRange = { 0.0, mapping.gradientMax / mapping.gradientScale };
  t.width = outputDimensions[0];
  t.height = outputDimensions[1];
  t.rgba = functionImage();
  const double inverse = 1.0 / mapping.opacityExponent;
  for (size_t i = 0; i < t.rgba.size(); i += 4)
  {
    for (size_t c = 0; c < 3; ++c)
      t.rgba[i + c] = std::clamp(t.rgba[i + c], 0.0f, 1.0f);
    // our renderer corrects a to 1 - (1 - a)^exponent per sample: undo it
    const double a = std::clamp(static_cast<double>(t.rgba[i + 3]), 0.0, 1.0);
    t.rgba[i + 3] = static_cast<float>(a > 1e-4 ? 1 - std::pow(1 - a, inverse) : a);
  }
  return t;
}

ParaViewTransfer2DMapping ParaViewTransfer2DMapping::forVolume(const std::array<int, 3>& dims,
  const std::array<double, 3>& spacing, const std::array<double, 2>& valueRange,
  double sampleDistance, double unitDistance)
{
  if (!(valueRange[1] > valueRange[0]) || !std::isfinite(valueRange[0]) ||
    !std::isfinite(valueRange[1]))
  {
    throw Error("ParaView 2D mapping: the data range is empty");
  }
  if (!(sampleDistance > 0) || !(unitDistance > 0) || !std::isfinite(sampleDistance) ||
    !std::isfinite(unitDistance))
  {
    throw Error("ParaView 2D mapping: sample and opacity unit distances must be positive");
  }
  double meanSpacing = 0;
  int axes = 0;
  for (int a = 0; a < 3; ++a)
  {
    meanSpacing += spacing[a] / 3.0;
    axes += dims[a] > 1 ? 1 : 0;
  }
  if (axes == 0 || !(meanSpacing > 0))
  {
    throw Error("ParaView 2D mapping: the volume has no extent");
  }
  ParaViewTransfer2DMapping m;
  m.valueRange = valueRange;
  m.gradientScale = meanSpacing; // Y = avgS G exactly (transferGradient, Render/Lighting.h)
  m.gradientMax = 0.25 * (valueRange[1] - valueRange[0]);
  m.opacityExponent = sampleDistance / unitDistance;
  return m;
}

double paraViewBoxLoss(const std::vector<ParaViewBox>& boxes, const std::array<double, 4>& range,
  int gridWidth, int gridHeight, const std::vector<double>& target, std::vector<double>* dL_dBoxes)
{
  checkRange(range);
  if (gridWidth < 1 || gridHeight < 1 ||
    target.size() != 4 * static_cast<size_t>(gridWidth) * gridHeight)
  {
    throw Error("ParaView box loss: the target does not match the grid");
  }
  std::vector<Box> b;
  for (const auto& box : boxes)
  {
    b.push_back(fromParaView(box));
  }
  const double l = loss(b, range, gridWidth, gridHeight, target, dL_dBoxes);
  if (dL_dBoxes)
  {
    // lower-left corner: cx = x + w / 2, so dL/dw at fixed x adds dL/dcx / 2
    for (size_t k = 0; k < boxes.size(); ++k)
    {
      double* g = &(*dL_dBoxes)[8 * k];
      g[2] += 0.5 * g[0];
      g[3] += 0.5 * g[1];
    }
  }
  return l;
}

ParaViewTransferFunction2D fitParaViewBoxes(const TransferFunction2D& tf,
  const ParaViewTransfer2DMapping& mapping, const ParaViewBoxFitOptions& options,
  ParaViewBoxFitReport* report)
{
  if (options.maxBoxes < 1 || options.maxBoxes > 256 || options.iterations < 0 ||
    options.gridWidth < 2 || options.gridHeight < 2)
  {
    throw Error("ParaView box fit: maxBoxes must be 1..256, iterations >= 0 and the grid >= 2 x 2");
  }
  if (!(mapping.gradientScale > 0) || !(mapping.gradientMax > 0) ||
    !(mapping.opacityExponent > 0) || !std::isfinite(mapping.gradientScale) ||
    !std::isfinite(mapping.gradientMax) || !std::isfinite(mapping.opacityExponent))
  {
    throw Error("ParaView box fit: the mapping's scales must be positive and finite");
  }
  ParaViewTransferFunction2D out;
  out.range = { mapping.valueRange[0], mapping.valueRange[1], 0.0, mapping.gradientMax };
  checkRange(out.range);
  const TransferTable2D table = tf.bake(); // validates
  const bool fromPrimitives = tf.table.rgba.empty() && !tf.primitives.empty() &&
    static_cast<int>(tf.primitives.size()) <= options.maxBoxes;

  // --- the target on the fit grid (per-sample alpha, straight colour) ---
  const int gw = options.gridWidth, gh = options.gridHeight;
  const auto& R = out.range;
  const double sx = (R[1] - R[0]) / gw, sy = (R[3] - R[2]) / gh;
  std::vector<double> target(4 * static_cast<size_t>(gw) * gh);
  double maxAlpha = 0;
  for (int j = 0; j < gh; ++j)
  {
    for (int i = 0; i < gw; ++i)
    {
      const auto v =
        table.lookup(R[0] + (i + 0.5) * sx, (R[2] + (j + 0.5) * sy) / mapping.gradientScale);
      double* t = &target[4 * (static_cast<size_t>(j) * gw + i)];
      const double a = std::clamp(static_cast<double>(v[3]), 0.0, 1.0);
      t[3] = a > 1e-4 ? 1 - std::pow(1 - a, mapping.opacityExponent) : a;
      for (int q = 0; q < 3; ++q)
      {
        t[q] = std::clamp(static_cast<double>(v[q]), 0.0, 1.0);
      }
      maxAlpha = std::max(maxAlpha, t[3]);
    }
  }

  // --- initial boxes ---
  std::vector<Box> boxes;
  if (fromPrimitives)
  {
    for (const auto& p : tf.primitives)
    {
      const double a = 1 - std::pow(1 - std::clamp(p.opacity, 0.0, 1.0), mapping.opacityExponent);
      boxes.push_back({ p.mean[0], p.mean[1] * mapping.gradientScale, p.stddev[0] / kSigma,
        p.stddev[1] * mapping.gradientScale / kSigma, { p.rgb[0], p.rgb[1], p.rgb[2] }, a });
    }
    std::stable_sort(
      boxes.begin(), boxes.end(), [](const Box& a, const Box& b) { return a.a < b.a; });
  }
  else
  {
    // Greedy: a box at the largest residual alpha, sized from its half-maximum extent.
    std::vector<double> residual(static_cast<size_t>(gw) * gh);
    for (size_t p = 0; p < residual.size(); ++p)
    {
      residual[p] = target[4 * p + 3];
    }
    for (int k = 0; k < options.maxBoxes; ++k)
    {
      const size_t p =
        static_cast<size_t>(std::max_element(residual.begin(), residual.end()) - residual.begin());
      const double peak = residual[p];
      if (peak <= std::max(1e-4, 0.02 * maxAlpha))
      {
        break;
      }
      const int pi = static_cast<int>(p % gw), pj = static_cast<int>(p / gw);
      auto extent = [&](int di, int dj)
      {
        int n = 0;
        for (int i = pi + di, j = pj + dj; i >= 0 && i < gw && j >= 0 && j < gh &&
             residual[static_cast<size_t>(j) * gw + i] > 0.5 * peak;
             i += di, j += dj)
        {
          ++n;
        }
        return n;
      };
      const int l = extent(-1, 0), r = extent(1, 0), d = extent(0, -1), u = extent(0, 1);
      // FWHM = 2.355 sigma; side = sigma / 0.3
      const double w = std::max(2.0, (l + r + 1) / 2.355 / kSigma) * sx;
      const double h = std::max(2.0, (d + u + 1) / 2.355 / kSigma) * sy;
      Box b{ R[0] + (pi + 0.5 + 0.5 * (r - l)) * sx, R[2] + (pj + 0.5 + 0.5 * (u - d)) * sy, w, h,
        { target[4 * p], target[4 * p + 1], target[4 * p + 2] }, peak };
      for (int j = 0; j < gh; ++j)
      {
        for (int i = 0; i < gw; ++i)
        {
          double dx, dy;
          const double alpha = boxAlpha(b, R[0] + (i + 0.5) * sx, R[2] + (j + 0.5) * sy, dx, dy);
          double& res = residual[static_cast<size_t>(j) * gw + i];
          res = alpha > 0 ? std::max(0.0, res - alpha) : res;
        }
      }
      boxes.push_back(b);
    }
    std::reverse(boxes.begin(), boxes.end()); // the strongest box composited last (on top)
  }

  // --- joint refinement: Adam on (centre, log size, colour and opacity logits) ---
  const double RX = R[1] - R[0], RY = R[3] - R[2];
  const size_t n = 8 * boxes.size();
  std::vector<double> theta(n), grad;
  auto unpack = [&](std::vector<Box>& out)
  {
    out.resize(boxes.size());
    for (size_t k = 0; k < boxes.size(); ++k)
    {
      const double* t = &theta[8 * k];
      out[k] = { R[0] + t[0] * RX, R[2] + t[1] * RY, RX * std::exp(t[2]), RY * std::exp(t[3]),
        { sigmoid(t[4]), sigmoid(t[5]), sigmoid(t[6]) }, sigmoid(t[7]) };
    }
  };
  for (size_t k = 0; k < boxes.size(); ++k)
  {
    const Box& b = boxes[k];
    double* t = &theta[8 * k];
    t[0] = (b.cx - R[0]) / RX;
    t[1] = (b.cy - R[2]) / RY;
    t[2] = std::log(std::max(b.w, 1e-6 * RX) / RX);
    t[3] = std::log(std::max(b.h, 1e-6 * RY) / RY);
    for (int q = 0; q < 3; ++q)
    {
      t[4 + q] = logit(b.rgb[q], kLogitMargin);
    }
    t[7] = logit(b.a, kLogitMargin);
  }
  unpack(boxes);
  const double initial = loss(boxes, R, gw, gh, target, nullptr);
  // per-parameter learning rates: centres, log sizes, colour and opacity logits
  const double rates[8] = { 0.005, 0.005, 0.02, 0.02, 0.05, 0.05, 0.05, 0.05 };
  std::vector<double> learningRates(n);
  for (size_t i = 0; i < n; ++i)
  {
    learningRates[i] = rates[i % 8];
  }
  Adam adam(AdamOptions{ 0.9, 0.999, 1e-12 }, n);
  double best = initial;
  std::vector<Box> bestBoxes = boxes, current = boxes;
  for (int it = 1; it <= options.iterations && !boxes.empty(); ++it)
  {
    const double l = loss(current, R, gw, gh, target, &grad);
    if (l < best)
    {
      best = l;
      bestBoxes = current;
    }
    for (size_t k = 0; k < current.size(); ++k)
    {
      const Box& b = current[k];
      double* g = &grad[8 * k];
      // chain rule to theta: cx = R0 + t0 RX, w = RX exp(t2), rgb = sigmoid(t4..6), a = sigmoid(t7)
      g[0] *= RX;
      g[1] *= RY;
      g[2] *= b.w;
      g[3] *= b.h;
      for (int q = 0; q < 3; ++q)
      {
        g[4 + q] *= b.rgb[q] * (1 - b.rgb[q]);
      }
      g[7] *= b.a * (1 - b.a);
    }
    adam.step(theta, grad, learningRates);
    for (size_t k = 0; k < current.size(); ++k)
    {
      theta[8 * k + 2] = std::clamp(theta[8 * k + 2], std::log(1.0 / gw), std::log(4.0));
      theta[8 * k + 3] = std::clamp(theta[8 * k + 3], std::log(1.0 / gh), std::log(4.0));
      for (int q = 4; q < 8; ++q)
      {
        theta[8 * k + q] = std::clamp(theta[8 * k + q], -12.0, 12.0);
      }
    }
    unpack(current);
  }
  if (!boxes.empty())
  {
    const double l = loss(current, R, gw, gh, target, nullptr);
    if (l < best)
    {
      best = l;
      bestBoxes = current;
    }
  }
  for (const auto& b : bestBoxes)
  {
    out.boxes.push_back(toParaView(b));
  }
  if (report)
  {
    report->initialRmse = std::sqrt(initial / 4);
    report->rmse = std::sqrt(best / 4);
    double alphaErr = 0;
    for (int j = 0; j < gh; ++j)
    {
      for (int i = 0; i < gw; ++i)
      {
        const auto c = composite(bestBoxes, R[0] + (i + 0.5) * sx, R[2] + (j + 0.5) * sy);
        const double d = c[3] - target[4 * (static_cast<size_t>(j) * gw + i) + 3];
        alphaErr += d * d;
      }
    }
    report->alphaRmse = std::sqrt(alphaErr / (static_cast<double>(gw) * gh));
    report->maxAlpha = maxAlpha;
    report->iterations = options.iterations;
  }
  return out;
}

} // namespace ddg
