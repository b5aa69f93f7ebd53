// DifferentiableRenderer.cxx: forward pass with ray records, and the replaying adjoint.
#include "Render/DifferentiableRenderer.h"

#include "Common/Parallel.h"
#include "Render/Adjoint.h"
#include "Render/DifferentiableTable.h"
#include "Render/Lighting.h"
#include "Render/PieceExchange.h"
#include "Render/RaySegment.h"
#include "Render/SortLast.h"
#include "Volume/VolumeBrick.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <optional>
#include <type_traits>

namespace ddg
{
using namespace differentiable; // FieldSampler, PreparedTable, Classifier

template <typename S>
struct DifferentiableRendererT<S>::Internals
{
  std::optional<RayCaster> Caster; // none for a piece that owns no cell
  GradientStencil Stencil;         // Shade and 2D: the gradient at a sample, from the scalars
  double TextureScale = 1;
  std::optional<VolumeBrick> Brick;              // a piece of a whole volume
  std::shared_ptr<const PieceExchange> Exchange; // pieces: how they exchange their parts

  explicit Internals(const Volume& v)
    : Stencil(GradientStencil::of(v))
    , TextureScale(RayCaster::textureScale(v.originalType()))
  {
    Caster.emplace(v);
  }

  Internals(const Volume& piece, const VolumeBrick& brick, std::shared_ptr<const PieceExchange> x)
    : TextureScale(RayCaster::textureScale(piece.originalType()))
    , Brick(brick)
    , Exchange(std::move(x))
  {
    if (!Exchange)
      throw Error("a volume piece renders with the other pieces: it needs their exchange");
    if (!brick.ownsNothing())
    {
      Caster.emplace(piece, brick);
      Stencil = GradientStencil::of(piece, brick.wholeDims);
    }
  }

  // Calls f(sampler) with a FieldSampler over the volume's scalars in their own type (shared
  // with the Volume and the RayCaster: no copy).
  template <typename F>
  void withValues(F&& f) const
  {
    const auto& d = Caster->volume().dims();
    Caster->volume().visit(
      [&](const auto* data)
      {
        using T = std::remove_const_t<std::remove_pointer_t<decltype(data)>>;
        f(FieldSampler<S, T>{ data, d[0], d[1], d[2] });
      });
  }

  // The 2D transfer function's gradient axis of kBatch samples e + (k0 + l) st (index
  // coordinates): transferGradient of the gradient there (GradientStencil over the scalars v;
  // `cell` keeps the ray's last cell).
  template <typename T>
  void sampleTransferGradients(
    const T* v, const S e[3], const S st[3], S k0, GradientStencil::Cell<S>& cell, S* out) const
  {
    for (int l = 0; l < FieldSampler<S>::kBatch; ++l)
    {
      const S kk = k0 + static_cast<S>(l);
      const S x[3] = { e[0] + kk * st[0], e[1] + kk * st[1], e[2] + kk * st[2] };
      S grad[3];
      Stencil.at(v, x, cell, grad);
      out[l] = transferGradient(grad);
    }
  }

  // Geometry shared by every ray of a view.
  struct Setup
  {
    bool lit = false;     // Shade on
    bool clampLit = true; // 1D: ParaView clamps the lit colour; 2D: it does not
    LightKit kit;
    LightingFrame frame;
    Eigen::Vector3d boxMin, boxMax, origin, spacing;
    double d = 1, unit = 1, offset = 0.5;
    S termination = S(1) - S(1) / S(255);
    bool jitter = false;
    bool piece = false; // owned samples only: cells lo .. hi of a whole of n points, at `off`
    int lo[3] = { 0, 0, 0 }, hi[3] = { 0, 0, 0 }, n[3] = { 0, 0, 0 };
    double off[3] = { 0, 0, 0 };
  };

