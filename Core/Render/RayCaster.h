// RayCaster.h: multithreaded CPU emission-absorption ray caster that follows ParaView 5.11's
// GPU volume mapper (sampling, tables, opacity correction, compositing, early termination).
#pragma once

#include "Image/Image.h"
#include "Render/View.h"
#include "TransferFunction/ParaViewTransferFunction2D.h"
#include "TransferFunction/TransferFunction1D.h"
#include "TransferFunction/TransferFunction2D.h"
#include "TransferFunction/TransferFunctionIO.h"
#include "Volume/Volume.h"
#include "Volume/VolumeBrick.h"

#include <cstdint>
#include <functional>
#include <memory>

namespace ddg
{

struct LightingFrame;

/// Thrown when a progress callback asks to stop.
class Cancelled : public Error
{
public:
  Cancelled()
    : Error("cancelled")
  {
  }
};

/// Called with the fraction done in [0, 1] from the calling thread; return false to cancel.
using ProgressCallback = std::function<bool(double fraction)>;

/// Counters of one render (for benchmarks and tests).
struct RenderStats
{
  std::int64_t rays = 0;           ///< rays that hit the volume's box
  std::int64_t samples = 0;        ///< samples interpolated and classified
  std::int64_t skippedSamples = 0; ///< samples jumped over in empty blocks
};

/// Options of a render. Defaults reproduce ParaView's still render of a Volume representation.
struct RenderOptions
{
  /// Step between samples in world units; 0 = ParaView's rule (RayCaster::defaultSampleDistance).
  double sampleDistance = 0.0;
  /// Per-pixel jitter of the first sample by j in [0, 1) steps, from ParaView's 64 x 64
  /// blue-noise tile as measured from its renders (jitterValue; Documentation/Rendering.md):
  /// on, the image is ParaView's sample for sample; off, every ray starts at sampleOffset.
  bool jitter = false;
  /// Offset of the first sample in steps when jitter is off: sample k sits at
  /// entry + (sampleOffset + k) * d. 0.5 is the mean of ParaView's jitter.
  double sampleOffset = 0.5;
  /// Stop a ray once its accumulated opacity exceeds this (ParaView: 1 - 1/255).
  double terminationOpacity = 1.0 - 1.0 / 255.0;
  /// Skip 8^3-cell blocks that the transfer function makes fully transparent. Exact: the
  /// image is the same with it on or off (only faster).
  bool emptySpaceSkipping = true;
  /// Worker threads; 0 = all cores.
  int threads = 0;
  /// With view.lighting.shade: the same march composites each visible sample unlit as well,
  /// into channels 4..7 (RGBA, premultiplied, the alpha the lit image's): the image of the view
  /// with Shade off, the same values as its own render, at the cost of the lit one alone.
  /// A piece of a volume refuses it. With Shade off the image is the plain RGBA one.
  bool unlitToo = false;
};

/// Renders a Volume with a 1D or 2D transfer function table and a View.
///
/// Model (per pixel, front to back; d = sample distance, ud = opacity unit distance):
///   sample k at p_k = entry + (j + k) d dir, k = 0, 1, ... while p_k is inside the point bounds
///   (the first sample is always taken), j = jitter or sampleOffset;
///   s = trilinear(value * q) with q = 256/255 (uint8), 65536/65535 (uint16), 32768/32767
///   (int16), else 1 (ParaView's texture normalisation); rgba = table lookup of s (linear);
///   a' = 1 - (1 - a)^(d / ud) when a > 1e-4 (else a);  C += (1 - A) a' clamp(rgb);
///   A += (1 - A) a'; stop when A > terminationOpacity.
/// With view.lighting.shade, the table colour of each visible sample is lit first as ParaView's
/// Shade does (Render/Lighting.h; 1D tables only).
/// Output: RGBA float image, premultiplied (C, A), row 0 at the top (8 channels, lit then unlit,
/// with RenderOptions::unlitToo and Shade); compose it over a
/// background with compositeOverBackground() (Image.h) to get ParaView's 8-bit screenshot.
///
/// A RayCaster reads the volume's scalars in place, in their own type (no copy: it shares them
/// with the Volume), keeps block min/max for empty-space skipping (8 bytes per 512 voxels) and
/// computes the gradients Shade and 2D tables need at each sample from the scalars around it
/// (GradientStencil, Render/Lighting.h: no per-voxel buffer); it can render many tables and
/// views, also concurrently.
class RayCaster
{
public:
  /// Throws ddg::Error when the volume has fewer than 2 points along an axis or is constant.
  explicit RayCaster(const Volume& volume);
  /// A renderer of one piece of a larger volume (VolumeBrick; ParaView's pieces under MPI): rays,
  /// samples, tables (the whole's data range), default distances, gradient scaling and lighting
  /// are the whole volume's, and it renders the samples it owns only. Its images have five
  /// channels: premultiplied (C, A) of its own samples along each ray, then the index k of its
  /// first sample on the ray (+inf where it has none); compositeBricks (Render/SortLast.h) puts
  /// the pieces' images together into the whole's image. Throws ddg::Error when the piece owns
  /// no cell, does not hold the points its cells need (VolumeBrick::validate; the ghost points
  /// the gradient needs are checked at render time) or the whole volume is constant.
  RayCaster(const Volume& piece, const VolumeBrick& brick);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  const Volume& volume() const;
  /// The piece this caster renders, or nullptr for a whole volume.
  const VolumeBrick* brick() const;
  /// The data range transfer functions are mapped over: the volume's, or the whole's for a piece.
  const std::array<double, 2>& dataRange() const;

