// DesignSpace.h: the design space of a volume (paper §4.3.1): feature regions found from the
// value histogram, one base Gaussian primitive per region, and the spec of how exemplars vary.
#pragma once

#include "Design/PictureLook.h"

#include "Image/Image.h"
#include "Render/RayCaster.h"
#include "Render/View.h"
#include "TransferFunction/GaussianPrimitive.h"
#include "TransferFunction/TransferFunction2D.h"
#include "Volume/Volume.h"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ddg
{

/// A feature region of the value axis: [lo, hi] around a histogram peak at `peak`; 2D regions
/// (value x gradient magnitude) also span [gradientLo, gradientHi] around gradientPeak.
struct FeatureRegion
{
  double lo = 0, hi = 0, peak = 0;
  double mass = 0; ///< fraction of the non-air voxels in the region
  double gradientLo = 0, gradientHi = 0, gradientPeak = 0; ///< 2D only (1D: all 0)
  bool twoD() const { return gradientHi > gradientLo; }
};

/// Finds up to maxRegions feature regions: the 256-bin value histogram, log-scaled and smoothed
/// (Gaussian, 2 bins), minus "air" (when the most frequent value lies in the lowest 30 % of the
/// range, everything up to the first valley above it; bins with < 1e-4 of the voxels count as
/// noise), then the most prominent peaks, each spanning the valleys on either side. A region
/// `keep` refuses is left out and the next most prominent peak is taken; `keep` may narrow the
/// region it keeps (see DesignCheck.h).
std::vector<FeatureRegion> findFeatureRegions(
  const Volume& volume, int maxRegions = 4, const std::function<bool(FeatureRegion&)>& keep = {});
/// The same from the 256-bin value histogram of a volume's points over its data range
/// (valueCounts): a volume split into pieces sums its pieces' counts (each point counted once).
std::vector<FeatureRegion> findFeatureRegions(const std::vector<double>& counts,
  const std::array<double, 2>& range, int maxRegions = 4,
  const std::function<bool(FeatureRegion&)>& keep = {});
/// The points lo .. hi (inclusive, per axis) of `volume` counted in 256 bins over `range` (a
/// whole volume's data range): findFeatureRegions' histogram. Throws ddg::Error for an empty
/// range (a constant volume).
std::vector<double> valueCounts(const Volume& volume, const std::array<double, 2>& range,
  const std::array<int, 3>& lo, const std::array<int, 3>& hi);

/// Finds up to maxRegions 2D feature regions in the value x gradient-magnitude histogram
/// (128 x 64 bins over the value range x [0, 99.5th percentile of the gradient magnitude]),
/// log-scaled and smoothed (Gaussian, 1.5 bins), air excluded as in findFeatureRegions: every
/// local maximum, highest first, grows over the connected bins within one decade of it; a maximum
/// inside an earlier region is the same feature. Regions under 0.5 % of the non-air voxels are
/// noise. A region spans +- 2 standard deviations of its voxels along each axis (within its
/// bins) and peaks at its maximum. Materials appear at low gradient, the boundaries between them
/// at high gradient. `keep` as in findFeatureRegions.
std::vector<FeatureRegion> findFeatureRegions2D(
  const Volume& volume, int maxRegions = 4, const std::function<bool(FeatureRegion&)>& keep = {});

/// The base primitive of a region: mean at the peak, stddev = (hi - lo) / 4 (2D regions the
/// same along gradient magnitude), neutral colour, opacity 0.5.
GaussianPrimitive basePrimitive(const FeatureRegion& region);

/// How exemplars vary (JSON keys in brackets; defaults in brackets too). Colours are drawn in
/// HSL; shifts of mean are in units of the region's width.
struct DesignSpaceSpec
{
  /// ["regions": [{"lo", "hi", "peak", and in 2D "gradient_lo", "gradient_hi",
  /// "gradient_peak"}]] empty = found automatically
  std::vector<FeatureRegion> regions;
  int dimensions = 1; ///< ["dimensions"] 1: TFs over value; 2: value x gradient magnitude [1]
  int maxRegions = 4; ///< ["max_regions"] [4]
  int minActive = 1;  ///< ["min_active"] regions per exemplar, at least [1]
  std::array<double, 2> saturation{ 0.2, 1.0 }; ///< ["saturation"] [0.2, 1]
  std::array<double, 2> lightness{ 0.3, 0.9 };  ///< ["lightness"] [0.3, 0.9]
  std::array<double, 2> opacity{ 0.05, 0.9 };   ///< ["opacity"] peak opacity [0.05, 0.9]
  double meanShift =
    0.25; ///< ["mean_shift"] +- fraction of the region width (2D: both axes) [0.25]
  std::array<double, 2> stddevScale{ 0.4, 1.6 }; ///< ["stddev_scale"] x base stddev [0.4, 1.6]
  std::array<double, 2> elevation{ -60, 60 };    ///< ["elevation"] degrees [-60, 60]
  std::array<double, 2> zoom{ 0.9, 1.4 };        ///< ["zoom"] [0.9, 1.4]
  double viewportOpacity = 0.35; ///< ["viewport_opacity"] auxiliary TF's opacity [0.35]
  /// ["lighting"] the exemplars' lighting, a view JSON's "lighting" object (ParaView's Shade and
  /// coefficients) [unlit]
  Lighting lighting;
  /// ["lit_fraction"] with Shade on in "lighting": the share of exemplars rendered lit, the
  /// others unlit — the query analyzer learns lit and unlit pictures of the same designs [0.5]
  double litFraction = 0.5;
  /// ["picture_fraction"] the share of exemplars whose analyzer image is drawn as a user's
  /// picture (PictureLook.h: frame, roll, pan, zoom, backgrounds, overlays, JPEG) and framed as a
  /// query is (prepareQueryImage), the others a clean render over black or white [0]
  double pictureFraction = 0;

  /// Throws ddg::Error with the key for out-of-range values (ranges must be increasing and
  /// inside [0, 1] where they are fractions; maxRegions 1..16; ...).
  void validate() const;
};

DesignSpaceSpec parseDesignSpaceSpec(
  const std::string& jsonText, const std::string& origin = "design space spec");
DesignSpaceSpec readDesignSpaceSpec(const std::string& path);
std::string designSpaceSpecToJson(const DesignSpaceSpec& spec);

/// One design exemplar's parameters (everything needed to re-render it).
struct Exemplar
{
  std::uint64_t seed = 0;
  std::vector<int> active;                   ///< indices of the regions it uses
  std::vector<GaussianPrimitive> primitives; ///< TF_exp, one per active region
  View viewExp, viewView;                    ///< V_exp and V_view (with its lighting)
  int background = 0;                        ///< 0 black, 1 white (of the RGB image at V_exp)
  /// The analyzer's image drawn as a user's picture of V_exp (spec.pictureFraction), else unset
  std::optional<PictureLook> picture;
};

/// Draws exemplar `index` of the design space deterministically from (seed, index). With Shade
/// on in spec.lighting, its views are lit with probability spec.litFraction (one more draw, after
/// the others: an unlit spec's exemplars are what they were before lighting existed); with
/// spec.pictureFraction > 0 its analyzer image is a user's picture with that probability (drawn
/// after the lighting, the same way).
Exemplar sampleExemplar(const Volume& volume, const DesignSpaceSpec& spec,
  const std::vector<FeatureRegion>& regions, std::uint64_t seed, std::uint64_t index, int size);
/// The index of an exemplar drawn by sampleExemplar with `seed` (unsigned arithmetic: exact).
std::uint64_t exemplarIndex(const Exemplar& exemplar, std::uint64_t seed);

/// The view the exemplars use: ParaView's reset camera (defaultView, size x size) orbited by
/// azimuth (about +y) and elevation, +y up, zoomed (distance and parallel scale / zoom).
View orbitView(const Volume& volume, int size, double azimuthDeg, double elevationDeg, double zoom);
/// The same for a volume's bounds (a whole volume split into pieces).
View orbitView(const std::array<double, 6>& bounds, int size, double azimuthDeg,
  double elevationDeg, double zoom);

/// The view a design space's designs are shown at when none is given: ParaView's reset camera
/// (defaultView, size x size), lit as the design space's exemplars (spec.lighting with Shade on).
View designDefaultView(const Volume& volume, const DesignSpaceSpec& spec, int size);
/// The same for a volume's bounds (a whole volume split into pieces).
View designDefaultView(const std::array<double, 6>& bounds, const DesignSpaceSpec& spec, int size);

/// Ray casts a TF of primitives (none: an empty image) as the generator does: a 256-entry 1D
/// table, or (dimensions 2) a 256 x 64 table over the value range x
/// Volume::gradientMagnitudeRange().
Image renderDesign(const RayCaster& caster, const std::vector<GaussianPrimitive>& tf,
  int dimensions, const std::array<double, 2>& gradientRange, const View& view,
  const RenderOptions& options = {});

/// The table renderDesign ray casts for a TF of primitives (`dimensions` 1: `oneD`, 2: `twoD`),
/// for a front end that renders it elsewhere (over the ranks of a split volume).
struct DesignTable
{
  int dimensions = 1;
  TransferTable1D oneD;
  TransferTable2D twoD;
};
DesignTable designTable(const std::vector<GaussianPrimitive>& tf, int dimensions,
  const std::array<double, 2>& valueRange, const std::array<double, 2>& gradientRange);
/// `table` ray cast at `view` by `caster` (its 1D or 2D table).
Image renderTable(const RayCaster& caster, const DesignTable& table, const View& view,
  const RenderOptions& options = {});

/// The auxiliary TF (one grey primitive per region at the viewport opacity).
std::vector<GaussianPrimitive> auxiliaryPrimitives(
  const DesignSpaceSpec& spec, const std::vector<FeatureRegion>& regions);

/// A fingerprint of a volume: dims, spacing, range and a 64-bit FNV-1a hash of its values.
std::string volumeFingerprint(const Volume& volume);

/// The hash of volumeFingerprint fed in parts: the volume's values as floats, in its order (x
/// fastest, then y, then z), in as many calls as the caller likes (a volume split over ranks
/// streams its point planes to one of them).
class VolumeHash
{
public:
  void add(const float* values, std::int64_t count);
  std::uint64_t value() const { return Hash; }

private:
  std::uint64_t Hash = 1469598103934665603ull;
};

/// volumeFingerprint from its parts: the whole volume's dims, spacing, range and VolumeHash.
std::string volumeFingerprint(const std::array<int, 3>& dims, const std::array<double, 3>& spacing,
  const std::array<double, 2>& range, std::uint64_t hash);
/// A fingerprint in words, for messages: "103 x 94 x 161 voxels, values 0 to 255" ("an unknown
/// volume" when it does not parse).
std::string describeFingerprint(const std::string& fingerprint);

} // namespace ddg