  Setup setup(const View& view, const RenderOptions& opt, bool twoD) const
  {
    view.validate();
    Setup s;
    const Volume& vol = Caster->volume();
    const auto b = Brick ? Brick->wholeBounds(vol.spacing()) : vol.bounds();
    for (int a = 0; a < 3; ++a)
    {
      s.boxMin[a] = b[2 * a];
      s.boxMax[a] = b[2 * a + 1];
      s.origin[a] = b[2 * a];
      s.spacing[a] = vol.spacing()[a];
    }
    if (Brick)
    {
      s.piece = true;
      for (int a = 0; a < 3; ++a)
      {
        s.lo[a] = Brick->ownedMin[a];
        s.hi[a] = Brick->ownedMax[a];
        s.n[a] = Brick->wholeDims[a];
        s.off[a] = Brick->offset[a];
      }
      if (twoD || view.lighting.shade)
        Brick->validate(vol, true); // the ghost points the gradient needs
    }
    s.d = opt.sampleDistance > 0 ? opt.sampleDistance : Caster->defaultSampleDistance();
    s.unit = Caster->opacityUnitDistance(view);
    s.offset = opt.sampleOffset;
    s.jitter = opt.jitter;
    s.termination = static_cast<S>(opt.terminationOpacity);
    if (view.lighting.shade)
    {
      s.lit = true;
      s.kit = LightKit::paraview(view.lighting);
      if (Brick)
      {
        // the whole's frame, for index coordinates `off` points into the whole
        s.frame = LightingFrame::of(Brick->wholeDims, Brick->wholeOrigin, vol.spacing(), view);
        for (int r = 0; r < 3; ++r)
          for (int a = 0; a < 3; ++a)
            s.frame.positionOffset[r] += s.frame.positionMap[r][a] * s.off[a];
      }
      else
        s.frame = LightingFrame::of(vol, view);
    }
    s.clampLit = !twoD;
    if (!(s.offset >= 0 && s.offset <= 1) || !(s.d > 0) || !std::isfinite(s.d))
    {
      throw Error("sample distance must be positive and the sample offset in [0, 1]");
    }
    return s;
  }

  // Runs body(listIndex, origin, direction, jitter, worker) over the listed pixels, in chunks of
  // 64. With `dealt`, worker w of `threads` (resolved) takes chunks w, w + threads, ... in
  // order, whichever thread runs it: what a worker sums is the same from run to run (the
  // backward pass's per-worker gradients), where taking the next free chunk is not.
  template <typename Body>
  void forPixels(const View& view, const Setup& s, const std::vector<int>& pixels, int threads,
    Body&& body, bool dealt = false) const
  {
    const RayGenerator rays(view);
    const std::int64_t n = pixels.empty() ? static_cast<std::int64_t>(view.width) * view.height
                                          : static_cast<std::int64_t>(pixels.size());
    constexpr std::int64_t chunk = 64;
    const std::int64_t chunks = (n + chunk - 1) / chunk;
    auto run = [&](std::int64_t c, int worker)
    {
      Eigen::Vector3d o, dir;
      for (std::int64_t q = c * chunk; q < std::min(n, (c + 1) * chunk); ++q)
      {
        const int pixel = pixels.empty() ? static_cast<int>(q) : pixels[static_cast<size_t>(q)];
        if (pixel < 0 || pixel >= view.width * view.height)
        {
          throw Error("pixel index out of range");
        }
        const int x = pixel % view.width, y = pixel / view.width;
        rays.ray(x, y, o, dir);
        const double j = s.jitter ? RayCaster::jitterValue(x, view.height - 1 - y) : s.offset;
        body(q, o, dir, j, worker);
      }
    };
    if (!dealt)
    {
      parallelFor(chunks, threads, run);
      return;
    }
    const int workers = resolveThreadCount(threads, chunks);
    parallelFor(workers, workers,
      [&](std::int64_t w, int)
      {
        for (std::int64_t c = w; c < chunks; c += workers)
          run(c, static_cast<int>(w));
      });
  }

  // The lit colour of sample i of a sampleLightSums (Render/Lighting.h) from its light sums and
  // table colour c, clamped to [0, 1] in 1D (ParaView clamps it there, not in 2D); with dLit, also
  // d(lit)/d(c) per channel (0 where the clamp cuts, or no light reaches).
  template <int K>
  void shade(const Setup& s, const S (&diffs)[3][K], const S (&specs)[3][K], int i, const S c[4],
    double col[3], double* dLit) const
  {
    const S diff[3] = { diffs[0][i], diffs[1][i], diffs[2][i] },
            spec[3] = { specs[0][i], specs[1][i], specs[2][i] };
    S lit[3];
    litColour(s.kit, diff, spec, c, lit);
    for (int ch = 0; ch < 3; ++ch)
    {
      const bool cut = s.clampLit && !(lit[ch] > S(0) && lit[ch] < S(1));
      col[ch] = s.clampLit ? std::clamp(static_cast<double>(lit[ch]), 0.0, 1.0)
                           : static_cast<double>(lit[ch]);
      if (dLit)
        dLit[ch] = cut ? 0.0 : static_cast<double>(s.kit.diffuse * diff[ch]);
    }
  }

