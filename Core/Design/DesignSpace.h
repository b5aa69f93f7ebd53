// DesignSpace.h: the design space of a volume (paper §4.3.1): feature regions found from the
// value histogram, one base Gaussian primitive per region, and the spec of how exemplars vary.
#pragma once

#include "Render/View.h"
#include "TransferFunction/GaussianPrimitive.h"
#include "Volume/Volume.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddg
{

/// A feature region of the value axis: [lo, hi] around a histogram peak at `peak`.
struct FeatureRegion
{
  double lo = 0, hi = 0, peak = 0;
  double mass = 0; ///< fraction of the non-air voxels in [lo, hi]
};

/// Finds up to maxRegions feature regions: the 256-bin value histogram, log-scaled and smoothed
/// (Gaussian, 2 bins), minus "air" (when the most frequent value lies in the lowest 30 % of the
/// range, everything up to the first valley above it; bins with < 1e-4 of the voxels count as
/// noise), then the most prominent peaks, each spanning the valleys on either side.
std::vector<FeatureRegion> findFeatureRegions(const Volume& volume, int maxRegions = 4);

/// The base primitive of a region: mean at the peak, stddev = (hi - lo) / 4, neutral colour,
/// opacity 0.5.
GaussianPrimitive basePrimitive(const FeatureRegion& region);

/// How exemplars vary (JSON keys in brackets; defaults in brackets too). Colours are drawn in
/// HSL; shifts of mean are in units of the region's width.
struct DesignSpaceSpec
{
  std::vector<FeatureRegion>
    regions;          ///< ["regions": [{"lo", "hi", "peak"}]] empty = found automatically
  int maxRegions = 4; ///< ["max_regions"] [4]
  int minActive = 1;  ///< ["min_active"] regions per exemplar, at least [1]
  std::array<double, 2> saturation{ 0.2, 1.0 }; ///< ["saturation"] [0.2, 1]
  std::array<double, 2> lightness{ 0.3, 0.9 };  ///< ["lightness"] [0.3, 0.9]
  std::array<double, 2> opacity{ 0.05, 0.9 };   ///< ["opacity"] peak opacity [0.05, 0.9]
  double meanShift = 0.25; ///< ["mean_shift"] +- fraction of the region width [0.25]
  std::array<double, 2> stddevScale{ 0.4, 1.6 }; ///< ["stddev_scale"] x base stddev [0.4, 1.6]
  std::array<double, 2> elevation{ -60, 60 };    ///< ["elevation"] degrees [-60, 60]
  std::array<double, 2> zoom{ 0.9, 1.4 };        ///< ["zoom"] [0.9, 1.4]
  double viewportOpacity = 0.35; ///< ["viewport_opacity"] auxiliary TF's opacity [0.35]

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
  View viewExp, viewView;                    ///< V_exp and V_view
  int background = 0;                        ///< 0 black, 1 white (of the RGB image at V_exp)
};

/// Draws exemplar `index` of the design space deterministically from (seed, index).
Exemplar sampleExemplar(const Volume& volume, const DesignSpaceSpec& spec,
  const std::vector<FeatureRegion>& regions, std::uint64_t seed, std::uint64_t index, int size);

/// The auxiliary TF (one grey primitive per region at the viewport opacity).
std::vector<GaussianPrimitive> auxiliaryPrimitives(
  const DesignSpaceSpec& spec, const std::vector<FeatureRegion>& regions);

/// A fingerprint of a volume: dims, spacing, range and a 64-bit FNV-1a hash of its values.
std::string volumeFingerprint(const Volume& volume);

} // namespace ddg
