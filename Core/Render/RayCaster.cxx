// RayCaster.cxx: prepared volume, per-render tables, block skipping and the ray march.
#include "Render/RayCaster.h"

#include "Common/Parallel.h"
#include "Render/Lighting.h"
#include "Render/RayCasterClassify.h"
#include "Render/RayCasterField.h"
#include "Render/RayCasterSample.h"
#include "Render/RaySegment.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <type_traits>

namespace ddg
{
using namespace raycast;
namespace
{

constexpr int kSuper = 4; // blocks per superblock side (coarse skipping level)
constexpr int kTile = 16; // pixels per tile side (unit of parallel work)

// Storage type of the prepared scalars: the smallest that holds the original type exactly.
enum class Storage
{
  U8,
  I8,
  U16,
  I16,
  F32
};

Storage storageFor(ScalarType t)
{
  switch (t)
  {
    case ScalarType::UInt8:
      return Storage::U8;
    case ScalarType::Int8:
      return Storage::I8;
    case ScalarType::UInt16:
      return Storage::U16;
    case ScalarType::Int16:
      return Storage::I16;
    default:
      return Storage::F32;
  }
}

} // namespace

namespace raycast
{
#if defined(__GNUC__) && defined(__x86_64__)
// The same code compiled for AVX2 (flatten: shadeBatch and the light sums inlined here): the
// queue's 8 lanes in one register instead of two. GCC's and Clang's "avx2" target does not
// enable FMA, so no multiply and add are fused: every operation rounds as in the baseline.
__attribute__((target("avx2"), flatten)) static void shadeQueueWide(const SampleLighting& light,
  int count, const float (&g)[3][kBatch], const float e[3], const float s[3],
  const float (&k)[kBatch], bool clamp, float (&rgb)[3][kBatch])
{
  light.shadeBatch(count, g, e, s, k, clamp, rgb);
}
#endif

bool shadeQueueAvx2(const SampleLighting& light, int count, const float (&g)[3][kBatch],
  const float e[3], const float s[3], const float (&k)[kBatch], bool clamp, float (&rgb)[3][kBatch])
{
#if defined(__GNUC__) && defined(__x86_64__)
  static const bool avx2 = __builtin_cpu_supports("avx2");
  if (avx2)
  {
    shadeQueueWide(light, count, g, e, s, k, clamp, rgb);
    return true;
  }
#endif
  (void)light, (void)count, (void)g, (void)e, (void)s, (void)k, (void)clamp, (void)rgb;
  return false;
}

void shadeQueue(const SampleLighting& light, int count, const float (&g)[3][kBatch],
  const float e[3], const float s[3], const float (&k)[kBatch], bool clamp, float (&rgb)[3][kBatch])
{
  if (!shadeQueueAvx2(light, count, g, e, s, k, clamp, rgb))
    light.shadeBatch(count, g, e, s, k, clamp, rgb);
}
} // namespace raycast

struct RayCaster::Internals
{
  Volume Vol;
  std::optional<VolumeBrick> Brick; // a piece of a whole volume
  // The whole volume's geometry and range (the volume's own unless a piece)
  std::array<int, 3> WholeDims{};
  std::array<double, 3> WholeOrigin{};
  std::array<double, 2> WholeRange{};
  double TextureScale = 1;
  Storage Kind = Storage::F32;
  Field<std::uint8_t> U8;
  Field<std::int8_t> I8;
  Field<std::uint16_t> U16;
  Field<std::int16_t> I16;
  Field<float> F32;
  GradientStencil Stencil; // Shade and 2D tables: the gradient at a sample, from the scalars
  std::once_flag GradientOnce;
  std::vector<float> GradientBlockMax; // 2D tables: block maxima of the per-point transferGradient

  // The field of scalars of type T.
  template <typename T>
  Field<T>& fieldFor()
  {
    if constexpr (std::is_same_v<T, std::uint8_t>)
      return U8;
    else if constexpr (std::is_same_v<T, std::int8_t>)
      return I8;
    else if constexpr (std::is_same_v<T, std::uint16_t>)
      return U16;
    else if constexpr (std::is_same_v<T, std::int16_t>)
      return I16;
    else
      return F32;
  }