  template <bool TwoD>
  void forward(const Classifier<S, TwoD>& cls, const Setup& s, const View& view,
    const RenderOptions& opt, const std::vector<int>& pixels, std::vector<S>& rgba,
    std::vector<RayRecord>& records)
  {
    const size_t n = pixels.empty() ? static_cast<size_t>(view.width) * view.height : pixels.size();
    rgba.assign(4 * n, S(0));
    // Reset the records, keeping their sample buffers' capacity (a reconstruction renders the
    // same number of rays step after step).
    records.resize(n);
    for (auto& r : records)
    {
      r.lastSample = -1;
      r.alpha = 0;
      r.samples.clear();
    }
    constexpr int channels = TwoD ? 2 : 1; // stored values per sample
    // and, Shade on, the sample's light sums (diffuse, specular) after them
    const int stride = channels + (s.lit ? kLightFloats : 0);
    std::atomic<std::int64_t> budget{ 0 }, lightBudget{ 0 };
    // Per thread, the values of the ray being marched; the record takes the marched part.
    const int threads = resolveThreadCount(opt.threads, static_cast<std::int64_t>((n + 63) / 64));
    std::vector<std::vector<float>> scratch(static_cast<size_t>(threads));
    withValues(
      [&](const auto& Values)
      {
        forPixels(view, s, pixels, threads,
          [&](std::int64_t q, const Eigen::Vector3d& o, const Eigen::Vector3d& dir, double j,
            int threadId)
          {
            RaySegment seg;
            if (!raySegment(o, dir, s.boxMin, s.boxMax, s.origin, s.spacing, s.d, j, seg))
            {
              return;
            }
            if (s.piece)
            {
              if (!ownedSamples(seg, j, s.lo, s.hi, s.n))
                return;
              for (int a = 0; a < 3; ++a)
                seg.e[a] -= s.off[a]; // into the piece's index space
            }
            RayRecord& rec = records[static_cast<size_t>(q)];
            rec.firstSample = static_cast<std::int32_t>(seg.kFirst);
            float* store = nullptr; // samples kFirst .. of this ray (float renderer)
            if constexpr (std::is_same_v<S, float>)
            {
              auto& buffer = scratch[static_cast<size_t>(threadId)];
              buffer.resize(
                std::max(buffer.size(), static_cast<size_t>(seg.kLast - seg.kFirst + 1) * stride));
              store = buffer.data();
            }
            const S e[3] = { static_cast<S>(seg.e[0]), static_cast<S>(seg.e[1]),
              static_cast<S>(seg.e[2]) };
            const S st[3] = { static_cast<S>(seg.s[0]), static_cast<S>(seg.s[1]),
              static_cast<S>(seg.s[2]) };
            double C[3] = { 0, 0, 0 }, A = 0;
            std::int64_t k = 0;
            bool done = false;
            S value[FieldSampler<S>::kBatch], gradient[FieldSampler<S>::kBatch];
            GradientStencil::Cell<S> cell; // the ray's last cell (2D gradients)
            // batches at multiples of kBatch from sample 0 (the same positions, bit for bit, in
            // every pass and every piece), lanes before kFirst left out
            constexpr int kB = FieldSampler<S>::kBatch;
            for (std::int64_t k0 = seg.kFirst - seg.kFirst % kB; k0 <= seg.kLast && !done; k0 += kB)
            {
              const S kk0 = static_cast<S>(j) + static_cast<S>(k0);
              Values.sampleBatch(e, st, kk0, value);
              if constexpr (TwoD)
              {
                sampleTransferGradients(Values.v, e, st, kk0, cell, gradient);
              }
              const int l0 = static_cast<int>(std::max<std::int64_t>(0, seg.kFirst - k0));
              const int n = static_cast<int>(std::min<std::int64_t>(kB, seg.kLast + 1 - k0));
              if (store)
              {
                for (int l = l0; l < n; ++l)
                {
                  store[stride * (k0 + l - seg.kFirst)] = static_cast<float>(value[l]);
                  if constexpr (TwoD)
                  {
                    store[stride * (k0 + l - seg.kFirst) + 1] = static_cast<float>(gradient[l]);
                  }
                }
              }
              S c[kB][4];
              for (int l = l0; l < n; ++l)
              {
                typename Classifier<S, TwoD>::Coord coord;
                cls.classify(value[l], TwoD ? gradient[l] : S(0), c[l], coord);
              }
              // Shade on: the light sums of the batch's visible samples the ray reaches (its
              // opacity, which the lighting does not change, says where it stops), together
              int lanes = 0;
              S kk[kB], diff[3][kB], spec[3][kB];
              if (s.lit)
              {
                double reached = A, ignored[3] = { 0, 0, 0 };
                for (int l = l0; l < n; ++l)
                  if (c[l][3] > S(0))
                  {
                    kk[lanes++] = static_cast<S>(j) + static_cast<S>(k0 + l);
                    adjoint::blend(ignored, reached, ignored, static_cast<double>(c[l][3]));
                    if (reached > static_cast<double>(s.termination))
                      break;
                  }
                sampleLightSums(
                  s.kit, s.frame, Stencil, Values.v, cell, e, st, kk, lanes, diff, spec);
              }
              // (the visible samples in the same order: the i-th has the light sums' lane i)
              for (int l = l0, i = 0; l < n; ++l)
              {
                k = k0 + l;
                if (c[l][3] > S(0))
                {
                  double col[3] = { c[l][0], c[l][1], c[l][2] };
                  if (s.lit)
                  {
                    if (store)
                    {
                      float* light = store + stride * (k - seg.kFirst) + channels;
                      for (int ch = 0; ch < 3; ++ch)
                      {
                        light[ch] = static_cast<float>(diff[ch][i]);
                        light[3 + ch] = static_cast<float>(spec[ch][i]);
                      }
                    }
                    shade(s, diff, spec, i++, c[l], col, nullptr);
                  }
                  adjoint::blend(C, A, col, static_cast<double>(c[l][3]));
                  if (A > static_cast<double>(s.termination))
                  {
                    done = true;
                    break;
                  }
                }
              }
            }
            S* out = &rgba[4 * static_cast<size_t>(q)];
            out[0] = static_cast<S>(C[0]);
            out[1] = static_cast<S>(C[1]);
            out[2] = static_cast<S>(C[2]);
            out[3] = static_cast<S>(A);
            rec.lastSample = static_cast<std::int32_t>(k);
            rec.alpha = A;
            if (store)
            {
              // Kept while the call's totals stay within their budgets (one for the values, one
              // for the light sums): the values and light sums, else the values alone (the
              // backward pass relights), else nothing (it re-interpolates too).
              const std::int64_t samples = k - seg.kFirst + 1;
              auto reserve = [&](std::atomic<std::int64_t>& total, std::int64_t used)
              {
                if (total.fetch_add(used, std::memory_order_relaxed) + used <= kRecordBudget)
                  return true;
                total.fetch_sub(used, std::memory_order_relaxed);
                return false;
              };
              const bool values = reserve(budget, samples * channels);
              if (values && stride > channels && reserve(lightBudget, samples * kLightFloats))
              {
                rec.samples.assign(store, store + samples * stride);
              }
              else if (values)
              {
                rec.samples.resize(static_cast<size_t>(samples * channels));
                for (std::int64_t i = 0; i < samples; ++i)
                  for (int ch = 0; ch < channels; ++ch)
                    rec.samples[static_cast<size_t>(i * channels + ch)] = store[i * stride + ch];
              }
              else
              {
                rec.samples.shrink_to_fit(); // over the budget: this ray is re-interpolated
              }
            }
          });
      });
  }

