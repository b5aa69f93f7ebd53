// DDGPieces.h: a filter's volume as pieces over the ranks of `mpiexec -np N pvserver` — each rank
// converts its own piece (with the ghost points the gradient needs), the ranks agree on the
// whole volume (extent, data range, a partition of its cells), and render it sort-last.
#pragma once

#include "DDGFiltersModule.h" // export macro
#include "DDGRanks.h"

#include "Design/DesignSpace.h"
#include "Gallery/BuildPlan.h"
#include "Gallery/DesignVolume.h"
#include "Render/DifferentiableRenderer.h"
#include "Render/RayCaster.h"
#include "Volume/VolumeBrick.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

class vtkDataArray;
class vtkImageData;

namespace ddg
{

/// Where `image` (this rank's piece, ghost points included) sits in the whole extent
/// `wholeExtent`: its points, the owned ones (the points not marked as ghosts by VTK's
/// vtkGhostType array: the piece's extent without ghosts), origin and dims of the whole. The
/// range is left for the ranks to agree on. An empty piece owns nothing.
DDGFILTERS_EXPORT VolumeBrick brickOf(vtkImageData* image, const int wholeExtent[6]);

/// A volume split over the ranks: this rank's piece and the caster of its owned cells (none when
/// it owns no cell).
struct DDGFILTERS_EXPORT RankVolume
{
  VolumeBrick brick;                 ///< this rank's (whole range agreed)
  std::vector<VolumeBrick> all;      ///< every rank's, rank by rank
  std::optional<Volume> piece;       ///< this rank's piece; none when it owns no cell
  std::unique_ptr<RayCaster> caster; ///< null when this rank owns no cell (or was not asked for)
  std::int64_t nonFiniteCount = 0;   ///< over the whole volume

