// ExemplarGenerator.h: renders design exemplars into compact binary shards plus a JSON index.
#pragma once

#include "Design/CandidateRenderer.h"
#include "Design/DesignSpace.h"
#include "Image/Image.h"
#include "Render/RayCaster.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ddg
{

/// Options (defaults in brackets).
struct GenerateOptions
{
  int count = 1000;       ///< exemplars [1000]
  int size = 64;          ///< square image side [64]
  std::uint64_t seed = 1; ///< the dataset is a deterministic function of (volume, spec, seed) [1]
  std::uint64_t firstIndex =
    0;                    ///< index of the first exemplar (held-out sets use another range) [0]
  int shardSize = 256;    ///< exemplars per shard file [256]
  int threads = 0;        ///< 0 = all cores
  std::string volumeFile; ///< recorded in dataset.json ("volume_file") so training finds it [""]
  /// Designs that show structure only (DesignCheck.h): feature regions that paint the box or
  /// show nothing are left out (findDesignRegions), and a design whose image at V_exp is empty or
  /// a flat box is passed over for the next index; once 4 x count candidates are examined (checked
  /// per batch) the rest are kept as drawn [false: every index in turn, as the shipped bundles were
  /// made]
  bool screen = false;
  /// The U-Net's viewport image (the auxiliary TF at V_view). The decoder never reads it: without
  /// it each exemplar costs two renders instead of three, its viewport bytes stay zero and
  /// dataset.json says "viewport": false (the U-Net refuses such data) [true]
  bool viewport = true;
  /// Other processes that render a share of every batch (not owned; the dataset is the same
  /// bytes as without them). The caller ends them ("end") when it has no more generations [none]
  ExemplarWorkers* workers = nullptr;
};

struct GenerateReport
{
  int count = 0;
  double seconds = 0;
  std::vector<FeatureRegion> regions;
  /// With GenerateOptions::screen: the indices examined, the designs passed over (empty, flat
  /// box), the feature regions left out, and whether the candidates ran out (then the last
  /// exemplars were kept unscreened).
  int candidates = 0, empty = 0, flatBox = 0, regionsLeftOut = 0;
  /// Candidates rendered by GenerateOptions::workers (the rest by this process).
  int workerCandidates = 0;
  bool screenExhausted = false;
};

/// Writes `dir` (created if needed; existing dataset files are replaced only when the new ones
/// are complete):
///   shard-NNNNN.bin  "DDGXSHRD", uint32 version 1, count, size, 0; then per exemplar, uint8:
///                    RGB at V_exp over its black/white background, or the exemplar's user's
///                    picture framed as a query (Exemplar::picture; size*size*3), the viewport
///                    image (auxiliary TF at V_view, premultiplied RGBA, size*size*4) and the
///                    ground truth (TF_exp at V_view, premultiplied RGBA, size*size*4)
///   dataset.json     format, version, volume fingerprint, size, count, seed, spec, regions,
///                    and per exemplar its seed, active regions, primitives, both views and
///                    its picture's look (when it has one);
///                    written last, so a dataset without it is incomplete.
/// Each exemplar is rendered on one thread, exemplars in parallel. Progress gets the fraction
/// done, on the calling thread, at least every 0.25 s of work and after each shard, and may
/// cancel (throws ddg::Cancelled within about one exemplar's render; the files of the cancelled
/// run are removed). With options.screen, exemplar i is the i-th index from firstIndex that
/// passes the screen (deterministic for any thread count); dataset.json records each one's seed.
GenerateReport generateExemplars(const Volume& volume, const DesignSpaceSpec& spec,
  const std::string& dir, const GenerateOptions& options,
  const std::function<bool(double)>& progress = {});

/// A generated dataset opened for reading (training, evaluation).
class ExemplarDataset
{
public:
  /// Reads dataset.json and checks every shard's header and size; throws ddg::Error naming the
  /// file for a missing, truncated or corrupt dataset.
  explicit ExemplarDataset(const std::string& dir);

  int count() const { return Count; }
  int size() const { return Size; }
  const std::string& fingerprint() const { return Fingerprint; }
  /// The volume file the dataset was generated from, as recorded ("" when unknown).
  const std::string& volumeFile() const { return VolumeFile; }
  /// Whether the exemplars have their viewport image (GenerateOptions::viewport).
  bool hasViewport() const { return Viewport; }
  const std::vector<Exemplar>& exemplars() const { return Items; }
  const std::vector<FeatureRegion>& regions() const { return Regions; }
  const DesignSpaceSpec& spec() const { return Spec; }

  /// The three images of exemplar i as uint8 (rgbExp: size*size*3; viewport, truth: *4).
  void load(int i, std::vector<std::uint8_t>& rgbExp, std::vector<std::uint8_t>& viewport,
    std::vector<std::uint8_t>& truth) const;

  /// The same as float images in [0, 1]: RGB at V_exp; premultiplied RGBA viewport and truth.
  struct Images
  {
    Image rgbExp, viewport, truth;
  };
  Images images(int i) const;

private:
  std::string Dir, Fingerprint, VolumeFile;
  int Count = 0, Size = 0, ShardSize = 0;
  bool Viewport = true;
  std::vector<Exemplar> Items;
  std::vector<FeatureRegion> Regions;
  DesignSpaceSpec Spec;
};

} // namespace ddg