  template <bool TwoD>
  void backward(const Classifier<S, TwoD>& cls, const Setup& s, size_t tableSize, const View& view,
    const RenderOptions& opt, const std::vector<int>& pixels, const std::vector<RayRecord>& records,
    const std::vector<S>& dL_dRGBA, std::vector<S>& dL_dTable)
  {
    const size_t n = pixels.empty() ? static_cast<size_t>(view.width) * view.height : pixels.size();
    if (records.size() != n || dL_dRGBA.size() != 4 * n || dL_dTable.size() != 4 * tableSize)
    {
      throw Error(
        "backward: sizes of records, dL_dRGBA or dL_dTable do not match the forward pass");
    }
    // Per-worker gradient buffers w.r.t. the prepared table, reduced at the end in worker order
    // (no atomics; for a given thread count, the same gradient every run).
    const int threads = resolveThreadCount(opt.threads, static_cast<std::int64_t>((n + 63) / 64));
    std::vector<std::vector<S>> local(
      static_cast<size_t>(threads), std::vector<S>(4 * tableSize, S(0)));
    withValues(
      [&](const auto& Values)
      {
        forPixels(
          view, s, pixels, threads,
          [&](std::int64_t q, const Eigen::Vector3d& o, const Eigen::Vector3d& dir, double j,
            int threadId)
          {
            const RayRecord& rec = records[static_cast<size_t>(q)];
            RaySegment seg;
            if (rec.lastSample < 0 ||
              !raySegment(o, dir, s.boxMin, s.boxMax, s.origin, s.spacing, s.d, j, seg))
            {
              return;
            }
            seg.kFirst = rec.firstSample; // a piece's first owned sample (forward's ownedSamples)
            if (s.piece)
              for (int a = 0; a < 3; ++a)
                seg.e[a] -= s.off[a];
            const S e[3] = { static_cast<S>(seg.e[0]), static_cast<S>(seg.e[1]),
              static_cast<S>(seg.e[2]) };
            const S st[3] = { static_cast<S>(seg.s[0]), static_cast<S>(seg.s[1]),
              static_cast<S>(seg.s[2]) };
            const S* g = &dL_dRGBA[4 * static_cast<size_t>(q)];
            const double gC[3] = { g[0], g[1], g[2] };
            double gA = g[3];
            double A = rec.alpha;
            S* dTable = local[static_cast<size_t>(threadId)].data();
            GradientStencil::Cell<S> litCell; // the ray's last cell (Shade)
            // One sample of the replay, from the last to the first.
            // light: the sample's light sums kept by the forward pass (Shade on), or null
            auto replay = [&](S value, S gradient, std::int64_t k, const float* light)
            {
              S c[4];
              typename Classifier<S, TwoD>::Coord coord;
              cls.classify(value, gradient, c, coord);
              const double a = c[3] > S(0) ? static_cast<double>(c[3]) : 0.0;
              // Inverse of the blend: the state before this sample.
              const double before =
                a > 0 ? adjoint::blendInvertAlphaReciprocal(A, a, 1.0 / (1.0 - a)) : A;
              double col[3] = { c[0], c[1], c[2] };
              double dLit[3] = { 1, 1, 1 }; // d(lit colour) / d(table colour), per channel
              if (s.lit && a > 0)
              {
                S diff[3][1], spec[3][1];
                if (light)
                  for (int ch = 0; ch < 3; ++ch)
                  {
                    diff[ch][0] = static_cast<S>(light[ch]);
                    spec[ch][0] = static_cast<S>(light[3 + ch]);
                  }
                else
                {
                  const S kk[1] = { static_cast<S>(j) + static_cast<S>(k) };
                  sampleLightSums(
                    s.kit, s.frame, Stencil, Values.v, litCell, e, st, kk, 1, diff, spec);
                }
                shade(s, diff, spec, 0, c, col, dLit);
              }
              double g_c[3] = { 0, 0, 0 }, g_a = 0;
              adjoint::blendAdjoint(gC, gA, before, col, a, g_c, g_a);
              for (int ch = 0; ch < 3; ++ch)
                g_c[ch] *= dLit[ch];
              A = before;
              const S dL_drgba[4] = { static_cast<S>(g_c[0]), static_cast<S>(g_c[1]),
                static_cast<S>(g_c[2]), static_cast<S>(g_a) };
              cls.classifyAdjoint(coord, dL_drgba, dTable);
            };
            const std::int64_t kStop = std::min<std::int64_t>(rec.lastSample, seg.kLast);
            const std::int64_t kFirst = seg.kFirst;
            constexpr int channels = TwoD ? 2 : 1;
            // the record holds values and light sums, the values alone, or nothing (forward)
            const int kept = static_cast<int>(rec.samples.size() /
              static_cast<size_t>(std::max<std::int64_t>(1, kStop - kFirst + 1)));
            const int stride = s.lit && kept == channels + kLightFloats ? kept : channels;
            if (rec.samples.size() == static_cast<size_t>(kStop - kFirst + 1) * stride)
            {
              // The values (and light sums) the forward pass kept.
              const float* v = rec.samples.data(); // from sample kFirst
              for (std::int64_t k = kStop; k >= kFirst; --k)
              {
                const float* w = v + stride * (k - kFirst);
                replay(static_cast<S>(w[0]), TwoD ? static_cast<S>(w[channels - 1]) : S(0), k,
                  stride > channels ? w + channels : nullptr);
              }
              return;
            }
            // Re-interpolate, a batch of values at a time.
            constexpr int kB = FieldSampler<S>::kBatch;
            S value[kB], gradient[kB];
            GradientStencil::Cell<S> cell; // the ray's last cell (2D gradients)
            for (std::int64_t k0 = kStop - kStop % kB; k0 + kB > kFirst; k0 -= kB)
            {
              const S kk0 = static_cast<S>(j) + static_cast<S>(k0);
              Values.sampleBatch(e, st, kk0, value);
              if constexpr (TwoD)
              {
                sampleTransferGradients(Values.v, e, st, kk0, cell, gradient);
              }
              const int l0 = static_cast<int>(std::max<std::int64_t>(0, kFirst - k0));
              for (int l = static_cast<int>(std::min<std::int64_t>(kB - 1, kStop - k0)); l >= l0;
                   --l)
              {
                replay(value[l], TwoD ? gradient[l] : S(0), k0 + l, nullptr);
              }
            }
          },
          true); // each worker's chunks fixed: the same sums, in the same order, every run
      });
    std::vector<S> dPrepared(4 * tableSize, S(0));
    for (const auto& buffer : local)
    {
      for (size_t i = 0; i < dPrepared.size(); ++i)
      {
        dPrepared[i] += buffer[i];
      }
    }
    cls.table.chain(dPrepared, dL_dTable);
  }