  // Calls f(field) with the field of the volume's storage type.
  template <typename F>
  decltype(auto) withField(F&& f) const
  {
    return dispatch(*this, std::forward<F>(f));
  }
  template <typename F>
  decltype(auto) withField(F&& f)
  {
    return dispatch(*this, std::forward<F>(f));
  }

  // Calls f with the field of the volume's storage type (const or not, as self).
  template <typename Self, typename F>
  static decltype(auto) dispatch(Self& self, F&& f)
  {
    switch (self.Kind)
    {
      case Storage::U8:
        return f(self.U8);
      case Storage::I8:
        return f(self.I8);
      case Storage::U16:
        return f(self.U16);
      case Storage::I16:
        return f(self.I16);
      default:
        return f(self.F32);
    }
  }
};

namespace
{
void checkRenderable(const Volume& volume, const std::array<double, 2>& range, const char* what)
{
  const auto& d = volume.dims();
  if (volume.empty())
  {
    throw Error(std::string(what) + " is empty");
  }
  if (d[0] < 2 || d[1] < 2 || d[2] < 2)
  {
    std::ostringstream msg;
    msg << what << " must have at least 2 points along each axis to be volume rendered, it has "
        << d[0] << " x " << d[1] << " x " << d[2];
    throw Error(msg.str());
  }
  if (!(range[1] > range[0]))
  {
    std::ostringstream msg;
    msg << "volume is constant (every voxel is " << range[0]
        << "): a transfer function over an empty data range shows nothing";
    throw Error(msg.str());
  }
}
} // namespace

RayCaster::RayCaster(const Volume& piece, const VolumeBrick& brick)
  : RayCaster(piece, &brick)
{
}

RayCaster::RayCaster(const Volume& volume)
  : RayCaster(volume, nullptr)
{
}

RayCaster::RayCaster(const Volume& volume, const VolumeBrick* brick)
  : In(std::make_unique<Internals>())
{
  const auto& d = volume.dims();
  if (brick)
  {
    brick->validate(volume, false);
    if (brick->ownsNothing())
      throw Error("this volume piece owns no cell: it has nothing to render");
  }
  checkRenderable(
    volume, brick ? brick->wholeRange : volume.range(), brick ? "volume piece" : "volume");
  In->Vol = volume;
  if (brick)
  {
    In->Brick = *brick;
    In->WholeDims = brick->wholeDims;
    In->WholeOrigin = brick->wholeOrigin;
    In->WholeRange = brick->wholeRange;
  }
  else
  {
    In->WholeDims = volume.dims();
    In->WholeOrigin = volume.origin();
    In->WholeRange = volume.range();
  }
  In->TextureScale = textureScale(volume.originalType());
  In->Kind = storageFor(volume.storageType());
  In->Stencil = GradientStencil::of(volume, In->WholeDims);
  volume.visit(
    [&](const auto* scalars)
    {
      using T = std::remove_const_t<std::remove_pointer_t<decltype(scalars)>>;
      In->fieldFor<T>().build(d[0], d[1], d[2], scalars);
    });
}

RayCaster::~RayCaster() = default;

const Volume& RayCaster::volume() const
{
  return In->Vol;
}

std::array<double, 6> RayCaster::wholeBounds() const
{
  return In->Brick ? In->Brick->wholeBounds(In->Vol.spacing()) : In->Vol.bounds();
}

const VolumeBrick* RayCaster::brick() const
{
  return In->Brick ? &*In->Brick : nullptr;
}

const std::array<double, 2>& RayCaster::dataRange() const
{
  return In->WholeRange;
}

double RayCaster::textureScale(ScalarType type)
{
  switch (type)
  {
    case ScalarType::UInt8:
      return 256.0 / 255.0;
    case ScalarType::UInt16:
      return 65536.0 / 65535.0;
    case ScalarType::Int16:
      return 32768.0 / 32767.0;
    default:
      return 1.0;
  }
}

double RayCaster::defaultSampleDistance() const
{
  return ddg::defaultSampleDistance(In->Vol.spacing(), In->WholeDims);
}

double RayCaster::defaultOpacityUnitDistance() const
{
  const auto b = wholeBounds();
  const auto& d = In->WholeDims;
  const double diag = std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
  const double cells = static_cast<double>(d[0] - 1) * (d[1] - 1) * (d[2] - 1);
  return diag / std::cbrt(cells);
}

double RayCaster::opacityUnitDistance(const View& view) const
{
  return view.opacityUnitDistance ? *view.opacityUnitDistance : defaultOpacityUnitDistance();
}

ParaViewTransfer2DMapping RayCaster::paraviewMapping2D(const View& view) const
{
  return ParaViewTransfer2DMapping::forVolume(In->WholeDims, In->Vol.spacing(), In->WholeRange,
    defaultSampleDistance(), opacityUnitDistance(view));
}

TransferTable1D RayCaster::paraviewTable(const TransferFunction1D& tf) const
{
  const auto& r = In->WholeRange;
  return bakeTable(tf, r[0], r[1], paraviewTableWidth(tf, r[0], r[1]));
}

TransferTable2D RayCaster::paraviewTable2D(
  const ParaViewTransferFunction2D& tf, const View& view) const
{
  return tf.table(paraviewMapping2D(view));
}

TransferFunctionFile RayCaster::resolve(const TransferFunctionFile& tf, const View& view) const
{
  if (!tf.isParaView2D)
    return tf;
  TransferFunctionFile out;
  out.is2D = true;
  out.tf2D.name = "ParaView 2D transfer function";
  out.tf2D.table = paraviewTable2D(tf.paraview2D, view);
  return out;
}

Image RayCaster::render(const TransferFunctionFile& tf, const View& view,
  const RenderOptions& options, const ProgressCallback& progress, RenderStats* stats) const
{
  const TransferFunctionFile ready = resolve(tf, view);
  return ready.is2D ? render(ready.tf2D.bake(), view, options, progress, stats)
                    : render(paraviewTable(ready.tf1D), view, options, progress, stats);
}

namespace
{

// One render: geometry, step, classification and block emptiness, shared read-only by workers.
template <typename FieldT>
struct March
{
  const FieldT* field = nullptr;
  const GradientStencil* stencil = nullptr; // the gradient at a sample: 2D, Shade
  const Classify1D* c1 = nullptr;
  const Classify2D* c2 = nullptr;
  const SampleLighting* light = nullptr; // Shade on
  std::vector<char> blockEmpty;
  std::vector<char> superEmpty; // kSuper^3 blocks, empty when all of them are
  int superX = 1, superY = 1, superZ = 1;
  double d = 1;
  float termination = 1.0f - 1.0f / 255.0f;
  bool jitter = false;
  double offset = 0.5;
  bool skip = true;
  bool unlitToo = false;                           // Shade: channels 4..7 the same samples unlit
  Eigen::Vector3d origin, spacing, boxMin, boxMax; // the whole volume's
  // A piece of a volume: its owned cells [lo, hi) of the whole's n points, and its first point's
  // whole index (off); rays and ownership in the whole's index space, the march in the piece's.
  bool piece = false;
  int lo[3] = { 0, 0, 0 }, hi[3] = { 0, 0, 0 }, n[3] = { 0, 0, 0 };
  double off[3] = { 0, 0, 0 };

