// RayCaster.cxx: prepared volume, per-render tables, block skipping and the ray march.
#include "Render/RayCaster.h"

#include "Common/Parallel.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <sstream>

namespace ddg
{
namespace
{

constexpr int kBlock = 8; // cells per block side for empty-space skipping
constexpr int kTile = 16; // pixels per tile side (unit of parallel work)

// Volume prepared for the march: normalised scalar field w = q * value, block min/max.
struct Field
{
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> w;
  int bx = 0, by = 0, bz = 0;
  std::vector<float> blockMin, blockMax;

  void build(int dx, int dy, int dz, std::vector<float> values)
  {
    nx = dx;
    ny = dy;
    nz = dz;
    w = std::move(values);
    bx = std::max(1, (nx - 1 + kBlock - 1) / kBlock);
    by = std::max(1, (ny - 1 + kBlock - 1) / kBlock);
    bz = std::max(1, (nz - 1 + kBlock - 1) / kBlock);
    blockMin.assign(static_cast<size_t>(bx) * by * bz, 0.0f);
    blockMax.assign(blockMin.size(), 0.0f);
    parallelFor(bz, 0, [&](std::int64_t c, int) {
      for (int b = 0; b < by; ++b)
      {
        for (int a = 0; a < bx; ++a)
        {
          float lo = w[index(a * kBlock, b * kBlock, static_cast<int>(c) * kBlock)], hi = lo;
          for (int k = static_cast<int>(c) * kBlock; k <= std::min(nz - 1, (static_cast<int>(c) + 1) * kBlock); ++k)
            for (int j = b * kBlock; j <= std::min(ny - 1, (b + 1) * kBlock); ++j)
              for (int i = a * kBlock; i <= std::min(nx - 1, (a + 1) * kBlock); ++i)
              {
                const float v = w[index(i, j, k)];
                lo = std::min(lo, v);
                hi = std::max(hi, v);
              }
          const size_t id = (static_cast<size_t>(c) * by + b) * bx + a;
          blockMin[id] = lo;
          blockMax[id] = hi;
        }
      }
    });
  }

  size_t index(int i, int j, int k) const
  {
    return static_cast<size_t>(i) + static_cast<size_t>(nx) * (static_cast<size_t>(j) + static_cast<size_t>(ny) * k);
  }

  // Trilinear interpolation at index coordinates, clamped to the grid (nx, ny, nz >= 2).
  float sample(float x, float y, float z) const
  {
    x = std::clamp(x, 0.0f, static_cast<float>(nx - 1));
    y = std::clamp(y, 0.0f, static_cast<float>(ny - 1));
    z = std::clamp(z, 0.0f, static_cast<float>(nz - 1));
    const int i = std::min(static_cast<int>(x), nx - 2);
    const int j = std::min(static_cast<int>(y), ny - 2);
    const int k = std::min(static_cast<int>(z), nz - 2);
    const float fx = x - i, fy = y - j, fz = z - k;
    const size_t sy = static_cast<size_t>(nx), sz = static_cast<size_t>(nx) * ny;
    const float* p = w.data() + index(i, j, k);
    const float c00 = p[0] + fx * (p[1] - p[0]);
    const float c10 = p[sy] + fx * (p[sy + 1] - p[sy]);
    const float c01 = p[sz] + fx * (p[sz + 1] - p[sz]);
    const float c11 = p[sz + sy] + fx * (p[sz + sy + 1] - p[sz + sy]);
    const float c0 = c00 + fy * (c10 - c00);
    const float c1 = c01 + fy * (c11 - c01);
    return c0 + fz * (c1 - c0);
  }
};

struct RGBA
{
  float r, g, b, a;
};

// Opacity correction for the step, as ParaView's opacity table (entries <= 1e-4 untouched).
float correctOpacity(float a, double exponent)
{
  return a > 0.0001f ? static_cast<float>(1.0 - std::pow(1.0 - a, exponent)) : a;
}

// Table coordinate of w: t = w * scale + bias, clamped to [0, width - 1].
struct Classify1D
{
  std::vector<RGBA> table;
  int width = 0;
  float scale = 1, bias = 0;
  std::vector<int> nonzeroPrefix; // count of entries with alpha > 0 in [0, i]

