// DifferentiableRenderer.h: the ray caster's forward pass and its analytic adjoint with respect
// to a dense transfer function table, in constant memory per ray.
#pragma once

#include "Render/RayCaster.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace ddg
{

/// Forward and backward passes of the RayCaster model (RayCaster.h) for a subset of pixels.
///
/// Differences from RayCaster::render, all documented here: no empty-space skipping (below),
/// opacities after the step correction are clamped to adjoint::kMaxOpacity = 1 - 1e-6 (the
/// guard of the inversion below), and the ray state is accumulated in double. Images otherwise
/// agree with RayCaster to ~1e-6.
///
/// Why no skipping: a sample whose table opacity is 0 adds nothing to the image, but its
/// gradient is not 0: dL/da = (1 - A) (dL/dC . c + dL/dA), with c the colour looked up there,
/// lands on the opacity entries around its value (raising them would make it visible). Over a
/// run of such samples A, dL/dC and dL/dA stay constant, yet each sample still adds at its own
/// table coordinate with its own colour, so the backward pass must visit every one of them;
/// only the forward pass could skip them (exactly, as RayCaster does). And the reconstruction's
/// opacities are sigmoids, never 0, so no block is ever empty there in the first place.
///
/// Backward (DiffDVR's method): the forward pass keeps each ray's final A and the index of its
/// last sample; the backward pass replays the ray from that sample to the first, classifies
/// each sample again, inverts the compositing to recover the state before it
/// (A = (A' - a) / (1 - a)) and accumulates the gradients. The inversion is ill-conditioned for
/// a -> 1: opacities are clamped to 1 - 1e-6 and rays stop at the early-termination threshold
/// (A > 1 - 1/255), which bounds the error amplification by 255 / 1e-6 over a ray; the double
/// state keeps the recovered A within ~1e-9.
///
/// Stored or recomputed samples: the float renderer's forward pass also keeps each sample's
/// interpolated scalar (and gradient magnitude, 2D) in the ray's record, 4 (8) bytes per sample,
/// while the call's total stays within kRecordBudget values; the backward pass then reads them
/// instead of interpolating the volume again (the interpolation's scattered memory reads are
/// the largest cost of a pass over sparse random rays). Rays beyond the budget, and the double
/// renderer, keep constant memory and re-interpolate. Both give the same values bit for bit,
/// hence the same gradients. Shade on, the record also keeps each sample's light sums (24 more
/// bytes), so that the backward pass does not light the samples a second time (the per-point
/// gradients and the light kit cost more than the rest of both passes). The forward pass lights
/// the visible samples of a batch that the ray reaches together (lightSumsBatch), the replay one
/// by one: the same operations per sample, the same light sums bit for bit.
///
/// Shade on (view.lighting.shade): each sample's table colour is lit as RayCaster lights it
/// (Render/Lighting.h; clamped to [0, 1] with 1D tables, not with 2D ones, as ParaView does);
/// the lighting depends on the volume's gradient and the camera, not on the table, so the
/// backward pass scales the colour gradient by Diffuse x the sample's diffuse light sum (0 where
/// the 1D clamp cuts or no light reaches), kept by the forward pass in the record or, where it
/// kept none, recomputed in the replay from the per-point gradients (GradientStencil,
/// Render/Lighting.h).
///
/// Tables: `table` is a dense RGBA table of `width` entries over [min, max] in data values, with
/// UNCORRECTED opacity and ParaView's lookup convention (TransferTable1D). Gradients are with
/// respect to these entries. 2D tables: value x gradient magnitude, as TransferTable2D, the
/// gradient axis per sample as RayCaster computes it (transferGradient, Render/Lighting.h).
///
/// Pieces (the constructor with a VolumeBrick and a PieceExchange; ParaView's ranks under MPI):
/// each piece marches the samples it owns (ownedSamples, Render/RaySegment.h) of the whole's
/// rays; the forward pass gathers every piece's partial RGBA and first-sample index, composites
/// them front to back per pixel (compositePixels, Render/SortLast.h) and returns the whole's
/// image on every piece; the backward pass hands each piece its share of dL/d(image)
/// (compositePixelsAdjoint: scaled by the transmittance in front of it) and sums the pieces'
/// table gradients, piece by piece in order (the same numbers on every piece). Every piece makes
/// the same calls with the same pixels; a piece whose local pass fails throws its error and the
/// others PieceFailed, after the exchange (none waits forever). Pieces exchange floats. Each
/// piece stops its rays at the early-termination threshold on its own opacity, so images and
/// gradients agree with one process's within that threshold (exactly, up to float rounding,
/// with termination off).
///
/// What the forward pass keeps per ray for the backward pass (constant size).
struct RayRecord
{
  std::int32_t lastSample = -1; ///< index of the last sample marched (-1: the ray misses)
  std::int32_t firstSample = 0; ///< index of the first (0; a piece's first owned sample)
  double alpha = 0;             ///< final accumulated opacity, in double for the inversion
  /// Interpolated value of samples firstSample .. lastSample (2D: value, gradient magnitude per
  /// sample; Shade on, then the kLightFloats light sums, kept where the table opacity is not 0),
  /// or empty: the backward pass then re-interpolates (and relights). Float renderer only.
  std::vector<float> samples;
  /// Pieces: the opacity of the pieces in front of this one on the ray and the composite
  /// (C, A) of those behind it (compositePixels).
  float front = 0;
  float back[4] = { 0, 0, 0, 0 };
};

class PieceExchange;
struct VolumeBrick;

/// Most sample values (floats) one forward call keeps in its records (32 MB).
constexpr std::int64_t kRecordBudget = std::int64_t(1) << 23;
/// Shade on: floats a record keeps per sample after its value(s): the light sums (diffuse and
/// specular RGB), which depend on the volume and the camera, not on the table.
constexpr int kLightFloats = 6;

/// S is float (production) or double (gradient checks).
template <typename S>
class DifferentiableRendererT
{
public:
  /// Same requirements on the volume as RayCaster (throws ddg::Error otherwise).
  explicit DifferentiableRendererT(const Volume& volume);
  /// A piece of a whole volume rendering with the other pieces through `exchange` (above): the
  /// whole's rays, default distances, lighting and table ranges (brick.wholeRange; 2D:
  /// brick.wholeGradientRange, which must be agreed first). A piece that owns no cell takes part
  /// in every exchange with nothing of its own. Throws ddg::Error as RayCaster(piece, brick).
  DifferentiableRendererT(
    const Volume& piece, const VolumeBrick& brick, std::shared_ptr<const PieceExchange> exchange);
  ~DifferentiableRendererT();

  /// The ray caster of the volume (of the piece: RayCaster(piece, brick)). Throws ddg::Error for
  /// a piece that owns no cell.
  const RayCaster& caster() const;
  /// The data range tables are laid over (the whole's for a piece).
  std::array<double, 2> dataRange() const;
  /// The (whole) volume's bounds (xmin, xmax, ymin, ...) and ParaView's sample distance for it.
  std::array<double, 6> bounds() const;
  double defaultSampleDistance() const;
  /// The piece this renderer renders (null for a whole volume) and how it exchanges with the
  /// other pieces (null for a whole volume).
  const VolumeBrick* brick() const;
  const PieceExchange* exchange() const;
  /// The gradient-magnitude range of 2D tables (Volume::gradientMagnitudeRange; a piece's
  /// brick.wholeGradientRange, ddg::Error when it was not agreed).
  std::array<double, 2> gradientRange() const;

  /// Renders the listed pixels (index y * width + x, row 0 at the top; all pixels of the view
  /// when `pixels` is empty): OVERWRITES rgba (4 values per listed pixel: premultiplied
  /// colour, alpha) and records (one per listed pixel).
  void forward(const S* table, int width, double min, double max, const View& view,
    const RenderOptions& options, const std::vector<int>& pixels, std::vector<S>& rgba,
    std::vector<RayRecord>& records) const;

  /// Backward pass for the same call: dL_dRGBA holds dL/d(premultiplied RGBA) per listed pixel;
  /// ACCUMULATES dL/d(table entries) into dL_dTable (width * 4 values, uncorrected opacity).
  void backward(const S* table, int width, double min, double max, const View& view,
    const RenderOptions& options, const std::vector<int>& pixels,
    const std::vector<RayRecord>& records, const std::vector<S>& dL_dRGBA,
    std::vector<S>& dL_dTable) const;

  /// The same two passes with a 2D table (width x height entries, value fastest) over
  /// valueRange x gradientRange.
  void forward2D(const S* table, int width, int height, std::array<double, 2> valueRange,
    std::array<double, 2> gradientRange, const View& view, const RenderOptions& options,
    const std::vector<int>& pixels, std::vector<S>& rgba, std::vector<RayRecord>& records) const;
  void backward2D(const S* table, int width, int height, std::array<double, 2> valueRange,
    std::array<double, 2> gradientRange, const View& view, const RenderOptions& options,
    const std::vector<int>& pixels, const std::vector<RayRecord>& records,
    const std::vector<S>& dL_dRGBA, std::vector<S>& dL_dTable) const;

private:
  struct Internals;
  std::unique_ptr<Internals> In;
};

using DifferentiableRenderer = DifferentiableRendererT<float>;

} // namespace ddg