  // The gradient's cells of one worker: a direct-mapped table of the last cells seen, shared
  // by the rays it marches (neighbouring rays cross the same cells).
  static constexpr int kCellBits = 10; // 1024 cells, 106 KB per worker
  static GradientStencil::Cell<float>& cellOf(
    std::vector<GradientStencil::Cell<float>>& cells, std::int64_t id)
  {
    const std::uint64_t h = static_cast<std::uint64_t>(id) * 0x9E3779B97F4A7C15ull;
    return cells[static_cast<size_t>(h >> (64 - kCellBits))];
  }

  template <bool TwoD>
  void castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& dir, float j, float* out,
    RenderStats& stats, std::vector<GradientStencil::Cell<float>>& cells) const
  {
    RaySegment seg;
    if (!raySegment(o, dir, boxMin, boxMax, origin, spacing, d, j, seg))
    {
      return;
    }
    if (piece)
    {
      if (!ownedSamples(seg, j, lo, hi, n))
        return;
      out[4] = static_cast<float>(seg.kFirst); // the sort-last order of the pieces on this ray
      for (int a = 0; a < 3; ++a)
        seg.e[a] -= off[a];
    }
    const double* e = seg.e;
    const double* s = seg.s;
    const std::int64_t kLast = seg.kLast;
    double invS[3];
    for (int a = 0; a < 3; ++a)
    {
      invS[a] = s[a] != 0.0 ? 1.0 / s[a] : 0.0;
    }
    ++stats.rays;
    const float ex = static_cast<float>(e[0]), ey = static_cast<float>(e[1]),
                ez = static_cast<float>(e[2]);
    const float sx = static_cast<float>(s[0]), sy = static_cast<float>(s[1]),
                sz = static_cast<float>(s[2]);
    const FieldT& f = *field;
    float cr = 0, cg = 0, cb = 0, ca = 0;
    float unlit[4] = { 0, 0, 0, 0 };
    float* const unlitSums = light && unlitToo ? unlit : nullptr;
    const float e3[3] = { ex, ey, ez }, s3[3] = { sx, sy, sz };
    LitQueue queue; // Shade: samples with opacity waiting to be lit and composited
    // March block by block: find the block of sample k and the first sample past its far faces;
    // skip the block when the TF makes it transparent, else sample it without further checks.
    // Classifies the block (or empty superblock) holding sample k; sets kEnd to the first
    // sample past its far faces. Samples within 1e-3 steps of a face are left to the next
    // block, so float positions never put a skipped sample outside its (empty) block.
    auto visitBlock = [&](std::int64_t k0, std::int64_t& kEnd)
    {
      const float kk = j + static_cast<float>(k0);
      const float p[3] = { ex + kk * sx, ey + kk * sy, ez + kk * sz };
      bool empty = false;
      for (int level = 0; level < 2; ++level)
      {
        const int cells = level == 0 ? kBlock * kSuper : kBlock;
        const int n[3] = { level == 0 ? superX : f.bx, level == 0 ? superY : f.by,
          level == 0 ? superZ : f.bz };
        int ib[3];
        for (int a = 0; a < 3; ++a)
        {
          ib[a] = std::clamp(static_cast<int>(p[a]) / cells, 0, n[a] - 1);
        }
        const size_t id = (static_cast<size_t>(ib[2]) * n[1] + ib[1]) * n[0] + ib[0];
        empty = level == 0 ? superEmpty[id] != 0 : blockEmpty[id] != 0;
        if (level == 0 && !empty)
        {
          continue; // look at the block inside the superblock
        }
        double kExit = static_cast<double>(kLast) + 1.0;
        for (int a = 0; a < 3; ++a)
        {
          if (s[a] != 0.0)
          {
            const double face = (s[a] > 0 ? ib[a] + 1 : ib[a]) * static_cast<double>(cells);
            kExit = std::min(kExit, (face - e[a]) * invS[a] - j);
          }
        }
        kEnd = std::clamp(
          static_cast<std::int64_t>(std::ceil(kExit - (empty ? 1e-3 : 0.0))), k0 + 1, kLast + 1);
        break;
      }
      return empty;
    };
    std::int64_t nextK = -1, nextEnd = 0; // a block classified ahead of time
    bool nextEmpty = false;
    std::int64_t k = seg.kFirst;
    while (k <= kLast)
    {
      std::int64_t kEnd = kLast + 1;
      bool empty = false;
      if (skip)
      {
        empty = (k == nextK) ? nextEmpty : visitBlock(k, kEnd);
        if (k == nextK)
        {
          kEnd = nextEnd;
        }
        // Extend a non-empty run over the following non-empty blocks, so that batches of
        // samples run across block faces; remember the first empty block found.
        while (!empty && kEnd <= kLast)
        {
          std::int64_t e2;
          const bool empty2 = visitBlock(kEnd, e2);
          if (empty2)
          {
            nextK = kEnd;
            nextEnd = e2;
            nextEmpty = true;
            break;
          }
          kEnd = e2;
        }
      }
      if (empty)
      {
        stats.skippedSamples += kEnd - k;
        k = kEnd;
        continue;
      }
      stats.samples += kEnd - k;
      // Interpolate a batch of kBatch samples (independent: vectorisable), then classify,
      // light and composite them in order. Lanes past kEnd are computed (clamped, in bounds)
      // but not used.
      bool done = false;
      for (; k < kEnd && !done; k += kBatch)
      {
        float value[kBatch];
        Lanes lanes;
        sampleBatch(f, j + static_cast<float>(k), ex, ey, ez, sx, sy, sz, value, lanes);
        const int n = static_cast<int>(std::min<std::int64_t>(kBatch, kEnd - k));
        // Classify the lanes. The interpolated gradient: 2D tables classify with it; Shade
        // lights with it, and in 1D only samples with opacity need it.
        RGBA c[kBatch];
        float g[3][kBatch];
        if constexpr (TwoD)
        {
          // the lanes' gradients one by one (through the cell table), then their magnitudes and
          // table coordinates together
          for (int l = 0; l < n; ++l)
          {
            float gl[3];
            stencil->inCell(f.w, lanes.i[l], lanes.j[l], lanes.k[l], lanes.idx[l], lanes.fx[l],
              lanes.fy[l], lanes.fz[l], cellOf(cells, lanes.idx[l]), gl);
            for (int a = 0; a < 3; ++a)
              g[a][l] = gl[a];
          }
          for (int l = n; l < kBatch; ++l)
            for (int a = 0; a < 3; ++a)
              g[a][l] = 0.0f;
          float gm[kBatch];
          transferGradientBatch(g, gm);
          c2->lookupBatch(n, value, gm, c);
        }
        else
        {
          for (int l = 0; l < n; ++l)
            c[l] = c1->lookup(value[l]);
        }
        if (light)
        {
          // Shade: the samples with opacity queue up across batches and are lit kBatch at a time
          // (full batches light faster than the few lanes of one batch that have opacity), then
          // composited in order; none past the ray's end is lit.
          for (int l = 0; l < n && !done; ++l)
          {
            if (c[l].a <= 0.0f)
              continue;
            float gl[3];
            if constexpr (TwoD)
              for (int a = 0; a < 3; ++a)
                gl[a] = g[a][l];
            else
              stencil->inCell(f.w, lanes.i[l], lanes.j[l], lanes.k[l], lanes.idx[l], lanes.fx[l],
                lanes.fy[l], lanes.fz[l], cellOf(cells, lanes.idx[l]), gl);
            if (queue.push(gl, j + static_cast<float>(k + l), c[l], termination))
            {
              stats.samples -= kEnd - (k + l) - 1;
              done = true;
            }
            if (queue.count == kBatch || done)
              queue.flush(*light, e3, s3, !TwoD, cr, cg, cb, ca, unlitSums);
          }
          continue;
        }
        for (int l = 0; l < n; ++l)
        {
          if (c[l].a <= 0.0f)
            continue;
          if (composite(c[l], cr, cg, cb, ca, termination))
          {
            stats.samples -= kEnd - (k + l) - 1;
            done = true;
            break;
          }
        }
      }
      if (done)
      {
        break;
      }
      k = kEnd;
    }
    if (light)
      queue.flush(*light, e3, s3, !TwoD, cr, cg, cb, ca, unlitSums);
    out[0] = cr;
    out[1] = cg;
    out[2] = cb;
    out[3] = ca;
    if (unlitSums)
      for (int c = 0; c < 4; ++c)
        out[4 + c] = unlit[c];
  }