  /// ParaView's sample distance for the (whole) volume (ddg::defaultSampleDistance, View.h).
  double defaultSampleDistance() const;
  /// ParaView's default Scalar Opacity Unit Distance: |bounds diagonal| / cbrt(cell count).
  double defaultOpacityUnitDistance() const;
  /// The opacity unit distance a TF is rendered and exported with at `view`: the view's, else
  /// ParaView's default (defaultOpacityUnitDistance).
  double opacityUnitDistance(const View& view) const;

  /// How ParaView's TransferFunction2D maps onto this volume's 2D TFs at `view` (its opacity
  /// unit distance, else the default; ParaView's sample distance): for fitParaViewBoxes.
  ParaViewTransfer2DMapping paraviewMapping2D(const View& view) const;

  /// The table ParaView builds for `tf` over this volume's data range.
  TransferTable1D paraviewTable(const TransferFunction1D& tf) const;
  /// The 2D table ParaView's mapper samples for its 2D TF `tf` on this volume at `view`
  /// (ParaViewTransferFunction2D::table with paraviewMapping2D(view)).
  TransferTable2D paraviewTable2D(const ParaViewTransferFunction2D& tf, const View& view) const;
  /// A TF file made ready for this volume at `view`: ParaView's 2D boxes become a 2D table
  /// (is2D); other files are returned as they are.
  TransferFunctionFile resolve(const TransferFunctionFile& tf, const View& view) const;
  /// Renders any TF file (1D preset, DDG 2D JSON, ParaView's 2D boxes) as ParaView would.
  Image render(const TransferFunctionFile& tf, const View& view, const RenderOptions& options = {},
    const ProgressCallback& progress = {}, RenderStats* stats = nullptr) const;

  /// Renders with a 1D table (any range; lookups use the table's own range).
  Image render(const TransferTable1D& table, const View& view, const RenderOptions& options = {},
    const ProgressCallback& progress = {}, RenderStats* stats = nullptr) const;
  /// Renders with a 2D (value x gradient magnitude) table, as ParaView's 2D transfer function
  /// with the gradient as Y: the gradient axis is taken per sample (transferGradient of the
  /// GradientStencil's gradient, Render/Lighting.h), opacity corrected for the step as 1D
  /// tables are; Shade on lights the sample as in 1D without clamping the lit colour (ParaView
  /// does not clamp it for 2D tables).
  Image render(const TransferTable2D& table, const View& view, const RenderOptions& options = {},
    const ProgressCallback& progress = {}, RenderStats* stats = nullptr) const;

  /// The per-pixel jitter tile value used when RenderOptions::jitter is on, for pixel (x, y)
  /// counted from the bottom-left as ParaView's window coordinates.
  static float jitterValue(int x, int yFromBottom);

  /// The normalisation factor q above for a scalar type.
  static double textureScale(ScalarType type);

private:
  RayCaster(const Volume& volume, const VolumeBrick* brick);
  std::array<double, 6> wholeBounds() const;
  // Shade and 2D tables on a piece: throws unless it holds the ghost points gradients need.
  void checkGradientPoints() const;
  LightingFrame lightingFrame(const View& view) const;
  struct Internals;
  std::unique_ptr<Internals> In;
};

} // namespace ddg