  /// Collective: converts every rank's piece and agrees on the whole (data range over the ranks,
  /// with `gradientRange` also the gradient-magnitude range of 2D tables; the owned cells must
  /// partition the whole's, else every rank throws with the reason). With `caster`, builds the
  /// ray caster of the piece.
  static RankVolume gather(const RankGroup& ranks, vtkImageData* piece, vtkDataArray* array,
    const int wholeExtent[6], bool caster = true, bool gradientRange = false);
};

/// Collective: the differentiable renderer of this rank's piece, rendering with the other ranks'
/// pieces (sort-last forward and adjoint over VTK's controller; DifferentiableRenderer.h). Every
/// rank must then make the same passes: reconstructTransferFunction with the same targets and
/// options runs in step on all of them.
DDGFILTERS_EXPORT std::unique_ptr<DifferentiableRenderer> differentiableOnRanks(
  const RankGroup& ranks, const RankVolume& volume);

/// Collective: renders `tf` at `view` over the ranks' pieces (each rank its owned cells; ranks
/// without cells contribute nothing) and composites the images on the first rank, front to back
/// per pixel (compositeBricks). Returns the whole's premultiplied RGBA on the first rank, an
/// empty image elsewhere. Every rank throws together when one fails or is cancelled.
DDGFILTERS_EXPORT Image renderOnRanks(const RankGroup& ranks, const RankVolume& volume,
  const TransferFunctionFile& tf, const View& view, const RenderOptions& options,
  const ProgressCallback& progress);

/// Collective: renderOnRanks for a design's table (renderDesign's, DesignTable) with the
/// default render options.
DDGFILTERS_EXPORT Image renderOnRanks(
  const RankGroup& ranks, const RankVolume& volume, const DesignTable& table, const View& view);

/// Collective: the whole volume's fingerprint (volumeFingerprint, the same text one process
/// gives for the whole) on the first rank, empty elsewhere. Every rank sends the points it owns
/// (each point of the whole is owned by one rank: VolumeBrick's ownership, the last point plane
/// closed) a slab of point planes at a time (about 4 Mi values) to the first rank, which hashes
/// them in the whole's order: no rank holds more than its piece and one slab.
DDGFILTERS_EXPORT std::string fingerprintOnRanks(const RankGroup& ranks, const RankVolume& volume);

/// Collective: every rank's owned points (VolumeBrick's ownership) sent to the first rank
/// `planes` point planes at a time; there `visit` gets each slab in z order: planes z0 ..
/// z0 + planes - 1 of the whole, x fastest. A failure in `visit` reaches every rank (after the
/// last slab). What fingerprintOnRanks and designSpaceInputOnRanks stream.
DDGFILTERS_EXPORT void streamToFirstRank(const RankGroup& ranks, const RankVolume& volume,
  int planes, const std::function<void(int z0, int planes, const std::vector<float>& slab)>& visit);

/// Collective: the design space's input of the whole volume (checkBuildVolume; the volume
/// DesignSpaceAssembler makes of it, downsampled above `maxVoxels`; the whole's fingerprint) on
/// the first rank, the same bits one process gives for the whole (designSpaceInput); an empty
/// input elsewhere. The points stream to the first rank as fingerprintOnRanks's do: no rank
/// holds more than its piece, one slab and (the first) the design-space volume.
DDGFILTERS_EXPORT DesignSpaceInput designSpaceInputOnRanks(
  const RankGroup& ranks, const RankVolume& volume, std::int64_t maxVoxels);

/// The design renders a first rank asks for while it runs `work` (renders a table at a view over
/// every rank's piece: renderOnRanks; the image on the first rank).
using RanksTableRender = std::function<Image(const DesignTable& table, const View& view)>;

/// Collective: runs `work` on the first rank while the other ranks serve its renders (any
/// number, in the order asked). A failure in `work` or in a render reaches every rank and they
/// all throw together (RankGroup::step).
DDGFILTERS_EXPORT void renderForFirstRank(const RankGroup& ranks, const RankVolume& volume,
  const std::function<void(const RanksTableRender& render)>& work);

/// Which input and array (volumeVersion, the array object) a filter's kept result came from.
class DDGFILTERS_EXPORT InputStamp
{
public:
  /// In this process: whether the input or array changed since keep() (or nothing is kept).
  bool changed(vtkImageData* input, vtkDataArray* array) const;
  /// Collective: true on every rank when any rank's input or array changed.
  bool changedOnAnyRank(const RankGroup& ranks, vtkImageData* input, vtkDataArray* array) const;
  /// After the result is kept: the input and array it came from.
  void keep(vtkImageData* input, vtkDataArray* array);
  void clear() { Known = false; }

private:
  bool Known = false;
  std::uint64_t Version = 0; // volumeVersion of the input kept
  vtkDataArray* Array = nullptr;
};

/// A filter's pieces under MPI and the whole volume's fingerprint (fingerprintOnRanks: on the
/// first rank), agreed again when any rank's input or array changed.
class DDGFILTERS_EXPORT RankVolumeCache
{
public:
  /// Collective. The pieces with their casters and the gradient range (2D designs).
  const RankVolume& get(
    const RankGroup& ranks, vtkImageData* piece, vtkDataArray* array, const int wholeExtent[6]);
  const std::string& fingerprint() const { return Fingerprint; }

private:
  std::unique_ptr<RankVolume> Pieces;
  std::string Fingerprint;
  InputStamp Stamp;
};

/// A volume split over the ranks as a design gallery sees it: the whole's ranges and bounds,
/// ParaView's mapping from the first rank's piece (whose caster knows the whole), and renders
/// over every rank's piece through the renderForFirstRank call in progress (use()).
class DDGFILTERS_EXPORT RanksDesignVolume : public DesignVolume
{
public:
  void use(const RankVolume* volume, const RanksTableRender* render)
  {
    Volume = volume;
    Render = render;
  }
  std::array<double, 2> range() const override;
  std::array<double, 2> gradientRange() const override;
  std::array<double, 6> bounds() const override;
  Image render(const DesignTable& table, const View& view) const override;
  double opacityUnitDistance(const View& view) const override;
  ParaViewTransfer2DMapping paraviewMapping2D(const View& view) const override;

private:
  const RankVolume& pieces() const;
  const RayCaster& firstCaster() const;
  const RankVolume* Volume = nullptr;
  const RanksTableRender* Render = nullptr;
};

} // namespace ddg