  // --- pieces: the local passes wrapped in the exchange -----------------------------------

  // One collective step: fill(mine) writes this piece's `stride` - 1 floats (its status, the
  // last float, is 1 when fill throws); every piece's block is gathered. Then this piece's own
  // failure is rethrown, or PieceFailed when another's failed; else every block is returned.
  template <typename Fill>
  std::vector<float> exchange(std::int64_t stride, Fill&& fill) const
  {
    std::vector<float> mine(static_cast<size_t>(stride), 0.0f);
    std::exception_ptr failure;
    try
    {
      fill(mine);
    }
    catch (...)
    {
      failure = std::current_exception();
      mine.back() = 1.0f;
    }
    const int pieces = Exchange->pieces();
    std::vector<float> all(static_cast<size_t>(stride) * pieces);
    Exchange->allGather(mine.data(), stride, all.data());
    if (failure)
      std::rethrow_exception(failure);
    for (int p = 0; p < pieces; ++p)
      if (all[static_cast<size_t>((p + 1) * stride - 1)] != 0.0f)
        throw PieceFailed();
    return all;
  }

  // local() runs this piece's forward pass into rgba and records; then every piece's partial
  // RGBA and first-sample index are gathered and composited: rgba becomes the whole's, the
  // records get this piece's front and back.
  template <typename Local>
  void forwardPieces(Local&& local, const View& view, const std::vector<int>& pixels,
    std::vector<S>& rgba, std::vector<RayRecord>& records) const
  {
    const std::int64_t n = pixels.empty() ? static_cast<std::int64_t>(view.width) * view.height
                                          : static_cast<std::int64_t>(pixels.size());
    const std::int64_t stride = 5 * n + 1;
    const std::vector<float> all = exchange(stride,
      [&](std::vector<float>& mine)
      {
        if (Caster)
          local();
        else // owns no cell: transparent, behind every piece
        {
          view.validate();
          rgba.assign(static_cast<size_t>(4 * n), S(0));
          records.assign(static_cast<size_t>(n), RayRecord());
        }
        for (std::int64_t q = 0; q < n; ++q)
        {
          for (int c = 0; c < 4; ++c)
            mine[4 * q + c] = static_cast<float>(rgba[4 * q + c]);
          const RayRecord& r = records[static_cast<size_t>(q)];
          mine[4 * n + q] = r.lastSample >= 0 ? static_cast<float>(r.firstSample)
                                              : std::numeric_limits<float>::infinity();
        }
      });
    const int pieces = Exchange->pieces();
    std::vector<const float*> colours, keys;
    for (int p = 0; p < pieces; ++p)
    {
      colours.push_back(all.data() + p * stride);
      keys.push_back(all.data() + p * stride + 4 * n);
    }
    std::vector<float> out(static_cast<size_t>(4 * n)), front(static_cast<size_t>(n)),
      back(static_cast<size_t>(4 * n));
    compositePixels(colours, keys, n, Exchange->piece(), out.data(), front.data(), back.data());
    rgba.assign(out.begin(), out.end());
    for (std::int64_t q = 0; q < n; ++q)
    {
      RayRecord& r = records[static_cast<size_t>(q)];
      r.front = front[static_cast<size_t>(q)];
      std::copy(&back[4 * q], &back[4 * q] + 4, r.back);
    }
  }