  void prepare(const TransferTable1D& t, double wMin, double wMax, double exponent)
  {
    if (t.width < 2 || t.rgba.size() != static_cast<size_t>(t.width) * 4 || !(t.max > t.min))
    {
      throw Error("transfer function table is empty, has a bad size or an empty range");
    }
    width = t.width;
    table.resize(static_cast<size_t>(width));
    nonzeroPrefix.resize(static_cast<size_t>(width));
    int count = 0;
    for (int i = 0; i < width; ++i)
    {
      const float* e = &t.rgba[4 * static_cast<size_t>(i)];
      for (int c = 0; c < 4; ++c)
      {
        if (!std::isfinite(e[c]))
        {
          throw Error("transfer function table holds a non-finite value");
        }
      }
      table[i] = { std::clamp(e[0], 0.0f, 1.0f), std::clamp(e[1], 0.0f, 1.0f),
        std::clamp(e[2], 0.0f, 1.0f), correctOpacity(std::clamp(e[3], 0.0f, 1.0f), exponent) };
      count += table[i].a > 0.0f ? 1 : 0;
      nonzeroPrefix[i] = count;
    }
    // t = ((w - min) / (max - min)) * width - 0.5
    scale = static_cast<float>(width / (t.max - t.min));
    bias = static_cast<float>(-t.min * width / (t.max - t.min) - 0.5);
    (void)wMin;
    (void)wMax;
  }

  bool anyOpaque(float lo, float hi) const
  {
    float t0 = lo * scale + bias, t1 = hi * scale + bias;
    if (t0 > t1) std::swap(t0, t1);
    const int i0 = std::clamp(static_cast<int>(std::floor(t0)) - 1, 0, width - 1);
    const int i1 = std::clamp(static_cast<int>(std::ceil(t1)) + 1, 0, width - 1);
    return nonzeroPrefix[i1] - (i0 > 0 ? nonzeroPrefix[i0 - 1] : 0) > 0;
  }

  RGBA lookup(float w) const
  {
    const float t = std::clamp(w * scale + bias, 0.0f, static_cast<float>(width - 1));
    const int i = std::min(static_cast<int>(t), width - 2);
    const float f = t - i;
    const RGBA& a = table[i];
    const RGBA& b = table[i + 1];
    return { a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b), a.a + f * (b.a - a.a) };
  }
};

} // namespace

struct RayCaster::Internals
{
  Volume Vol;
  Field F;
  double TextureScale = 1;
  std::once_flag GradientOnce;
  Field Gradient; // gradient magnitude (unscaled), for 2D tables
};

RayCaster::RayCaster(const Volume& volume)
  : In(std::make_unique<Internals>())
{
  const auto& d = volume.dims();
  if (volume.empty())
  {
    throw Error("volume is empty");
  }
  if (d[0] < 2 || d[1] < 2 || d[2] < 2)
  {
    std::ostringstream msg;
    msg << "volume must have at least 2 points along each axis to be volume rendered, it has "
        << d[0] << " x " << d[1] << " x " << d[2];
    throw Error(msg.str());
  }
  if (!(volume.range()[1] > volume.range()[0]))
  {
    std::ostringstream msg;
    msg << "volume is constant (every voxel is " << volume.range()[0]
        << "): a transfer function over an empty data range shows nothing";
    throw Error(msg.str());
  }
  In->Vol = volume;
  In->TextureScale = textureScale(volume.originalType());
  std::vector<float> w(volume.values().size());
  const float q = static_cast<float>(In->TextureScale);
  const auto& v = volume.values();
  for (size_t i = 0; i < w.size(); ++i)
  {
    w[i] = v[i] * q;
  }
  In->F.build(d[0], d[1], d[2], std::move(w));
}

RayCaster::~RayCaster() = default;

const Volume& RayCaster::volume() const
{
  return In->Vol;
}

double RayCaster::textureScale(ScalarType type)
{
  switch (type)
  {
    case ScalarType::UInt8: return 256.0 / 255.0;
    case ScalarType::UInt16: return 65536.0 / 65535.0;
    case ScalarType::Int16: return 32768.0 / 32767.0;
    default: return 1.0;
  }
}