  // `origin`, `spacing`, `bounds`: the whole volume's; `brick`: the piece the field holds, if any.
  void setup(const std::array<double, 3>& originIn, const std::array<double, 3>& spacingIn,
    const std::array<double, 6>& b, const VolumeBrick* brick, const FieldT& fieldIn,
    double defaultD, const RenderOptions& opt)
  {
    field = &fieldIn;
    d = opt.sampleDistance > 0 ? opt.sampleDistance : defaultD;
    if (!std::isfinite(d) || d <= 0)
    {
      throw Error("sample distance must be positive");
    }
    termination = static_cast<float>(opt.terminationOpacity);
    jitter = opt.jitter;
    offset = opt.sampleOffset;
    if (!(offset >= 0.0 && offset <= 1.0))
    {
      throw Error("sample offset must lie in [0, 1]");
    }
    skip = opt.emptySpaceSkipping;
    unlitToo = opt.unlitToo;
    for (int a = 0; a < 3; ++a)
    {
      origin[a] = originIn[a];
      spacing[a] = spacingIn[a];
      boxMin[a] = b[2 * a];
      boxMax[a] = b[2 * a + 1];
    }
    piece = brick != nullptr;
    if (piece && unlitToo)
      throw Error("a piece of a volume is rendered in one lighting at a time");
    if (piece)
      for (int a = 0; a < 3; ++a)
      {
        lo[a] = brick->ownedMin[a];
        hi[a] = brick->ownedMax[a];
        n[a] = brick->wholeDims[a];
        off[a] = brick->offset[a];
      }
  }

