// KindNetwork.h: whether a picture shows a volume of the kind the user's volume is (issue 20, bad
// input "a picture of a volume of another kind"). A small network is taught to tell several
// volumes apart from their design-space exemplars (random TFs, views, lighting, drawn as users'
// pictures); a picture and a volume agree in kind when the network's answers for the picture and
// for the volume's own exemplars overlap (Bhattacharyya coefficient). It never saw the volume
// that is checked: it only needs its answers for both to look alike.
#pragma once

#include "Design/DesignSpace.h"
#include "Image/Image.h"
#include "Volume/Volume.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ddg
{

/// Training options (defaults in brackets: the shipped network's, scripts/train_kind.sh).
struct KindTrainOptions
{
  int epochs = 40;               ///< passes over the training exemplars [40]
  int batch = 128;               ///< exemplars per step [128]
  double maxLearningRate = 3e-3; ///< Adam, one-cycle schedule up to this rate [3e-3]
  double weightDecay = 1e-4;     ///< [1e-4]
  double validationShare = 0.1;  ///< exemplars held out to report accuracy [0.1]
  std::uint64_t seed = 5;        ///< weights, split, order and augmentation [5]
  int threads = 0;               ///< libtorch threads, 0 = all cores
};

struct KindTrainReport
{
  int trainingExemplars = 0, validationExemplars = 0;
  double validationAccuracy = 0; ///< held-out exemplars named right, after the last epoch
  double seconds = 0;
};

/// What the network says of a picture, and how that compares with a volume's exemplars.
struct KindCheck
{
  /// Bhattacharyya coefficient of the picture's class probabilities and the volume's mean ones:
  /// 1 = the network answers the same for both, 0 = nothing in common.
  double agreement = 1;
  double threshold = 0; ///< the network's calibrated threshold
  bool differs = false; ///< agreement < threshold: the picture may show another kind of volume
  std::string pictureLike, volumeLike; ///< the training volume each is most like
};

class KindNetwork
{
public:
  KindNetwork();
  ~KindNetwork();
  KindNetwork(KindNetwork&&) noexcept;
  KindNetwork& operator=(KindNetwork&&) noexcept;

  /// Trains on generated datasets (`ddg generate`, one per named volume; ExemplarDataset), their
  /// analyzer images (users' pictures framed as a query, or clean renders) augmented with flips,
  /// quarter turns, shuffled channels, grey and brightness. All datasets must have one image size
  /// and one spec (recorded: the volume's exemplars in kindReference are drawn with it). Progress
  /// gets (epoch, mean loss, held-out accuracy) after each epoch and may cancel (ddg::Cancelled).
  /// Throws ddg::Error for fewer than two datasets, a name given twice, or mismatched datasets.
  static KindNetwork train(const std::vector<std::string>& names,
    const std::vector<std::string>& datasetDirs, const KindTrainOptions& options,
    KindTrainReport* report = nullptr,
    const std::function<bool(int, double, double)>& progress = {});

  /// `dir`/kind.pt (weights) and `dir`/kind.json (format, classes, image size, spec, threshold,
  /// reference count and seed, training record), kind.json last.
  void save(const std::string& dir) const;
  /// Throws ddg::Error naming the directory for a missing or corrupt network.
  static KindNetwork load(const std::string& dir);

  const std::vector<std::string>& kinds() const;
  int imageSize() const;
  const DesignSpaceSpec& spec() const;
  /// Below this agreement a picture is said to show another kind of volume (calibrated on
  /// pictures of known kind, `ddg kind --calibrate`; 0 until then: never).
  double threshold() const;
  void setThreshold(double t);
  /// The volume's exemplars kindReference draws: count and seed [128, 99].
  int referenceCount() const;
  std::uint64_t referenceSeed() const;
  /// How the network was trained (kind.json "training"), as JSON text.
  const std::string& trainingRecord() const;
  /// A hash of the network's files (the weights, the reference's spec, count, seed and image
  /// size), set by load; 0 for a network not loaded from files.
  std::uint64_t identity() const;

  /// Class probabilities of a picture as a query reads and frames it (queryPicture, then
  /// prepareQueryImage at imageSize()), averaged over its 8 flips and quarter turns.
  std::vector<double> pictureProbabilities(const Image& picture) const;
  /// The same for images already framed at imageSize() (RGB, [0, 1]), averaged over all.
  std::vector<double> meanProbabilities(const std::vector<Image>& framed) const;

private:
  struct Internals;
  std::unique_ptr<Internals> In;
};

/// The volume's mean class probabilities: referenceCount() exemplars generated with the
/// network's spec and referenceSeed() (screened as `ddg generate --screen`, no viewport images;
/// written to a temporary directory that is removed). About 10 s for 128 exemplars at 64 px on
/// 2 cores. Progress gets the fraction done and may cancel (ddg::Cancelled). `count` > 0: the
/// first `count` exemplars only (KindChecker's probe of how references are drawn).
std::vector<double> kindReference(const KindNetwork& network, const Volume& volume, int threads = 0,
  const std::function<bool(double)>& progress = {}, int count = 0);

/// The picture's probabilities against a reference from kindReference.
KindCheck checkKind(
  const KindNetwork& network, const Image& picture, const std::vector<double>& reference);

/// Where KindChecker keeps references between sessions: $DDG_CACHE_DIR ("none": nowhere), else
/// $XDG_CACHE_HOME/ddg (when absolute), else $HOME/.cache/ddg; empty when none is known. (Unset
/// and empty variables are passed over.)
std::string kindCacheDirectory();

/// A kind network loaded once, and the reference of each volume it has checked kept (by volume
/// fingerprint): the kind check of the filters, the panel and `ddg reconstruct`. A reference is
/// also kept on disk (kindCacheDirectory()/kind-references/, one small JSON file per network and
/// volume, written atomically), so that the next session reads it instead of drawing its
/// exemplars again (7-10 s); a missing, unreadable or mismatched file is drawn again, and a
/// cache that cannot be written is left alone. The files' key holds the network's identity and
/// its reference of a fixed small volume (4 exemplars, drawn once per network), so that a
/// change in how references are drawn leaves the old files unread.
class KindChecker
{
public:
  /// checkKind of the picture against the volume with the network in `dir` (loaded when it is
  /// not the last one; throws ddg::Error as KindNetwork::load does).
  KindCheck check(const std::string& dir, const Image& picture, const Volume& volume,
    int threads = 0, const std::function<bool(double)>& progress = {});
  /// The same with the volume's volumeFingerprint already known (a filter's bundle session
  /// computed it): not computed again (empty: computed here).
  KindCheck check(const std::string& dir, const Image& picture, const Volume& volume,
    const std::string& fingerprint, int threads = 0,
    const std::function<bool(double)>& progress = {});
  /// Loads the network in `dir` now unless it is the one loaded (what check does first).
  void load(const std::string& dir);
  /// Whether the reference of the volume whose volumeFingerprint is `fingerprint` is kept for the
  /// network in `dir` (loaded first): in memory, or on disk (then read into memory).
  bool hasReference(const std::string& dir, const std::string& fingerprint);
  /// Keeps kindReference of `volume` under `fingerprint` (the fingerprint of the volume it
  /// stands for: under MPI the whole volume's, `volume` its design-space volume assembled on one
  /// process) for the network in `dir`.
  void addReference(const std::string& dir, const std::string& fingerprint, const Volume& volume,
    int threads = 0, const std::function<bool(double)>& progress = {});
  /// checkKind against the kept reference of `fingerprint` (throws ddg::Error when none is kept).
  KindCheck check(const std::string& dir, const Image& picture, const std::string& fingerprint);

private:
  /// The network's identity and its reference of a fixed small volume, hashed: the files' key
  /// (0: the network was not loaded from files, nothing is kept on disk).
  std::uint64_t diskKey();
  std::string Dir;
  std::unique_ptr<KindNetwork> Network;
  std::vector<std::pair<std::string, std::vector<double>>> References;
  std::uint64_t DiskKey = 0;
};

/// The check as JSON {"agreement", "threshold", "differs", "picture_like", "volume_like"} (the
/// filters' "Kind" field) and in words (one line: the CLI's and the filters' warning).
std::string kindCheckToJson(const KindCheck& check);
std::string describeKindCheck(const KindCheck& check);

/// sum_i sqrt(p_i q_i); throws ddg::Error for lengths that differ.
double bhattacharyya(const std::vector<double>& p, const std::vector<double>& q);

} // namespace ddg