double RayCaster::defaultSampleDistance() const
{
  const auto& s = In->Vol.spacing();
  const auto& d = In->Vol.dims();
  double dist = (s[0] + s[1] + s[2]) / 6.0;
  const double n = std::pow(static_cast<double>(d[0] - 1) * (d[1] - 1) * (d[2] - 1), 0.333);
  if (n < 100.0)
  {
    dist *= 0.01 + 0.99 * n / 100.0;
  }
  return dist;
}

double RayCaster::defaultOpacityUnitDistance() const
{
  const auto b = In->Vol.bounds();
  const auto& d = In->Vol.dims();
  const double diag = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
    (b[5] - b[4]) * (b[5] - b[4]));
  const double cells = static_cast<double>(d[0] - 1) * (d[1] - 1) * (d[2] - 1);
  return diag / std::cbrt(cells);
}

TransferTable1D RayCaster::paraviewTable(const TransferFunction1D& tf) const
{
  const auto& r = In->Vol.range();
  return bakeTable(tf, r[0], r[1], paraviewTableWidth(tf, r[0], r[1]));
}

float RayCaster::jitterValue(int x, int yFromBottom)
{
  // 64 x 64 tile of white noise from an integer hash (deterministic, no data file).
  std::uint32_t h = static_cast<std::uint32_t>(x & 63) * 73856093u ^
    static_cast<std::uint32_t>(yFromBottom & 63) * 19349663u;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return static_cast<float>(h >> 8) / 16777216.0f;
}

namespace
{

// Everything one render needs, shared read-only by the workers.
struct March
{
  const Field* field = nullptr;
  const Field* gradient = nullptr; // 2D only
  const Classify1D* c1 = nullptr;
  const TransferTable2D* t2 = nullptr;
  std::vector<char> blockEmpty;
  double d = 1, exponent = 1;
  float termination = 1.0f - 1.0f / 255.0f;
  bool jitter = false;
  double offset = 0.5;
  bool skip = true;
  Eigen::Vector3d origin, spacing, boxMin, boxMax;
  std::vector<RGBA> table2D; // corrected 2D table
  float vScale = 1, vBias = 0, gScale = 1, gBias = 0;
  int tw = 0, th = 0;

  RGBA lookup2D(float w, float g) const
  {
    const float tx = std::clamp(w * vScale + vBias, 0.0f, static_cast<float>(tw - 1));
    const float ty = std::clamp(g * gScale + gBias, 0.0f, static_cast<float>(th - 1));
    const int i = std::min(static_cast<int>(tx), tw - 2);
    const int j = std::min(static_cast<int>(ty), th - 2);
    const float fx = tx - i, fy = ty - j;
    const RGBA* r0 = &table2D[static_cast<size_t>(j) * tw + i];
    const RGBA* r1 = r0 + tw;
    auto lerp = [](const RGBA& a, const RGBA& b, float f) {
      return RGBA{ a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b), a.a + f * (b.a - a.a) };
    };
    return lerp(lerp(r0[0], r0[1], fx), lerp(r1[0], r1[1], fx), fy);
  }