  // local(dPiece, dTable) runs this piece's backward pass from its share of dL/d(image) into a
  // zeroed table gradient; the pieces' table gradients are gathered and added to dL_dTable
  // piece by piece (the same sums on every piece).
  template <typename Local>
  void backwardPieces(Local&& local, size_t tableSize, const View& view,
    const std::vector<int>& pixels, const std::vector<RayRecord>& records,
    const std::vector<S>& dL_dRGBA, std::vector<S>& dL_dTable) const
  {
    const std::int64_t n = pixels.empty() ? static_cast<std::int64_t>(view.width) * view.height
                                          : static_cast<std::int64_t>(pixels.size());
    const std::int64_t stride = 4 * static_cast<std::int64_t>(tableSize) + 1;
    const std::vector<float> all = exchange(stride,
      [&](std::vector<float>& mine)
      {
        if (records.size() != static_cast<size_t>(n) || dL_dRGBA.size() != 4 * records.size() ||
          dL_dTable.size() != 4 * tableSize)
          throw Error(
            "backward: sizes of records, dL_dRGBA or dL_dTable do not match the forward pass");
        if (Caster)
        {
          std::vector<float> g(dL_dRGBA.begin(), dL_dRGBA.end()), front(static_cast<size_t>(n)),
            back(static_cast<size_t>(4 * n)), d(static_cast<size_t>(4 * n));
          for (std::int64_t q = 0; q < n; ++q)
          {
            const RayRecord& r = records[static_cast<size_t>(q)];
            front[static_cast<size_t>(q)] = r.front;
            std::copy(r.back, r.back + 4, &back[4 * q]);
          }
          compositePixelsAdjoint(g.data(), front.data(), back.data(), n, d.data());
          const std::vector<S> dPiece(d.begin(), d.end());
          std::vector<S> dTable(4 * tableSize, S(0));
          local(dPiece, dTable);
          for (size_t i = 0; i < dTable.size(); ++i)
            mine[i] = static_cast<float>(dTable[i]);
        }
      });
    for (int p = 0; p < Exchange->pieces(); ++p)
      for (size_t i = 0; i < 4 * tableSize; ++i)
        dL_dTable[i] += static_cast<S>(all[static_cast<size_t>(p * stride) + i]);
  }
};

template <typename S>
DifferentiableRendererT<S>::DifferentiableRendererT(const Volume& volume)
  : In(std::make_unique<Internals>(volume))
{
}

template <typename S>
DifferentiableRendererT<S>::DifferentiableRendererT(
  const Volume& piece, const VolumeBrick& brick, std::shared_ptr<const PieceExchange> exchange)
  : In(std::make_unique<Internals>(piece, brick, std::move(exchange)))
{
}

template <typename S>
DifferentiableRendererT<S>::~DifferentiableRendererT() = default;

template <typename S>
const RayCaster& DifferentiableRendererT<S>::caster() const
{
  if (!In->Caster)
    throw Error("this volume piece owns no cell: it has no ray caster");
  return *In->Caster;
}

template <typename S>
std::array<double, 2> DifferentiableRendererT<S>::dataRange() const
{
  return In->Brick ? In->Brick->wholeRange : In->Caster->dataRange();
}

template <typename S>
std::array<double, 6> DifferentiableRendererT<S>::bounds() const
{
  return In->Brick ? In->Brick->wholeBounds(In->Brick->spacing) : In->Caster->volume().bounds();
}

template <typename S>
double DifferentiableRendererT<S>::defaultSampleDistance() const
{
  return In->Brick ? ddg::defaultSampleDistance(In->Brick->spacing, In->Brick->wholeDims)
                   : In->Caster->defaultSampleDistance();
}

template <typename S>
const VolumeBrick* DifferentiableRendererT<S>::brick() const
{
  return In->Brick ? &*In->Brick : nullptr;
}

template <typename S>
const PieceExchange* DifferentiableRendererT<S>::exchange() const
{
  return In->Exchange.get();
}

template <typename S>
std::array<double, 2> DifferentiableRendererT<S>::gradientRange() const
{
  if (!In->Brick)
    return In->Caster->volume().gradientMagnitudeRange();
  if (!(In->Brick->wholeGradientRange[1] > 0))
    throw Error("the volume pieces have not agreed on the whole's gradient-magnitude range (2D "
                "tables need it)");
  return In->Brick->wholeGradientRange;
}

namespace
{

template <typename S>
Classifier<S, false> make1D(
  const S* table, int width, double min, double max, double q, double exponent)
{
  if (width < 2 || !(max > min) || !table)
  {
    throw Error("transfer function table needs >= 2 entries and a non-empty range");
  }
  Classifier<S, false> c;
  c.width = width;
  c.table.prepare(table, static_cast<size_t>(width), static_cast<S>(exponent));
  c.vScale = static_cast<S>(q * width / (max - min));
  c.vBias = static_cast<S>(-min * width / (max - min) - 0.5);
  return c;
}

template <typename S>
Classifier<S, true> make2D(const S* table, int width, int height, std::array<double, 2> vr,
  std::array<double, 2> gr, double q, double exponent)
{
  if (width < 2 || height < 2 || !(vr[1] > vr[0]) || !(gr[1] > gr[0]) || !table)
  {
    throw Error("2D transfer function table needs >= 2 x 2 entries and non-empty ranges");
  }
  Classifier<S, true> c;
  c.width = width;
  c.height = height;
  c.table.prepare(table, static_cast<size_t>(width) * height, static_cast<S>(exponent));
  c.vScale = static_cast<S>(q * width / (vr[1] - vr[0])); // q: as RayCaster's Classify2D
  c.vBias = static_cast<S>(-vr[0] * width / (vr[1] - vr[0]) - 0.5);
  c.gScale = static_cast<S>(q * height / (gr[1] - gr[0]));
  c.gBias = static_cast<S>(-gr[0] * height / (gr[1] - gr[0]) - 0.5);
  return c;
}

} // namespace

template <typename S>
void DifferentiableRendererT<S>::forward(const S* table, int width, double min, double max,
  const View& view, const RenderOptions& options, const std::vector<int>& pixels,
  std::vector<S>& rgba, std::vector<RayRecord>& records) const
{
  auto local = [&]
  {
    const auto s = In->setup(view, options, false);
    In->forward(make1D(table, width, min, max, In->TextureScale, s.d / s.unit), s, view, options,
      pixels, rgba, records);
  };
  if (In->Exchange)
    In->forwardPieces(local, view, pixels, rgba, records);
  else
    local();
}

template <typename S>
void DifferentiableRendererT<S>::backward(const S* table, int width, double min, double max,
  const View& view, const RenderOptions& options, const std::vector<int>& pixels,
  const std::vector<RayRecord>& records, const std::vector<S>& dL_dRGBA,
  std::vector<S>& dL_dTable) const
{
  auto local = [&](const std::vector<S>& dRGBA, std::vector<S>& dTable)
  {
    const auto s = In->setup(view, options, false);
    In->backward(make1D(table, width, min, max, In->TextureScale, s.d / s.unit), s,
      static_cast<size_t>(width), view, options, pixels, records, dRGBA, dTable);
  };
  if (In->Exchange)
    In->backwardPieces(
      local, static_cast<size_t>(width), view, pixels, records, dL_dRGBA, dL_dTable);
  else
    local(dL_dRGBA, dL_dTable);
}

template <typename S>
void DifferentiableRendererT<S>::forward2D(const S* table, int width, int height,
  std::array<double, 2> valueRange, std::array<double, 2> gradientRange, const View& view,
  const RenderOptions& options, const std::vector<int>& pixels, std::vector<S>& rgba,
  std::vector<RayRecord>& records) const
{
  auto local = [&]
  {
    const auto s = In->setup(view, options, true);
    In->forward(
      make2D(table, width, height, valueRange, gradientRange, In->TextureScale, s.d / s.unit), s,
      view, options, pixels, rgba, records);
  };
  if (In->Exchange)
    In->forwardPieces(local, view, pixels, rgba, records);
  else
    local();
}

template <typename S>
void DifferentiableRendererT<S>::backward2D(const S* table, int width, int height,
  std::array<double, 2> valueRange, std::array<double, 2> gradientRange, const View& view,
  const RenderOptions& options, const std::vector<int>& pixels,
  const std::vector<RayRecord>& records, const std::vector<S>& dL_dRGBA,
  std::vector<S>& dL_dTable) const
{
  const size_t entries = static_cast<size_t>(width) * height;
  auto local = [&](const std::vector<S>& dRGBA, std::vector<S>& dTable)
  {
    const auto s = In->setup(view, options, true);
    In->backward(
      make2D(table, width, height, valueRange, gradientRange, In->TextureScale, s.d / s.unit), s,
      entries, view, options, pixels, records, dRGBA, dTable);
  };
  if (In->Exchange)
    In->backwardPieces(local, entries, view, pixels, records, dL_dRGBA, dL_dTable);
  else
    local(dL_dRGBA, dL_dTable);
}

template class DifferentiableRendererT<float>;
template class DifferentiableRendererT<double>;

} // namespace ddg
