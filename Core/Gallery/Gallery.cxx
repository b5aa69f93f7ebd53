// Gallery.cxx: outline latents, query images, thumbnails and the outline sheet.
#include "Gallery/Gallery.h"

#include "Common/Error.h"
#include "Common/Parallel.h"
#include "Design/DecoderLayout.h"
#include "Design/DesignCheck.h"
#include "Design/DesignSpace.h"
#include "Gallery/Export.h"
#include "Image/ImageMetrics.h"
#include "Reconstruct/CarryLook.h"
#include "Reconstruct/Reconstruction.h"
#include "TransferFunction/TransferFunction2D.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>

namespace ddg
{

// ---- outline latents ----------------------------------------------------------------------

LatentSet buildOutlineLatents(const NeuralDesignModel& model, const Volume& volume, int count,
  std::uint64_t seed, std::uint64_t firstIndex, int threads,
  const std::function<bool(double)>& progress, bool screen, ExemplarWorkers* workers)
{
  if (count < 3)
    throw Error("an outline needs at least 3 designs (got " + std::to_string(count) + ")");
  const auto& spec = model.spec();
  const auto& regions = model.regions();
  if (regions.empty())
    throw Error("the model has no feature regions (load it from a bundle)");
  const int s = model.config().imageSize;
  CandidateRenderer renderer(volume, spec, s, seed, false);
  renderer.setRegions(regions);
  renderer.setUpWorkers(workers);
  LatentSet set;
  set.dim = model.config().latent;
  set.seed = seed;
  set.values.resize(static_cast<size_t>(count) * set.dim);
  // screened: candidates up to 4 x count, then the rest as drawn (as generateExemplars does)
  const std::int64_t maxCandidates = 4LL * count;
  std::int64_t examined = 0;
  std::uint64_t next = firstIndex;
  double shown = 0; // the fraction reported
  const int chunk = 512;
  while (set.count() < count)
  {
    const bool screening = screen && examined < maxCandidates;
    const int n = std::min(chunk, count - set.count());
    std::vector<Image> images(n);
    // rendered in slices of 64 (shared with the workers) with a progress call after each (cancel
    // within ~0.5 s on large volumes); analysed 512 at a time; junk is left as an empty image
    for (int part = 0; part < n; part += 64)
    {
      renderer.outline(
        next + part, std::min(64, n - part), screening, workers, threads, images.data() + part);
      // (monotonic: designs passed over make a batch add less than it rendered)
      shown = std::max(
        shown, std::min(1.0, (set.count() + 0.95 * (part + std::min(64, n - part))) / count));
      if (progress && !progress(shown))
        throw Cancelled();
    }
    std::vector<Image> kept;
    for (int q = 0; q < n; ++q)
    {
      examined += screening;
      if (!images[q].pixels.empty())
      {
        kept.push_back(std::move(images[q]));
        set.indices.push_back(next + q);
      }
    }
    next += n;
    if (!kept.empty())
    {
      const auto z = model.analyzeBatch(kept);
      std::copy(z.begin(), z.end(),
        set.values.begin() + static_cast<size_t>(set.count() - kept.size()) * set.dim);
    }
    shown = std::max(shown, static_cast<double>(set.count()) / count);
    if (progress && !progress(shown))
      throw Cancelled();
  }
  return set;
}

LatentSet outlineFromExemplars(const NeuralDesignModel& model, const Volume& volume,
  const ExemplarDataset& training, int count, std::uint64_t seed, int threads,
  const std::function<bool(double)>& progress, bool screen, ExemplarWorkers* workers)
{
  const int reused = std::min(count, training.count());
  if (training.spec().pictureFraction > 0 || reused < 3)
    return buildOutlineLatents(model, volume, count, seed, 0, threads, progress, screen, workers);
  if (model.config().imageSize != training.size())
    throw Error("the exemplars' images are " + std::to_string(training.size()) +
      " pixels, the model's " + std::to_string(model.config().imageSize));
  const double share = static_cast<double>(reused) / count; // of the progress
  LatentSet set;
  set.dim = model.config().latent;
  set.seed = seed;
  const int chunk = 512;
  for (int first = 0; first < reused; first += chunk)
  {
    std::vector<Image> images;
    for (int i = first; i < std::min(reused, first + chunk); ++i)
    {
      images.push_back(training.images(i).rgbExp);
      set.indices.push_back(exemplarIndex(training.exemplars()[static_cast<size_t>(i)], seed));
    }
    const auto z = model.analyzeBatch(images);
    set.values.insert(set.values.end(), z.begin(), z.end());
    if (progress && !progress(share * set.count() / reused))
      throw Cancelled();
  }
  if (count > reused)
  {
    const LatentSet rest = buildOutlineLatents(
      model, volume, count - reused, seed, set.indices.back() + 1, threads,
      [&](double f) { return !progress || progress(share + (1 - share) * f); }, screen, workers);
    set.values.insert(set.values.end(), rest.values.begin(), rest.values.end());
    set.indices.insert(set.indices.end(), rest.indices.begin(), rest.indices.end());
  }
  return set;
}

std::string outlineFile(const std::string& bundleDir)
{
  return (std::filesystem::path(bundleDir) / "outline.bin").string();
}

QueryRecall queryRecall(const NeuralDesignModel& model, const LatentSet& outline,
  const ExemplarDataset& heldout, int count, int k, const QueryKey& key)
{
  if (count < 1 || k < 1)
    throw Error("query recall needs count >= 1 and k >= 1");
  const int s = model.config().imageSize;
  if (heldout.size() != s)
    throw Error("the held-out images are " + std::to_string(heldout.size()) +
      " pixels, the model's " + std::to_string(s));
  if (outline.dim != model.config().latent)
    throw Error("the outline's latents come from another model");
  count = std::min(count, heldout.count());
  std::vector<Image> own(count), other(count);
  for (int i = 0; i < count; ++i)
  {
    const auto im = heldout.images(i);
    own[i] = im.rgbExp;
    other[i] = compositeOverBackground(im.truth, heldout.exemplars()[i].viewExp.background);
  }
  LatentSet joined = outline;
  const auto z = model.analyzeBatch(own);
  joined.values.insert(joined.values.end(), z.begin(), z.end());
  for (int i = 0; i < count; ++i)
    joined.indices.push_back(heldout.exemplars()[i].seed);
  DesignOutline searched(std::move(joined)); // nearest rows as the gallery's query finds them
  searched.setQueryKey(key);
  auto recall = [&](const std::vector<Image>& images)
  {
    // queried as a screenshot three times the model's size would be: upsampled, then framed
    // and resized back by the query pipeline
    std::vector<Image> prepared;
    for (const auto& im : images)
      prepared.push_back(prepareQueryImage(resizeImage(im, 3 * s, 3 * s), s));
    const auto q = model.analyzeBatch(prepared);
    int hits = 0;
    for (int i = 0; i < count; ++i)
    {
      const auto nn = searched.nearest(q.data() + static_cast<size_t>(i) * outline.dim, k);
      const int want = outline.count() + i;
      hits += std::any_of(nn.begin(), nn.end(), [&](const Neighbour& n) { return n.row == want; });
    }
    return static_cast<double>(hits) / count;
  };
  QueryRecall r;
  r.count = count;
  r.k = k;
  r.ownImage = recall(own);
  r.otherView = recall(other);
  return r;
}

QueryKey queryKeyFromExemplars(const NeuralDesignModel& model, const ExemplarDataset& data,
  int maxPairs, int threads, const std::function<bool(double)>& progress)
{
  const int s = model.config().imageSize, dim = model.config().latent;
  if (data.size() != s)
    throw Error("the exemplars' images are " + std::to_string(data.size()) +
      " pixels, the model's " + std::to_string(s));
  const int n = std::max(0, std::min(maxPairs, data.count()));
  // the share of the progress before the contrastive fit (on 2 cores ~11 ms a pair framed and
  // analysed, ~4 ms fitted)
  constexpr double kFramed = 0.7;
  // the other view framed as a query (the costly part: ~9 ms an image), on every thread
  std::vector<Image> own(static_cast<size_t>(n)), other(static_cast<size_t>(n));
  std::vector<char> usable(static_cast<size_t>(n), 0);
  std::atomic<int> done{ 0 };
  parallelFor(n, threads,
    [&](std::int64_t i64, int thread)
    {
      const auto i = static_cast<size_t>(i64);
      if (thread == 0 && progress && !progress(kFramed * done.load() / std::max(1, n)))
        throw Cancelled();
      const auto im = data.images(static_cast<int>(i));
      const Image view = compositeOverBackground(im.truth, data.exemplars()[i].viewExp.background);
      try
      {
        other[i] = prepareQueryImage(resizeImage(view, 3 * s, 3 * s), s);
        own[i] = im.rgbExp;
        usable[i] = 1;
      }
      catch (const Error&) // nothing shows from the other view: a query would be refused
      {
      }
      ++done;
    });
  std::vector<Image> ownKept, otherKept;
  for (size_t i = 0; i < usable.size(); ++i)
    if (usable[i])
    {
      ownKept.push_back(std::move(own[i]));
      otherKept.push_back(std::move(other[i]));
    }
  if (static_cast<int>(ownKept.size()) < 2 * dim)
    return {};
  const auto zOwn = model.analyzeBatch(ownKept), zOther = model.analyzeBatch(otherKept);
  if (static_cast<int>(ownKept.size()) < kContrastiveKeyPairs)
  {
    const QueryKey key = fitQueryKey(zOwn, zOther, dim, kQueryKeyComponents);
    if (progress && !progress(1.0))
      throw Cancelled();
    return key;
  }
  return fitContrastiveQueryKey(zOwn, zOther, dim, {},
    [&](double f) { return !progress || progress(kFramed + (1 - kFramed) * f); });
}

// ---- the gallery --------------------------------------------------------------------------

DesignGallery::DesignGallery(NeuralDesignModel& model, const Volume& volume, LatentSet latents)
  : DesignGallery(model, std::make_shared<LocalDesignVolume>(volume), std::move(latents))
{
  Vol = &volume;
  if (model.config().kind == "decoder")
    model.attachVolume(volume); // checks the fingerprint
}

DesignGallery::DesignGallery(
  NeuralDesignModel& model, std::shared_ptr<const DesignVolume> volume, LatentSet latents)
  : Model(model)
  , Space(std::move(volume))
  , Outline(std::move(latents))
{
  if (Outline.latents().dim != model.config().latent)
    throw Error("the outline's latents have " + std::to_string(Outline.latents().dim) +
      " values, the model's " + std::to_string(model.config().latent) +
      ": they come from another model");
}

const Volume& DesignGallery::volume() const
{
  if (!Vol)
    throw Error("this needs the whole volume in one process, and it is split over ranks");
  return *Vol;
}

const RayCaster& DesignGallery::caster() const
{
  volume();
  return *Space->caster();
}

std::array<double, 2> DesignGallery::gradientAxis() const
{
  return Model.spec().dimensions == 2 ? Space->gradientRange() : std::array<double, 2>{ 0.0, 1.0 };
}

// renderDesign's ray cast of a TF of primitives (none: an empty image), through the volume
Image DesignGallery::renderTable(const std::vector<GaussianPrimitive>& tf, const View& view) const
{
  if (tf.empty())
    return Image(view.width, view.height, 4, 0.0f);
  return Space->render(tableOf(tf), view);
}

DesignTable DesignGallery::tableOf(const std::vector<GaussianPrimitive>& tf) const
{
  return designTable(tf, Model.spec().dimensions, Space->range(), gradientAxis());
}

std::array<Image, 2> DesignGallery::renderBothLightings(
  const std::vector<float>& latent, const View& view, const View& other) const
{
  if (Model.config().kind != "decoder" || view.lighting.shade == other.lighting.shade)
    return { render(latent, view), render(latent, other) };
  const std::vector<GaussianPrimitive> tf = Model.decode(latent);
  if (tf.empty())
    return { renderTable(tf, view), renderTable(tf, other) };
  // the unlit image does not depend on the lighting's coefficients: the lit view's march gives
  // both (the unlit view checked as its own render would check it)
  const bool viewLit = view.lighting.shade;
  (viewLit ? other : view).validate();
  std::array<Image, 2> both = Space->renderLitAndUnlit(tableOf(tf), viewLit ? view : other);
  if (!viewLit)
    std::swap(both[0], both[1]);
  return both;
}

std::vector<float> DesignGallery::latent(int row) const
{
  if (row < 0 || row >= Outline.count())
    throw Error("design " + std::to_string(row) + " is not in the outline (0.." +
      std::to_string(Outline.count() - 1) + ")");
  const float* z = Outline.latents().row(row);
  return std::vector<float>(z, z + Outline.latents().dim);
}

Exemplar DesignGallery::exemplar(int row) const
{
  latent(row); // range check
  return sampleExemplar(volume(), Model.spec(), Model.regions(), Outline.latents().seed,
    Outline.latents().indices[row], Model.config().imageSize);
}

const Image& DesignGallery::viewport(const View& view) const
{
  const std::string key = viewToJson(view);
  if (Viewport.empty() || key != ViewportKey)
  {
    View v = view;
    v.width = v.height = Model.config().imageSize;
    Viewport = renderTable(auxiliaryPrimitives(Model.spec(), Model.regions()), v);
    ViewportKey = key;
  }
  return Viewport;
}

Image DesignGallery::render(const std::vector<float>& latent, const View& view) const
{
  if (Model.config().kind == "decoder") // NeuralDesignModel::renderAt's ray cast, here
    return renderTable(Model.decode(latent), view);
  return Model.renderAt(latent, viewport(view), view);
}

const Image& DesignGallery::thumbnail(int row, const View& view)
{
  const std::string key = viewToJson(view);
  if (key != CacheView) // the cache holds one view's thumbnails: a new camera starts it anew
  {
    Cache.clear();
    CacheView = key;
  }
  auto it = Cache.find(row);
  if (it == Cache.end())
    it = Cache.emplace(row, render(latent(row), view)).first;
  return it->second;
}

std::vector<float> DesignGallery::analyzeImage(const Image& image) const
{
  Image held;
  return Model.analyze(prepareQueryImage(queryPicture(image, held), Model.config().imageSize));
}

QueryResult DesignGallery::query(const Image& picture, const View& view, int neighbours) const
{
  if (neighbours < 0)
    throw Error("the neighbour count must be >= 0");
  Image held;
  const Image& image = queryPicture(picture, held);
  QueryResult r;
  r.input = prepareQueryImage(image, Model.config().imageSize);
  // a chart is refused; a picture that cannot be read as a rendered volume gets a warning
  const Image colour = image.channels >= 3 ? Image() : inColour(image);
  r.warning = checkQueryPicture(image.channels >= 3 ? image : colour);
  r.latent = Model.analyze(r.input);
  r.position = Outline.project(r.latent.data());
  r.neighbours = Outline.nearest(r.latent.data(), neighbours);
  std::vector<bool> lit;
  std::vector<Image> atView;
  r.picturePSNR = againstPicture(image, { r.latent }, view, &lit, &atView).front();
  r.pictureLit = lit.front();
  r.preview = std::move(atView.front());
  return r;
}

std::vector<double> DesignGallery::picturePSNR(const Image& picture,
  const std::vector<std::vector<float>>& latents, const View& view, std::vector<bool>* lit) const
{
  Image held;
  return againstPicture(queryPicture(picture, held), latents, view, lit, nullptr);
}

std::vector<double> DesignGallery::againstPicture(const Image& picture,
  const std::vector<std::vector<float>>& latents, const View& view, std::vector<bool>* lit,
  std::vector<Image>* atView) const
{
  // a lit scene's render against an unlit picture (or the other way) would score the lighting,
  // not the design: the other lighting is rendered too and the better figure kept
  View other = view;
  other.lighting = Lighting{}; // ParaView's coefficients
  other.lighting.shade = !view.lighting.shade;
  std::vector<double> best(latents.size());
  if (lit)
    lit->assign(latents.size(), false);
  if (atView)
    atView->clear();
  // the picture framed once per chunk of designs (framing a large picture costs more than a
  // design's two renders), at most 2 x kChunk renders held at a time, whatever the count
  constexpr size_t kChunk = 8;
  for (size_t first = 0; first < latents.size(); first += kChunk)
  {
    const size_t end = std::min(latents.size(), first + kChunk);
    std::vector<Image> renders;
    for (size_t i = first; i < end; ++i)
    {
      std::array<Image, 2> both = renderBothLightings(latents[i], view, other);
      renders.push_back(std::move(both[0]));
      renders.push_back(std::move(both[1]));
    }
    std::vector<const Image*> shown;
    for (const Image& image : renders)
      shown.push_back(&image);
    const std::vector<double> figures = framedPSNR(picture, shown);
    for (size_t i = first; i < end; ++i)
    {
      const double here = figures[2 * (i - first)], there = figures[2 * (i - first) + 1];
      best[i] = std::max(here, there);
      if (lit)
        (*lit)[i] = there > here ? other.lighting.shade : view.lighting.shade;
      if (atView)
        atView->push_back(std::move(renders[2 * (i - first)]));
    }
  }
  return best;
}

std::vector<GaussianPrimitive> DesignGallery::primitives(const std::vector<float>& latent) const
{
  if (Model.config().kind != "decoder")
    throw Error("the U-Net model has no explicit TF: reconstruct one from its render");
  return Model.decode(latent);
}

// ---- lock, edits, explicit TFs, fidelity, animation ---------------------------------------

bool FeatureLock::any() const
{
  return std::find(locked.begin(), locked.end(), true) != locked.end();
}

std::vector<GaussianPrimitive> DesignGallery::regionPrimitives(
  const std::vector<float>& latent, const FeatureLock* lock) const
{
  auto prims = Model.decodeRegions(latent);
  if (lock)
  {
    if (lock->primitives.size() != prims.size() || lock->locked.size() != prims.size())
      throw Error("the feature lock holds " + std::to_string(lock->locked.size()) +
        " regions, the model " + std::to_string(prims.size()));
    for (size_t r = 0; r < prims.size(); ++r)
      if (lock->locked[r])
        prims[r] = lock->primitives[r];
  }
  return prims;
}

FeatureLock DesignGallery::lockRegions(
  const std::vector<float>& latent, const std::vector<int>& regions) const
{
  FeatureLock lock;
  lock.primitives = Model.decodeRegions(latent);
  lock.locked.assign(lock.primitives.size(), false);
  for (int r : regions)
  {
    if (r < 0 || r >= static_cast<int>(lock.primitives.size()))
      throw Error("feature region " + std::to_string(r) + " does not exist (0.." +
        std::to_string(lock.primitives.size() - 1) + ")");
    lock.locked[r] = true;
  }
  return lock;
}

Image DesignGallery::renderPrimitives(
  const std::vector<GaussianPrimitive>& primitives, const View& view) const
{
  std::vector<GaussianPrimitive> visible;
  for (const auto& g : primitives)
    if (g.opacity >= DecoderLayout::kMinOpacity)
      visible.push_back(g);
  return renderTable(visible, view);
}

Image DesignGallery::render(
  const std::vector<float>& latent, const View& view, const FeatureLock* lock) const
{
  if (!lock || !lock->any() || Model.config().kind != "decoder")
    return render(latent, view);
  return renderPrimitives(regionPrimitives(latent, lock), view);
}

std::vector<float> DesignGallery::analyzeEdit(
  const Image& rgba, const std::array<double, 3>& background) const
{
  if (rgba.channels != 4)
    throw Error("an edited design image is premultiplied RGBA");
  return analyzeImage(compositeOverBackground(rgba, background));
}

TransferFunctionFile DesignGallery::explicitTransferFunction(
  const std::vector<float>& latent, const View& view, const FeatureLock* lock) const
{
  const int dims = Model.spec().dimensions;
  const auto valueRange = Space->range();
  const auto gradientRange = gradientAxis();
  if (Model.config().kind == "decoder")
  {
    std::vector<GaussianPrimitive> visible;
    for (const auto& g : regionPrimitives(latent, lock))
      if (g.opacity >= DecoderLayout::kMinOpacity)
        visible.push_back(g);
    return primitivesToTransferFunction(visible, dims, valueRange, gradientRange, "ddg design");
  }
  // the U-Net's image has no TF: reconstruct one from it at this view
  if (!Space->caster())
    throw Error("a U-Net bundle's transfer function is reconstructed from its image over the "
                "whole volume in one process, and here the volume is split over the MPI ranks: "
                "use a decoder bundle (ddg build, ddg train and the panel's Build... make them)");
  const DifferentiableRenderer diff(volume());
  ReconstructionOptions opt;
  opt.twoD = dims == 2;
  ReconstructionTarget target;
  target.image = compositeOverBackground(render(latent, view), view.background);
  target.view = view;
  return resultTransferFunction(reconstructTransferFunction(diff, { target }, opt), "ddg design");
}

namespace
{
Image heatMap(const Image& a, const Image& b, double* maxError)
{
  Image heat(a.width, a.height, 3);
  *maxError = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
    {
      double e = 0;
      for (int c = 0; c < 3; ++c)
        e = std::max(e, static_cast<double>(std::abs(a.at(x, y, c) - b.at(x, y, c))));
      *maxError = std::max(*maxError, e);
      const double t = std::min(1.0, e / 0.25) * 3; // black -> red -> yellow -> white
      heat.at(x, y, 0) = static_cast<float>(std::min(1.0, t));
      heat.at(x, y, 1) = static_cast<float>(std::clamp(t - 1, 0.0, 1.0));
      heat.at(x, y, 2) = static_cast<float>(std::clamp(t - 2, 0.0, 1.0));
    }
  return heat;
}
} // namespace

Fidelity DesignGallery::fidelity(
  const std::vector<float>& latent, const View& view, const FeatureLock* lock) const
{
  Fidelity f;
  f.neural = compositeOverBackground(render(latent, view, lock), view.background);
  const auto tf = explicitTransferFunction(latent, view, lock);
  const Image real = Space->render(transferTable(tf, Space->range()), view);
  f.real = compositeOverBackground(real, view.background);
  f.psnr = psnr(f.neural, f.real);
  f.ssim = ssim(f.neural, f.real);
  f.heat = heatMap(f.neural, f.real, &f.maxError);
  return f;
}

Animation DesignGallery::animate(const std::vector<float>& a, const std::vector<float>& b,
  const View& view, int frames, const std::string& easing, int keyEvery,
  const FeatureLock* lock) const
{
  if (keyEvery < 1)
    throw Error("keyframes must be at least 1 frame apart");
  Animation anim;
  anim.latents = latentPath(a, b, frames, easing);
  for (int f = 0; f < frames; f += keyEvery)
    anim.keyframes.push_back(f);
  if (anim.keyframes.back() != frames - 1)
    anim.keyframes.push_back(frames - 1);
  // explicit TFs at the keyframes, as dense tables (1D: ParaView's table of the exported preset)
  std::vector<TransferTable1D> t1;
  std::vector<TransferTable2D> t2;
  bool twoD = false;
  for (int k : anim.keyframes)
  {
    const auto tf = explicitTransferFunction(anim.latents[k], view, lock);
    twoD = tf.is2D;
    if (twoD)
      t2.push_back(tf.tf2D.bake());
    else
      t1.push_back(bakeTable(tf.tf1D, Space->range()[0], Space->range()[1], 1024));
  }
  for (int f = 0; f < frames; ++f)
  {
    anim.neural.push_back(
      compositeOverBackground(render(anim.latents[f], view, lock), view.background));
    size_t k = 0;
    while (k + 1 < anim.keyframes.size() && anim.keyframes[k + 1] <= f)
      ++k;
    const size_t k1 = std::min(k + 1, anim.keyframes.size() - 1);
    const double span = anim.keyframes[k1] - anim.keyframes[k];
    const double t = span > 0 ? (f - anim.keyframes[k]) / span : 0.0;
    auto mix = [t](const std::vector<float>& p, const std::vector<float>& q)
    {
      std::vector<float> m(p.size());
      for (size_t i = 0; i < p.size(); ++i)
        m[i] = static_cast<float>((1 - t) * p[i] + t * q[i]);
      return m;
    };
    Image real;
    if (twoD)
    {
      DesignTable table;
      table.dimensions = 2;
      table.twoD = t2[k];
      table.twoD.rgba = mix(t2[k].rgba, t2[k1].rgba);
      real = Space->render(table, view);
    }
    else
    {
      DesignTable table;
      table.oneD = t1[k];
      table.oneD.rgba = mix(t1[k].rgba, t1[k1].rgba);
      real = Space->render(table, view);
    }
    anim.real.push_back(compositeOverBackground(real, view.background));
  }
  return anim;
}

Image DesignGallery::sheet(
  const OutlineViewState& state, const View& view, int side, const FeatureLock* lock)
{
  if (side < 64 || side > 8192)
    throw Error("the sheet side must be in [64, 8192]");
  const OutlineBox& box = state.current();
  const auto rows = selectThumbnails(Outline, box, state.count, state.seed);
  Image canvas(side, side, 3, 1.0f);
  auto toPixel = [&](std::array<double, 2> p)
  {
    return std::array<double, 2>{ (p[0] - box.x0) / (box.x1 - box.x0) * (side - 1),
      (box.y1 - p[1]) / (box.y1 - box.y0) * (side - 1) };
  };
  for (int i : Outline.inside(box))
  {
    const auto q = toPixel(Outline.point(i));
    const int x = static_cast<int>(q[0]), y = static_cast<int>(q[1]);
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        if (x + dx < side && y + dy < side)
          for (int c = 0; c < 3; ++c)
            canvas.at(x + dx, y + dy, c) = std::min(canvas.at(x + dx, y + dy, c), 0.72f);
  }
  for (int row : rows)
  {
    const Image thumb = compositeOverBackground(
      lock && lock->any() ? render(latent(row), view, lock) : thumbnail(row, view),
      { 0.12, 0.12, 0.12 });
    const auto q = toPixel(Outline.point(row));
    const int tw = thumb.width, th = thumb.height;
    const int x0 = std::clamp(static_cast<int>(q[0]) - tw / 2, 1, std::max(1, side - tw - 1));
    const int y0 = std::clamp(static_cast<int>(q[1]) - th / 2, 1, std::max(1, side - th - 1));
    for (int y = -1; y <= th; ++y)
      for (int x = -1; x <= tw; ++x)
      {
        const int px = x0 + x, py = y0 + y;
        if (px < 0 || py < 0 || px >= side || py >= side)
          continue;
        const bool frame = x < 0 || y < 0 || x >= tw || y >= th;
        for (int c = 0; c < 3; ++c)
          canvas.at(px, py, c) = frame ? 1.0f : thumb.at(x, y, c);
      }
  }
  return canvas;
}

} // namespace ddg