  template <bool TwoD>
  void castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& dir, float j, float* out) const
  {
    // Slab intersection with the point bounds.
    double t0 = -1e300, t1 = 1e300;
    for (int a = 0; a < 3; ++a)
    {
      if (dir[a] != 0.0)
      {
        double ta = (boxMin[a] - o[a]) / dir[a], tb = (boxMax[a] - o[a]) / dir[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      else if (o[a] < boxMin[a] || o[a] > boxMax[a])
      {
        return;
      }
    }
    t0 = std::max(t0, 0.0);
    if (!(t1 >= t0))
    {
      return;
    }
    // Index-space start and step; sample k at E + (j + k) S, k = 0 .. kLast.
    Eigen::Vector3d e, s;
    for (int a = 0; a < 3; ++a)
    {
      e[a] = (o[a] + t0 * dir[a] - origin[a]) / spacing[a];
      s[a] = d * dir[a] / spacing[a];
    }
    const double span = (t1 - t0) / d - j;
    const std::int64_t kLast = span > 0 ? static_cast<std::int64_t>(std::floor(span)) : 0;
    const float ex = static_cast<float>(e[0]), ey = static_cast<float>(e[1]), ez = static_cast<float>(e[2]);
    const float sx = static_cast<float>(s[0]), sy = static_cast<float>(s[1]), sz = static_cast<float>(s[2]);
    const Field& f = *field;
    float cr = 0, cg = 0, cb = 0, ca = 0;
    int lastBlock = -1;
    for (std::int64_t k = 0; k <= kLast; ++k)
    {
      const float kk = j + static_cast<float>(k);
      const float px = ex + kk * sx, py = ey + kk * sy, pz = ez + kk * sz;
      if (skip)
      {
        const int ix = std::clamp(static_cast<int>(px) / kBlock, 0, f.bx - 1);
        const int iy = std::clamp(static_cast<int>(py) / kBlock, 0, f.by - 1);
        const int iz = std::clamp(static_cast<int>(pz) / kBlock, 0, f.bz - 1);
        const int block = (iz * f.by + iy) * f.bx + ix;
        if (block != lastBlock && blockEmpty[static_cast<size_t>(block)])
        {
          // Jump to the first sample past this block's far faces.
          double kExit = 1e300;
          const int ib[3] = { ix, iy, iz };
          for (int a = 0; a < 3; ++a)
          {
            if (s[a] > 0)
              kExit = std::min(kExit, ((ib[a] + 1) * kBlock - e[a]) / s[a] - j);
            else if (s[a] < 0)
              kExit = std::min(kExit, (ib[a] * kBlock - e[a]) / s[a] - j);
          }
          const double next = std::ceil(kExit);
          if (next > static_cast<double>(k + 1))
          {
            k = static_cast<std::int64_t>(std::min(next, static_cast<double>(kLast) + 1.0)) - 1;
          }
          continue;
        }
        lastBlock = block;
      }
      RGBA c;
      if constexpr (TwoD)
      {
        c = lookup2D(f.sample(px, py, pz), gradient->sample(px, py, pz));
      }
      else
      {
        c = c1->lookup(f.sample(px, py, pz));
      }
      if (c.a > 0.0f)
      {
        const float wgt = (1.0f - ca) * c.a;
        cr += wgt * c.r;
        cg += wgt * c.g;
        cb += wgt * c.b;
        ca += wgt;
        if (ca > termination)
        {
          break;
        }
      }
    }
    out[0] = cr;
    out[1] = cg;
    out[2] = cb;
    out[3] = ca;
  }
};

template <bool TwoD>
Image runMarch(const March& m, const View& view, int threads, const ProgressCallback& progress)
{
  const RayGenerator rays(view);
  Image img(view.width, view.height, 4, 0.0f);
  const int tilesX = (view.width + kTile - 1) / kTile;
  const int tilesY = (view.height + kTile - 1) / kTile;
  const std::int64_t tiles = static_cast<std::int64_t>(tilesX) * tilesY;
  std::atomic<std::int64_t> done{ 0 };
  std::atomic<bool> cancel{ false };
  parallelFor(tiles, threads, [&](std::int64_t tile, int threadId) {
    if (cancel.load(std::memory_order_relaxed))
    {
      return;
    }
    const int x0 = static_cast<int>(tile % tilesX) * kTile;
    const int y0 = static_cast<int>(tile / tilesX) * kTile;
    Eigen::Vector3d o, dir;
    for (int y = y0; y < std::min(y0 + kTile, view.height); ++y)
    {
      for (int x = x0; x < std::min(x0 + kTile, view.width); ++x)
      {
        rays.ray(x, y, o, dir);
        const float j = m.jitter ? RayCaster::jitterValue(x, view.height - 1 - y) : static_cast<float>(m.offset);
        m.template castRay<TwoD>(o, dir, j, &img.at(x, y, 0));
      }
    }
    const std::int64_t n = ++done;
    if (threadId == 0 && progress && !progress(static_cast<double>(n) / tiles))
    {
      cancel = true;
    }
  });
  if (cancel)
  {
    throw Cancelled();
  }
  if (progress)
  {
    progress(1.0);
  }
  return img;
}

void setupMarch(March& m, const Volume& vol, const Field& field, double defaultD,
  double defaultUnit, const View& view, const RenderOptions& opt)
{
  view.validate();
  m.field = &field;
  m.d = opt.sampleDistance > 0 ? opt.sampleDistance : defaultD;
  if (!std::isfinite(m.d) || m.d <= 0)
  {
    throw Error("sample distance must be positive");
  }
  const double unit = view.opacityUnitDistance ? *view.opacityUnitDistance : defaultUnit;
  m.exponent = m.d / unit;
  m.termination = static_cast<float>(opt.terminationOpacity);
  m.jitter = opt.jitter;
  m.offset = opt.sampleOffset;
  if (!(m.offset >= 0.0 && m.offset <= 1.0))
  {
    throw Error("sample offset must lie in [0, 1]");
  }
  m.skip = opt.emptySpaceSkipping;
  const auto b = vol.bounds();
  for (int a = 0; a < 3; ++a)
  {
    m.origin[a] = vol.origin()[a];
    m.spacing[a] = vol.spacing()[a];
    m.boxMin[a] = b[2 * a];
    m.boxMax[a] = b[2 * a + 1];
  }
}

} // namespace

