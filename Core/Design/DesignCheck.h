// DesignCheck.h: does a design show structure? A design whose image is empty, or a flat box (the
// volume's whole box painted: air, noise, a scanner's field of view or a container made
// visible), teaches a gallery nothing. Used to screen exemplars, outline designs and feature
// regions, and to measure design spaces (`ddg validity`).
#pragma once

#include "Design/DesignSpace.h"
#include "Image/Image.h"
#include "Render/RayCaster.h"
#include "Render/View.h"

namespace ddg
{

/// How a design's image covers the volume's box at its view. A pixel shows the design when the
/// render's alpha there is at least kDesignVisibleAlpha (over black, 0.03 of a mid-light colour
/// is ~4 of 255 levels: a haze a user sees). The box's footprint is the set of pixels whose ray
/// enters the volume's box; its ring is the footprint's outermost pixels (a 4-neighbour outside
/// it, or the image border).
struct DesignLook
{
  double coverage = 0;     ///< fraction of the footprint where the design shows
  double ringCoverage = 0; ///< the same on the footprint's ring
  int footprint = 0;       ///< pixels of the footprint (0: the box is not in view)
  /// Less than 1 % of the footprint shows anything.
  bool empty() const { return coverage < 0.01; }
  /// The box itself is painted: 90 % of the footprint and 80 % of its ring show the design (an
  /// object cut by the box's faces fills part of the ring, not most of it).
  bool flatBox() const { return coverage >= 0.9 && ringCoverage >= 0.8; }
  bool junk() const { return empty() || flatBox(); }
};

constexpr float kDesignVisibleAlpha = 0.03f;

/// The box's footprint at `view`: a 1-channel image, 1 where the pixel's ray enters the box.
Image boxFootprint(const RayCaster& caster, const View& view);

/// The look of a premultiplied RGBA render against the footprint of the same view (same size;
/// throws ddg::Error otherwise). A footprint of 0 pixels gives an empty look.
DesignLook lookOfDesign(const Image& premultipliedRGBA, const Image& footprint);

/// The mean opacity (the table's alpha per value) a 1D TF table gives `values` (0 for none): how
/// the box's corners and the outline check's boundary faces are judged.
double meanOpacity(const TransferTable1D& table, const std::vector<float>& values);

/// Air where it meets the box: the voxels of the box's eight corners (cubes of 1/16 of each side,
/// at least 2 voxels), where scans hold air, noise or a field of view and simulations their far
/// field. A haze over the box can be too faint at the box's silhouette (short rays) for the
/// footprint test, yet plain to see across it: a TF hazes the box when, at six or more corners,
/// its mean opacity there would show (alpha >= kDesignVisibleAlpha) across the box's shortest
/// side at the default opacity unit distance. (Six: a table or a plate under the object fills
/// four corners, not six.)
class BoxCorners
{
public:
  BoxCorners(const Volume& volume, int dimensions, double opacityUnitDistance);
  bool hazy(const std::vector<GaussianPrimitive>& tf) const;

private:
  std::array<std::vector<float>, 8> Values, Gradients;
  std::array<double, 2> Range{}, GradientRange{};
  int Dimensions = 1;
  double Threshold = 1; ///< the mean opacity that shows across the shortest side
};

/// The look of a TF of primitives at `view` (rendered as the generator does).
DesignLook lookOfPrimitives(const RayCaster& caster, const std::vector<GaussianPrimitive>& tf,
  int dimensions, const std::array<double, 2>& gradientRange, const View& view);

/// A TF judged at the three canonical views (azimuth 0, 120, 240, elevation 20, size x size,
/// exemplar views of zoom 1): empty when empty at all three, a flat box when a flat box at two
/// or more or when it hazes the box (BoxCorners).
struct DesignVerdict
{
  bool empty = false, flatBox = false;
  bool junk() const { return empty || flatBox; }
};
DesignVerdict judgeDesign(const RayCaster& caster, const BoxCorners& corners,
  const std::vector<GaussianPrimitive>& tf, int dimensions,
  const std::array<double, 2>& gradientRange, int size = 48);

/// Whether a feature region can carry designs: its base primitive alone (opacity 0.5) is not
/// junk by judgeDesign.
bool regionShowsStructure(const RayCaster& caster, const BoxCorners& corners,
  const FeatureRegion& region, int dimensions, const std::array<double, 2>& gradientRange);

/// The feature regions of a design space: the spec's own, else the histogram's most prominent
/// peaks (findFeatureRegions / findFeatureRegions2D) that show structure
/// (regionShowsStructure). A region that does not is narrowed about its peak to half its
/// extent, up to three times (a wide region's tails reach the air: the CT head's bone spans
/// everything above soft tissue), and left out when it still does not; `left` counts the peaks
/// left out. When no peak shows structure, the unscreened regions are returned (and left
/// stays 0).
/// `caster` and `corners` are the volume's (the generator's own, built once per build).
std::vector<FeatureRegion> findDesignRegions(const Volume& volume, const RayCaster& caster,
  const BoxCorners& corners, const DesignSpaceSpec& spec, int* left = nullptr);

/// The screen of one drawn design from its render at its V_exp view (premultiplied RGBA, as the
/// generator renders it): empty or a flat box at that view (lookOfDesign), or a haze over the box
/// (BoxCorners). The one rule of generateExemplars and buildOutlineLatents.
DesignVerdict screenDesign(const RayCaster& caster, const BoxCorners& corners,
  const std::vector<GaussianPrimitive>& tf, const Image& rgbaExp, const View& viewExp);

} // namespace ddg
