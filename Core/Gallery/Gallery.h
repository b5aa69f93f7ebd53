// Gallery.h: the design gallery over a model bundle (paper §5): outline latents of many
// generated designs, thumbnails at the current view, query by image, explicit TFs of designs.
#pragma once

#include "Design/CandidateRenderer.h"
#include "Gallery/DesignVolume.h"
#include "Gallery/Edit.h"
#include "Gallery/Navigation.h"
#include "Gallery/Outline.h"
#include "Gallery/QueryImage.h"
#include "Neural/NeuralDesignModel.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ddg
{

/// Latents of `count` designs of the model's design space for its outline: design index
/// firstIndex + i of seed `seed` (sampleExemplar with the bundle's spec and regions), its RGB
/// image at V_exp over its background at the model's size, analyzed. Deterministic; designs
/// 0..N-1 of seed 1 are the training exemplars of scripts/train_model.sh. Progress gets the
/// fraction done and may cancel (throws ddg::Cancelled). With `screen`, designs whose image is
/// empty or a flat box (DesignCheck.h) are passed over for the next index, as
/// GenerateOptions::screen does, so a screened build's outline holds its training exemplars.
/// `workers` (not owned) render shares of every slice of candidates (the same latents).
LatentSet buildOutlineLatents(const NeuralDesignModel& model, const Volume& volume, int count,
  std::uint64_t seed = 1, std::uint64_t firstIndex = 0, int threads = 0,
  const std::function<bool(double)>& progress = {}, bool screen = false,
  ExemplarWorkers* workers = nullptr);

/// The outline of a build (buildOutlineLatents' designs and screening) whose first designs are its
/// training exemplars: their latents from the analyzer images the training read (as saveBundle
/// analyses them; no design rendered again), then, when `count` is larger, designs drawn from the
/// index after the last exemplar's. Renders them all (buildOutlineLatents) when the exemplars'
/// analyzer images are users' pictures (spec.pictureFraction > 0): an outline shows clean
/// renders. Progress and cancel as buildOutlineLatents.
LatentSet outlineFromExemplars(const NeuralDesignModel& model, const Volume& volume,
  const ExemplarDataset& training, int count, std::uint64_t seed = 1, int threads = 0,
  const std::function<bool(double)>& progress = {}, bool screen = false,
  ExemplarWorkers* workers = nullptr);

/// The file of a bundle's outline latents.
std::string outlineFile(const std::string& bundleDir);

/// What a query returns.
struct QueryResult
{
  Image input;                       ///< what the analyzer saw (RGB, model size)
  std::vector<float> latent;         ///< its latent TF
  std::array<double, 2> position{};  ///< on the outline plane
  std::vector<Neighbour> neighbours; ///< nearest outline designs, nearest first
  Image preview;                     ///< neural render at the view (premultiplied RGBA)
  /// The design against the picture, both framed on their content (framedPSNR): how close the
  /// query's design looks to the picture without knowing its camera (dB). Nor is the picture's
  /// lighting known: the better of the design rendered unlit and lit (the view's coefficients
  /// when its Shade is on, ParaView's defaults otherwise), the preview being the one at the view.
  double picturePSNR = 0;
  bool pictureLit = false; ///< whether the figure is of the lit render
  /// Empty, or why the design is a guess: the picture cannot be read as a rendered volume (its
  /// border has no one colour: a photograph, or the object cut by the frame; checkQueryPicture).
  std::string warning;
};

/// How often a query finds the design it shows (the retrieval check of the gallery).
struct QueryRecall
{
  int count = 0, k = 0;
  double ownImage = 0;  ///< fraction found querying the design's own image (V_exp)
  double otherView = 0; ///< ... querying its ground truth at V_view over the same background
};

/// For each of the first `count` exemplars of a held-out dataset: its latent from its V_exp
/// image (as buildOutlineLatents makes them) joins `outline`; then the exemplar is queried
/// through prepareQueryImage and the analyzer, with its own image and with the other view (each
/// upsampled to 3x the model's size first, as a larger screenshot), and
/// counts as found when its row is among the k nearest of the joined set (by `key`, as the
/// gallery's query finds them, when it is not empty). Throws ddg::Error for
/// count < 1, k < 1, or data whose image size or volume is not the model's.
QueryRecall queryRecall(const NeuralDesignModel& model, const LatentSet& outline,
  const ExemplarDataset& heldout, int count, int k = 5, const QueryKey& key = {});

/// The query key of a model fitted on up to `maxPairs` exemplars of `data`: each exemplar's
/// V_exp image analysed as the outline's designs are, and its ground truth at V_view over the
/// same background framed and analysed as a query is (prepareQueryImage of it upsampled 3x, as
/// queryRecall's other view); pictures in which nothing shows are passed over. The contrastive
/// key (fitContrastiveQueryKey) from kContrastiveKeyPairs usable pairs, the linear one
/// (fitQueryKey) below. Returns an empty key when fewer than 2 x latent pairs are usable (a
/// model's key needs more designs than it has values). `progress(fraction)` returning false
/// cancels (ddg::Cancelled).
QueryKey queryKeyFromExemplars(const NeuralDesignModel& model, const ExemplarDataset& data,
  int maxPairs = kQueryKeyPairs, int threads = 0, const std::function<bool(double)>& progress = {});

/// Regions whose primitives stay fixed while the rest changes (feature lock): `primitives` holds
/// one primitive per feature region of the model (from the design they were locked on, opacity
/// 0 = the region is off), `locked` which of them are kept.
struct FeatureLock
{
  std::vector<GaussianPrimitive> primitives;
  std::vector<bool> locked;
  bool any() const;
};

/// How far a design's neural image is from what ParaView will show with its explicit TF.
struct Fidelity
{
  double psnr = 0, ssim = 0;
  double maxError = 0; ///< largest per-pixel error (max over RGB, 0..1)
  Image neural, real;  ///< both over the view's background (RGB)
  Image heat;          ///< per-pixel error, black (0) -> red -> yellow -> white (>= 0.25)
};

/// Frames of an animation between two designs.
struct Animation
{
  std::vector<Latent> latents; ///< per frame (eased path)
  std::vector<Image> neural;   ///< the model's render per frame (RGB over the background)
  std::vector<Image> real;     ///< ray casts of the interpolated explicit TFs (RGB)
  std::vector<int> keyframes;  ///< frames whose TF was made explicit
};

/// A model with its outline. Renders are premultiplied RGBA at a view's size: for the decoder
/// model the ray cast of the decoded TF, for the U-Net model its render of the viewport image
/// (the auxiliary TF ray cast at the view) resized to the view.
class DesignGallery
{
public:
  /// `model` must outlive the gallery; a decoder model gets `volume` attached. Throws
  /// ddg::Error when the latents' size differs from the model's latent or the volume is not
  /// the model's (fingerprint).
  DesignGallery(NeuralDesignModel& model, const Volume& volume, LatentSet latents);
  /// The same over a volume given by what it can do (DesignVolume; a volume split over ranks):
  /// the fingerprint is the caller's to check (NeuralDesignModel::loadBundle). Exemplars, a
  /// U-Net's TFs and what needs `volume()` or `caster()` need the volume in this process.
  DesignGallery(
    NeuralDesignModel& model, std::shared_ptr<const DesignVolume> volume, LatentSet latents);

  const DesignOutline& outline() const { return Outline; }
  /// A query's nearest designs by this key from now on (DesignOutline::setQueryKey).
  void setQueryKey(QueryKey key) { Outline.setQueryKey(std::move(key)); }
  NeuralDesignModel& model() { return Model; }
  /// The volume and its ray caster (one, shared by every render of the gallery): throw
  /// ddg::Error when the volume is not in this process.
  const Volume& volume() const;
  const RayCaster& caster() const;
  /// What the gallery renders with: the volume in this process, or split over ranks.
  const DesignVolume& space() const { return *Space; }

  std::vector<float> latent(int row) const;
  /// The design a row came from, regenerated from (seed, index): its TF and views.
  Exemplar exemplar(int row) const;

  /// Neural render of a latent at `view`.
  Image render(const std::vector<float>& latent, const View& view) const;
  /// render() at `view` and at `other`, which differs from it in its lighting: one march for
  /// both when the model decodes a TF (DesignVolume::renderLitAndUnlit); the query's figure.
  std::array<Image, 2> renderBothLightings(
    const std::vector<float>& latent, const View& view, const View& other) const;
  /// Thumbnail of a row at `view`, cached by row for the last view asked (a thumbnail at another
  /// view empties the cache: it holds at most one view's thumbnails, never one per camera).
  const Image& thumbnail(int row, const View& view);

  /// The analyzer's latent of any image, read (queryPicture) and framed (prepareQueryImage) as a
  /// query's.
  std::vector<float> analyzeImage(const Image& image) const;

  /// Analyzer -> latent -> place on the outline, nearest designs and a preview at `view`. The
  /// picture is read as queryPicture reads it: inside a letterbox, at the render view of a
  /// window's screenshot, halved while over kQueryPictureSide.
  /// Throws ddg::Error for an unusable image (prepareQueryImage) or a picture of lines or text
  /// (a chart: checkQueryPicture); a picture that cannot be read as a rendered volume (a
  /// photograph) is answered with a warning.
  QueryResult query(const Image& image, const View& view, int neighbours = 5) const;
  /// Designs against a picture as the query judges its own (QueryResult::picturePSNR): each
  /// latent rendered at `view` and in the other lighting, both framed on their content, the
  /// better figure (dB); `lit`, when given, says for each whether that is the lit render.
  std::vector<double> picturePSNR(const Image& picture,
    const std::vector<std::vector<float>>& latents, const View& view,
    std::vector<bool>* lit = nullptr) const;

  /// The explicit TF of a latent as Gaussian primitives: the decoder's output. (The U-Net
  /// model has none: throws ddg::Error; reconstruct from its render instead.)
  std::vector<GaussianPrimitive> primitives(const std::vector<float>& latent) const;

  /// The TF of a latent per feature region (opacity after the activity; none left out), with
  /// the lock's regions replaced. Decoder models only.
  std::vector<GaussianPrimitive> regionPrimitives(
    const std::vector<float>& latent, const FeatureLock* lock = nullptr) const;
  /// A lock on `regions` (indices of feature regions) of a latent's design.
  FeatureLock lockRegions(const std::vector<float>& latent, const std::vector<int>& regions) const;
  /// Ray cast of explicit primitives at `view` as the designs are rendered (premultiplied RGBA).
  Image renderPrimitives(const std::vector<GaussianPrimitive>& primitives, const View& view) const;
  /// Neural render of a latent under a lock: decoder models ray cast regionPrimitives (locked
  /// regions fixed); without a lock (or for the U-Net) the same as render().
  Image render(const std::vector<float>& latent, const View& view, const FeatureLock* lock) const;

  /// Re-analyzes an edited design image (premultiplied RGBA, e.g. from recolour()) composed over
  /// `background` (black or white, as the analyzer was trained): its latent.
  std::vector<float> analyzeEdit(const Image& rgba, const std::array<double, 3>& background) const;

  /// The design's explicit TF in ParaView's form (ParaView preset for 1D, DDG 2D JSON): the
  /// decoder's output (regionPrimitives under the lock) or, for the U-Net, a TF reconstructed
  /// from its render at `view`.
  TransferFunctionFile explicitTransferFunction(
    const std::vector<float>& latent, const View& view, const FeatureLock* lock = nullptr) const;

  /// Fidelity of a design at `view`: its neural image against the ray cast of its explicit TF
  /// as ParaView builds the table from the exported file (RayCaster::paraviewTable).
  Fidelity fidelity(
    const std::vector<float>& latent, const View& view, const FeatureLock* lock = nullptr) const;

  /// Animation from a to b: `frames` latents on an eased path; neural frames; explicit TFs at
  /// every `keyEvery`-th frame and the last, tables linearly interpolated between keyframes,
  /// so the real frames are ray casts. Throws ddg::Error for frames < 2 or keyEvery < 1.
  Animation animate(const std::vector<float>& a, const std::vector<float>& b, const View& view,
    int frames, const std::string& easing = "smoothstep", int keyEvery = 5,
    const FeatureLock* lock = nullptr) const;

  /// The outline sheet: every latent in the state's current box as a grey dot, and the state's
  /// K thumbnails (selectThumbnails with its seed) rendered at `view` and centred on their
  /// points (clamped inside), on a side x side white canvas (RGB). `view`'s size is the
  /// thumbnail size.
  /// With a feature lock the thumbnails show the locked regions fixed (rendered, not cached).
  Image sheet(const OutlineViewState& state, const View& view, int side = 1024,
    const FeatureLock* lock = nullptr);

private:
  // picturePSNR, and with `atView` the renders at `view` (the query's preview among them)
  std::vector<double> againstPicture(const Image& picture,
    const std::vector<std::vector<float>>& latents, const View& view, std::vector<bool>* lit,
    std::vector<Image>* atView) const;
  NeuralDesignModel& Model;
  const Volume* Vol = nullptr; // the volume in this process, else null
  std::shared_ptr<const DesignVolume> Space;
  DesignOutline Outline;
  std::array<double, 2> gradientAxis() const; // the 2D tables' gradient range ([0, 1] for 1D)
  Image renderTable(const std::vector<GaussianPrimitive>& tf, const View& view) const;
  DesignTable tableOf(
    const std::vector<GaussianPrimitive>& tf) const; // the table renderTable casts
  mutable Image Viewport; ///< U-Net only: the auxiliary TF at the last view (model size)
  mutable std::string ViewportKey;
  std::map<int, Image> Cache; ///< thumbnails by row, at CacheView
  std::string CacheView;
  const Image& viewport(const View& view) const;
};

} // namespace ddg