Image RayCaster::render(const TransferTable1D& table, const View& view, const RenderOptions& options,
  const ProgressCallback& progress) const
{
  March m;
  setupMarch(m, In->Vol, In->F, defaultSampleDistance(), defaultOpacityUnitDistance(), view, options);
  Classify1D c;
  c.prepare(table, 0, 0, m.exponent);
  m.c1 = &c;
  const Field& f = In->F;
  m.blockEmpty.resize(f.blockMin.size());
  for (size_t i = 0; i < f.blockMin.size(); ++i)
  {
    m.blockEmpty[i] = !c.anyOpaque(f.blockMin[i], f.blockMax[i]);
  }
  return runMarch<false>(m, view, options.threads, progress);
}

Image RayCaster::render(const TransferTable2D& table, const View& view, const RenderOptions& options,
  const ProgressCallback& progress) const
{
  table.validate();
  std::call_once(In->GradientOnce, [this] {
    const auto& d = In->Vol.dims();
    In->Gradient.build(d[0], d[1], d[2], In->Vol.gradientMagnitude());
  });
  March m;
  setupMarch(m, In->Vol, In->F, defaultSampleDistance(), defaultOpacityUnitDistance(), view, options);
  m.gradient = &In->Gradient;
  m.t2 = &table;
  m.tw = table.width;
  m.th = table.height;
  m.table2D.resize(static_cast<size_t>(m.tw) * m.th);
  std::vector<char> opaque(m.table2D.size());
  for (size_t i = 0; i < m.table2D.size(); ++i)
  {
    const float* e = &table.rgba[4 * i];
    m.table2D[i] = { e[0], e[1], e[2], correctOpacity(e[3], m.exponent) };
    opaque[i] = m.table2D[i].a > 0.0f;
  }
  // The value axis uses the same scaled field w as the 1D path.
  const double q = In->TextureScale;
  m.vScale = static_cast<float>(m.tw / (q * (table.valueRange[1] - table.valueRange[0])));
  m.vBias = static_cast<float>(-table.valueRange[0] * m.tw / (table.valueRange[1] - table.valueRange[0]) - 0.5);
  m.gScale = static_cast<float>(m.th / (table.gradientRange[1] - table.gradientRange[0]));
  m.gBias = static_cast<float>(-table.gradientRange[0] * m.th / (table.gradientRange[1] - table.gradientRange[0]) - 0.5);
  const Field& f = In->F;
  const Field& g = In->Gradient;
  m.blockEmpty.resize(f.blockMin.size());
  for (size_t b = 0; b < f.blockMin.size(); ++b)
  {
    auto range = [](float lo, float hi, float scale, float bias, int n, int& i0, int& i1) {
      float t0 = lo * scale + bias, t1 = hi * scale + bias;
      if (t0 > t1) std::swap(t0, t1);
      i0 = std::clamp(static_cast<int>(std::floor(t0)) - 1, 0, n - 1);
      i1 = std::clamp(static_cast<int>(std::ceil(t1)) + 1, 0, n - 1);
    };
    int v0, v1, g0, g1;
    range(f.blockMin[b], f.blockMax[b], m.vScale, m.vBias, m.tw, v0, v1);
    range(g.blockMin[b], g.blockMax[b], m.gScale, m.gBias, m.th, g0, g1);
    bool any = false;
    for (int jj = g0; jj <= g1 && !any; ++jj)
      for (int ii = v0; ii <= v1 && !any; ++ii)
        any = opaque[static_cast<size_t>(jj) * m.tw + ii];
    m.blockEmpty[b] = !any;
  }
  return runMarch<true>(m, view, options.threads, progress);
}

} // namespace ddg