  // Superblock emptiness from blockEmpty (call after filling blockEmpty).
  void buildSuperLevel()
  {
    const FieldT& f = *field;
    superX = (f.bx + kSuper - 1) / kSuper;
    superY = (f.by + kSuper - 1) / kSuper;
    superZ = (f.bz + kSuper - 1) / kSuper;
    superEmpty.assign(static_cast<size_t>(superX) * superY * superZ, 1);
    for (int c = 0; c < f.bz; ++c)
      for (int b = 0; b < f.by; ++b)
        for (int a = 0; a < f.bx; ++a)
          if (!blockEmpty[(static_cast<size_t>(c) * f.by + b) * f.bx + a])
            superEmpty[(static_cast<size_t>(c / kSuper) * superY + b / kSuper) * superX +
              a / kSuper] = 0;
  }

  template <bool TwoD>
  Image run(
    const View& view, int threads, const ProgressCallback& progress, RenderStats* stats) const
  {
    const RayGenerator rays(view);
    Image img(view.width, view.height, piece ? 5 : (light && unlitToo ? 8 : 4), 0.0f);
    if (piece) // no sample of this piece on the ray until castRay says where its first one is
      for (size_t p = 4; p < img.pixels.size(); p += 5)
        img.pixels[p] = std::numeric_limits<float>::infinity();
    const int tilesX = (view.width + kTile - 1) / kTile;
    const int tilesY = (view.height + kTile - 1) / kTile;
    const std::int64_t tiles = static_cast<std::int64_t>(tilesX) * tilesY;
    std::atomic<std::int64_t> done{ 0 };
    std::atomic<bool> cancel{ false };
    std::atomic<std::int64_t> rayCount{ 0 }, sampleCount{ 0 }, skipCount{ 0 };
    std::vector<std::vector<GradientStencil::Cell<float>>> cells(
      static_cast<size_t>(resolveThreadCount(threads, tiles)));
    if (stencil)
      for (auto& c : cells)
        c.resize(size_t(1) << kCellBits);
    parallelFor(tiles, threads,
      [&](std::int64_t tile, int threadId)
      {
        if (cancel.load(std::memory_order_relaxed))
        {
          return;
        }
        const int x0 = static_cast<int>(tile % tilesX) * kTile;
        const int y0 = static_cast<int>(tile / tilesX) * kTile;
        Eigen::Vector3d o, dir;
        RenderStats tileStats;
        for (int y = y0; y < std::min(y0 + kTile, view.height); ++y)
        {
          for (int x = x0; x < std::min(x0 + kTile, view.width); ++x)
          {
            rays.ray(x, y, o, dir);
            const float j =
              jitter ? RayCaster::jitterValue(x, view.height - 1 - y) : static_cast<float>(offset);
            castRay<TwoD>(
              o, dir, j, &img.at(x, y, 0), tileStats, cells[static_cast<size_t>(threadId)]);
          }
        }
        rayCount += tileStats.rays;
        sampleCount += tileStats.samples;
        skipCount += tileStats.skippedSamples;
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
    if (stats)
    {
      stats->rays = rayCount;
      stats->samples = sampleCount;
      stats->skippedSamples = skipCount;
    }
    return img;
  }
};

} // namespace

void RayCaster::checkGradientPoints() const
{
  if (In->Brick)
    In->Brick->validate(In->Vol, true);
}

LightingFrame RayCaster::lightingFrame(const View& view) const
{
  return LightingFrame::of(In->WholeDims, In->WholeOrigin, In->Vol.spacing(), view);
}

Image RayCaster::render(const TransferTable1D& table, const View& view,
  const RenderOptions& options, const ProgressCallback& progress, RenderStats* stats) const
{
  view.validate();
  return In->withField(
    [&](const auto& field)
    {
      March<std::decay_t<decltype(field)>> m;
      m.setup(In->WholeOrigin, In->Vol.spacing(), wholeBounds(), brick(), field,
        defaultSampleDistance(), options);
      const double unit = opacityUnitDistance(view);
      Classify1D c;
      c.prepare(table, In->TextureScale, m.d / unit);
      m.c1 = &c;
      m.blockEmpty.resize(field.blockMin.size());
      for (size_t i = 0; i < field.blockMin.size(); ++i)
      {
        m.blockEmpty[i] = !c.anyOpaque(field.blockMin[i], field.blockMax[i]);
      }
      m.buildSuperLevel();
      SampleLighting lighting;
      if (view.lighting.shade)
      {
        checkGradientPoints();
        lighting.setup(lightingFrame(view), view, m.off);
        m.light = &lighting;
        m.stencil = &In->Stencil;
      }
      return m.template run<false>(view, options.threads, progress, stats);
    });
}

Image RayCaster::render(const TransferTable2D& table, const View& view,
  const RenderOptions& options, const ProgressCallback& progress, RenderStats* stats) const
{
  view.validate();
  table.validate();
  checkGradientPoints();
  std::call_once(In->GradientOnce,
    [&]
    {
      // Block maxima of the per-point transferGradient bound it at every sample (the norm of
      // a trilinear blend is at most the largest norm blended); the bound below is 0.
      In->withField(
        [&](const auto& field)
        {
          std::vector<float> lo;
          int bx, by, bz;
          blockRanges(
            field.nx, field.ny, field.nz,
            [&](size_t, int i, int j, int k)
            {
              float g[3];
              In->Stencil.atPoint(field.w, i, j, k, g);
              return transferGradient(g);
            },
            lo, In->GradientBlockMax, bx, by, bz);
        });
    });
  return In->withField(
    [&](const auto& field)
    {
      March<std::decay_t<decltype(field)>> m;
      m.setup(In->WholeOrigin, In->Vol.spacing(), wholeBounds(), brick(), field,
        defaultSampleDistance(), options);
      const double unit = opacityUnitDistance(view);
      Classify2D c;
      c.prepare(table, In->TextureScale, m.d / unit);
      m.c2 = &c;
      m.stencil = &In->Stencil;
      const std::vector<float>& gradientMax = In->GradientBlockMax;
      m.blockEmpty.resize(field.blockMin.size());
      for (size_t b = 0; b < field.blockMin.size(); ++b)
      {
        m.blockEmpty[b] = !c.anyOpaque(field.blockMin[b], field.blockMax[b], 0.0f, gradientMax[b]);
      }
      m.buildSuperLevel();
      SampleLighting lighting;
      if (view.lighting.shade)
      {
        lighting.setup(lightingFrame(view), view, m.off);
        m.light = &lighting;
      }
      return m.template run<true>(view, options.threads, progress, stats);
    });
}

} // namespace ddg
