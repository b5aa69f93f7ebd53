// Match.cxx: background, masks, the camera search (silhouettes, colours), then the reconstruction
// (Match.h).
#include "Reconstruct/Match.h"

#include "Reconstruct/MatchCamera.h"

#include "Common/Error.h"
#include "Common/Parallel.h"
#include "Render/RayCaster.h"
#include "Volume/Volume.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <sstream>
#include <tuple>

namespace ddg
{

namespace
{
using namespace matchparts;

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t)
{
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// The picture prepared for the match: RGB (alpha composited away) or RGBA, and its masks.
struct Picture
{
  Image rgb;                    // RGB in [0, 1] (working size)
  Image rgba;                   // RGBA straight, when the picture has transparency
  bool alpha = false;           // compare premultiplied RGBA (no background)
  Mask foreground;              // differs from the background
  std::vector<int> label, area; // connected parts of the foreground
};

} // namespace

MatchResult matchPictureLit(const DifferentiableRenderer& renderer, const Image& input,
  const MatchOptions& opt, const MatchProgress& progress, CameraSearchStages* stages)
{
  const auto t0 = Clock::now();
  auto report = [&](const std::string& stage, double fraction, const Image* preview)
  {
    if (progress && !progress(stage, fraction, preview))
      throw Cancelled();
  };
  if (input.empty() || input.width < 16 || input.height < 16)
  {
    std::ostringstream msg;
    msg << "the picture is " << input.width << " x " << input.height
        << " pixels: at least 16 x 16 are needed to match it";
    throw Error(msg.str());
  }
  if (input.channels != 3 && input.channels != 4)
  {
    throw Error("the picture has " + std::to_string(input.channels) +
      " channels: an RGB (or RGBA) picture is needed");
  }
  for (float v : input.pixels)
    if (!std::isfinite(v))
      throw Error("the picture holds NaN or infinite values");
  report("background", 0.0, nullptr);

  // the working picture: at most 1024 pixels a side (the fit samples rays; more is not better)
  MatchResult result;
  Picture pic;
  {
    // a letterbox's bands, and a window's panels around its render view, are not the picture's
    // background: matched inside them
    const Image inside = insideRenderedPart(input, result.crop);
    const int longest = std::max(inside.width, inside.height);
    Image work = inside;
    if (longest > 1024)
    {
      const double f = 1024.0 / longest;
      work = resizeImage(inside, std::max(16, static_cast<int>(std::lround(inside.width * f))),
        std::max(16, static_cast<int>(std::lround(inside.height * f))));
    }
    for (auto& v : work.pixels)
      v = std::clamp(v, 0.0f, 1.0f);
    bool transparent = false;
    if (work.channels == 4)
      for (size_t i = 3; i < work.pixels.size(); i += 4)
        transparent = transparent || work.pixels[i] < 254.5f / 255.0f;
    pic.alpha = transparent;
    if (transparent)
    {
      pic.rgba = work;
    }
    pic.rgb = Image(work.width, work.height, 3);
    for (size_t i = 0, n = static_cast<size_t>(work.width) * work.height; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        pic.rgb.pixels[3 * i + c] = work.pixels[i * work.channels + c];
  }
  const int W = pic.rgb.width, H = pic.rgb.height;

  // background and foreground
  View view = opt.view ? *opt.view : defaultView(renderer.bounds(), W, H);
  view.width = W;
  view.height = H;
  if (opt.lighting)
    view.lighting = *opt.lighting;
  if (opt.opacityUnitDistance)
    view.opacityUnitDistance = opt.opacityUnitDistance;
  pic.foreground = Mask(W, H);
  if (pic.alpha)
  {
    for (size_t i = 0; i < pic.foreground.m.size(); ++i)
      pic.foreground.m[i] = pic.rgba.pixels[4 * i + 3] > 1.5f / 255.0f;
  }
  else
  {
    if (opt.background)
    {
      result.background.bottom = result.background.top = *opt.background;
      result.background.noise = 0;
    }
    else
    {
      result.background = estimateBackground(pic.rgb);
    }
    result.background.applyTo(view);
    pic.foreground = foregroundOf(pic.rgb, view, result.background.noise);
  }
  pic.label = components(pic.foreground, pic.area);
  const long foregroundArea = std::accumulate(pic.area.begin(), pic.area.end(), 0L);
  if (foregroundArea < 16)
  {
    throw Error("the picture shows nothing but the background colour: there is nothing to match");
  }
  // overlay candidates: parts much smaller than the largest (axes, text, a scalar bar)
  std::vector<char> candidate(pic.area.size(), 0);
  if (opt.maskOverlays)
    candidate = smallParts(pic.area, 0.2);
  result.backgroundSeconds = secondsSince(t0);
  report("camera", 0.05, nullptr);

  // --- the camera -------------------------------------------------------------------------
  const auto tCamera = Clock::now();
  auto tLap = tCamera;
  auto lap = [&]
  {
    const double s = secondsSince(tLap);
    tLap = Clock::now();
    return s;
  };
  // a piece of a volume (ParaView's ranks): every piece runs the match in step, each rendering
  // its part of the whole's rays (collective renders: no renders side by side in threads)
  const bool pieces = renderer.exchange() != nullptr;
  // the search's lighting-free stages, from an earlier match of the picture (MatchLighting.cxx)
  const bool searched = stages && stages->model && !stages->finalists.empty();
  const std::shared_ptr<const SilhouetteModel> silhouettes =
    searched ? stages->model : std::make_shared<const SilhouetteModel>(renderer);
  const SilhouetteModel& model = *silhouettes;
  if (model.levels() == 0)
  {
    throw Error("the volume has no structure to match a picture with");
  }
  // search raster: ~128 pixels on the longest side
  const double sf = 128.0 / std::max(W, H);
  const int sw = std::max(8, static_cast<int>(std::lround(W * sf))),
            sh = std::max(8, static_cast<int>(std::lround(H * sf)));
  Mask targetFull(W, H), candidateFull(W, H);
  for (size_t i = 0; i < targetFull.m.size(); ++i)
  {
    const int l = pic.label[i];
    targetFull.m[i] = l >= 0 && !candidate[static_cast<size_t>(l)];
    candidateFull.m[i] = l >= 0 && candidate[static_cast<size_t>(l)];
  }
  // the object's silhouette: its foreground with the holes filled (background seen through a
  // semi-transparent object, or between structures), as the volume's silhouettes have none
  const Mask target = fillHoles(shrink(targetFull, sw, sh));
  Mask care = shrink(dilate(candidateFull, std::max(1, W / sw)), sw, sh);
  for (auto& v : care.m)
    v = !v;
  const Moments mt = moments(target, &care);
  View base = view;
  base.width = sw;
  base.height = sh;
  const View resetView = [&]
  {
    View r = defaultView(renderer.bounds(), sw, sh);
    r.background = base.background;
    r.background2 = base.background2;
    r.opacityUnitDistance = base.opacityUnitDistance;
    r.camera.viewAngle = base.camera.viewAngle;
    r.lighting = base.lighting;
    return r;
  }();
  // the search starts from ParaView's reset camera, or from the given view
  const View start = opt.view ? base : resetView;

  CameraParams best;
  std::vector<CameraParams> finalists;
  std::shared_ptr<const EmissionScreen> screen; // the colours' screening (stage 2b)
  Mask scratch;
  auto iouAt = [&](const CameraParams& p, Mask& buffer)
  {
    model.render(p.view(start), p.level, sw, sh, buffer);
    return maskIoU(target, care, buffer);
  };
  auto exactIoU = [&](const CameraParams& p) { return iouAt(p, scratch); };
  // p at the level whose silhouette overlaps the picture's object best, that overlap its score
  auto atBestLevel = [&](CameraParams p)
  {
    CameraParams best = p;
    best.score = -1;
    for (p.level = 0; p.level < model.levels(); ++p.level)
      if (const double iou = exactIoU(p); iou > best.score)
        best = p, best.score = iou;
    return best;
  };
  const int threads = opt.reconstruction.render.threads;
  const bool search = !opt.view || opt.refineGivenView;
  if (search && searched)
  {
    finalists = stages->finalists;
    screen = stages->screen;
  }
  else if (search)
  {
    // stage 1: directions x levels, each aligned in the image plane by moments
    std::vector<CameraParams> coarse;
    std::vector<std::pair<double, double>> directions;
    const double range = opt.view ? 30.0 : 180.0; // a given view: search near it
    for (double el = -60; el <= 60; el += 30)
      for (double az = -180; az < 180; az += 30)
        if (std::abs(az) <= range && std::abs(el) <= std::max(range, 60.0))
          directions.emplace_back(az, el);
    if (!opt.view)
    {
      directions.emplace_back(0, 89);
      directions.emplace_back(0, -89);
    }
    // per direction, its alignments to the picture (for the colours' screening below)
    std::vector<Aligned> aligned(directions.size());
    std::vector<std::vector<CameraParams>> coarseOf(directions.size());
    parallelFor(static_cast<std::int64_t>(directions.size()), threads,
      [&](std::int64_t d, int)
      {
        Mask rendered;
        for (int level = 0; level < model.levels(); ++level)
        {
          const auto [az, el] = directions[static_cast<size_t>(d)];
          CameraParams p;
          p.az = az;
          p.el = el;
          p.level = level;
          model.render(p.view(start), level, sw, sh, rendered);
          const Moments mr = moments(rendered);
          if (mr.area < 4)
            continue;
          const double scale = std::sqrt(mt.area / mr.area);
          for (double rho : alignmentTurns(mt, mr))
          {
            const double iou =
              similarityIoU(target, care, rendered, mr.cx, mr.cy, mt.cx, mt.cy, rho, scale);
            CameraParams q = p;
            // roll: a camera roll of +a turns the picture by -a in pixel coordinates (y down)
            q.roll = -rho * 180.0 / M_PI;
            q.logZoom = std::log(scale);
            // where the render's centroid lands after the roll and zoom about the centre, and
            // the pan that moves it onto the target's
            const double c = std::cos(rho), s = std::sin(rho);
            const double rx = mr.cx - 0.5 * sw, ry = mr.cy - 0.5 * sh;
            const double lx = 0.5 * sw + scale * (c * rx - s * ry),
                         ly = 0.5 * sh + scale * (s * rx + c * ry);
            q.panX = -(mt.cx - lx) / sh;
            q.panY = (mt.cy - ly) / sh;
            q.score = iou;
            coarseOf[static_cast<size_t>(d)].push_back(q);
            if (iou >= 0.5)
              aligned[static_cast<size_t>(d)].push_back(
                { { mr.cx, mr.cy, mt.cx, mt.cy, rho, scale }, q });
          }
        }
      });
    for (const auto& c : coarseOf)
      coarse.insert(coarse.end(), c.begin(), c.end());
    std::sort(coarse.begin(), coarse.end(),
      [](const CameraParams& a, const CameraParams& b) { return a.score > b.score; });
    report("camera", 0.15, nullptr);
    // stage 2: the best distinct ones refined on exact silhouettes
    std::vector<CameraParams> seeds;
    for (const auto& c : coarse)
    {
      bool distinct = true;
      for (const auto& s : seeds)
        distinct = distinct && orientationDistance(c.view(start), s.view(start)) > 20;
      if (distinct)
        seeds.push_back(c);
      if (seeds.size() >= 12)
        break;
    }
    finalists.resize(seeds.size());
    parallelFor(static_cast<std::int64_t>(seeds.size()), threads,
      [&](std::int64_t i, int)
      {
        Mask local;
        finalists[static_cast<size_t>(i)] = nelderMead(
          seeds[static_cast<size_t>(i)], [&](const CameraParams& p) { return iouAt(p, local); },
          160);
      });
    report("camera", 0.3, nullptr);
    result.cameraStages.silhouettes = lap();
    // stage 2b: the colours. Silhouettes cannot tell apart the directions of a roundish or
    // translucent object; the emission model (MatchCamera.h) ranks every alignment of stage 1
    // by how well its rays explain the picture's colours; the best distinct ones, refined on
    // it, join the finalists (and the short fits below when they explain the colours clearly
    // better than the silhouettes' cameras; see stage 3)
    if (opt.colourCandidates > 0)
    {
      const Image difference = pictureDifference(pic.alpha ? pic.rgba : pic.rgb, view, sw, sh);
      // one thread a ray cast: the directions, then the candidates, run side by side (pieces:
      // one after the other, each ray cast on every thread)
      RenderOptions how = opt.reconstruction.render;
      how.sampleDistance = 3.0 * renderer.defaultSampleDistance();
      how.threads = pieces ? threads : 1;
      screen = std::make_shared<const EmissionScreen>(renderer, how, difference, care);
      auto refined = screenByColours(
        *screen, start, directions, aligned, opt.colourCandidates, pieces ? 1 : threads);
      for (auto& r : refined)
      {
        Mask local;
        r.score = iouAt(r, local);
      }
      finalists.insert(finalists.end(), refined.begin(), refined.end());
      report("camera", 0.45, nullptr);
      result.cameraStages.colours = lap();
    }
    // the discs of the blocks make a silhouette a little larger than the volume's own (and the
    // search then moves the camera away): the distance corrected by the ratio of the sizes of
    // the block silhouette and a ray cast of the same level (opaque above its threshold)
    {
      RenderOptions coarse = opt.reconstruction.render;
      coarse.sampleDistance = 2.0 * renderer.defaultSampleDistance();
      const auto range = renderer.dataRange();
      for (auto& f : finalists)
      {
        if (f.fromColours)
          continue; // its distance was fitted on the colours
        TransferFunction1D occupancy;
        const double t = model.threshold(f.level), eps = 1e-4 * (range[1] - range[0]);
        occupancy.color = { { range[0], 1, 1, 1 } };
        occupancy.opacity = { { range[0], 0 }, { std::max(range[0], t - eps), 0 }, { t, 1 },
          { range[1], 1 } };
        const Image cast = renderTable(
          renderer, bakeTable(occupancy, range[0], range[1], 1024), f.view(start), coarse);
        model.render(f.view(start), f.level, sw, sh, scratch);
        double castArea = 0, modelArea = 0;
        for (size_t i = 0; i < scratch.m.size(); ++i)
        {
          castArea += cast.pixels[4 * i + 3] > 0.5f;
          modelArea += scratch.m[i];
        }
        if (castArea > 4 && modelArea > 4)
          f.logZoom += 0.5 * std::log(modelArea / castArea);
      }
    }
    std::sort(finalists.begin(), finalists.end(),
      [](const CameraParams& a, const CameraParams& b) { return a.score > b.score; });
    if (stages)
      *stages = { silhouettes, finalists, screen };
  }
  else
  {
    best = atBestLevel(CameraParams{});
    finalists.push_back(best);
  }
  if (search && (finalists.empty() || finalists.front().score < opt.minimumOverlap))
  {
    std::ostringstream msg;
    msg << "no camera explains the picture: the best camera's silhouette overlaps the picture's "
           "object by "
        << std::lround(100 * (finalists.empty() ? 0.0 : finalists.front().score)) << " % (at least "
        << std::lround(100 * opt.minimumOverlap) << " % needed) — is it a picture of this volume?";
    throw Error(msg.str());
  }

  result.cameraStages.silhouettes += lap(); // with the distances corrected
  // stage 3: the finalists whose overlap is close to the best scored by a short reconstruction
  // (mirror views have alike silhouettes; colours tell them apart)
  const Image& workImage = pic.alpha ? pic.rgba : pic.rgb;
  Mask overlayFull(W, H);
  // overlay candidates that the best camera's silhouette covers are the object after all
  {
    const CameraParams& b = finalists.front();
    View full = b.view(start);
    full.width = W;
    full.height = H;
    Mask sil;
    model.render(full, b.level, W, H, sil);
    const Mask silWide = dilate(sil, std::max(2, W / 100));
    std::vector<long> covered(pic.area.size(), 0);
    for (size_t i = 0; i < sil.m.size(); ++i)
      if (pic.label[i] >= 0 && silWide.m[i])
        ++covered[static_cast<size_t>(pic.label[i])];
    std::vector<char> overlay(pic.area.size(), 0);
    for (size_t k = 0; k < pic.area.size(); ++k)
      overlay[k] = candidate[k] && covered[k] < 0.5 * pic.area[k];
    for (size_t i = 0; i < sil.m.size(); ++i)
      overlayFull.m[i] = pic.label[i] >= 0 && overlay[static_cast<size_t>(pic.label[i])];
    overlayFull = dilate(overlayFull, std::max(2, W / 200));
  }
  Mask emptyFull(W, H);
  if (!pic.alpha)
  {
    const Mask near = dilate(pic.foreground, std::max(2, W / 300));
    for (size_t i = 0; i < emptyFull.m.size(); ++i)
      emptyFull.m[i] = !near.m[i] && !overlayFull.m[i];
  }
  Image weightFull(W, H, 1);
  for (size_t i = 0; i < weightFull.pixels.size(); ++i)
    weightFull.pixels[i] = overlayFull.m[i] ? 0.0f : 1.0f;
  Image emptyImage = toImage(emptyFull);
  auto makeTarget = [&](const View& v, const Image& image, int w, int h)
  {
    ReconstructionTarget t;
    t.image = image;
    t.view = v;
    t.view.width = w;
    t.view.height = h;
    t.mask = w == W && h == H ? weightFull : resizeImage(weightFull, w, h);
    if (!pic.alpha && opt.emptySpaceWeight > 0)
    {
      t.empty = w == W && h == H ? emptyImage : resizeImage(emptyImage, w, h);
      for (auto& e : t.empty.pixels)
        e = e > 0.99f ? 1.0f : 0.0f;
      t.emptyWeight = opt.emptySpaceWeight;
    }
    return t;
  };
  // the camera stage's TF: the final fit starts from it
  std::optional<TransferTable1D> warm;
  if (search)
  {
    std::vector<CameraParams> scored = camerasToScore(finalists, start, opt.cameraCandidates,
      screen
        ? std::function<double(const View&)>([&](const View& v) { return screen->residual(v); })
        : nullptr);
    ReconstructionOptions sopt = opt.reconstruction;
    sopt.twoD = false;
    sopt.primitives = 0;
    sopt.iterations = 40;
    sopt.patience = 40;
    sopt.raysPerIteration = 512;
    // coarser samples: the camera stage needs the picture's look, not its last digit
    sopt.render.sampleDistance = 3.0 * renderer.defaultSampleDistance();
    sopt.seed = 7;
    sopt.bins = 64;
    sopt.snapshotEvery = 0;
    sopt.ssimWeight = 0;
    // a short reconstruction at a camera: its TF and final loss (mean of the last steps)
    auto shortFit = [&](const CameraParams& c, const std::optional<TransferTable1D>& init)
    {
      ReconstructionOptions o = sopt;
      if (init)
        o.initial1D = init;
      auto r =
        reconstructTransferFunction(renderer, { makeTarget(c.view(start), workImage, W, H) }, o);
      const double loss = tailLoss(r);
      return std::make_pair(std::move(r), loss);
    };
    // the image loss of a TF at a camera (the reconstruction's: L1 over the compared pixels,
    // plus the empty-space term), for the camera's photometric refinement
    // a fixed set of the picture's pixels (most on and around the object, the rest anywhere
    // compared), rendered at full resolution: the camera is refined to a fraction of a pixel
    std::vector<int> probe;
    {
      const Mask around = dilate(pic.foreground, std::max(2, std::max(W, H) / 20));
      std::vector<int> near, far;
      for (int i = 0; i < W * H; ++i)
        if (!overlayFull.m[static_cast<size_t>(i)])
          (around.m[static_cast<size_t>(i)] ? near : far).push_back(i);
      std::mt19937 rng(11);
      std::shuffle(near.begin(), near.end(), rng);
      std::shuffle(far.begin(), far.end(), rng);
      near.resize(std::min<size_t>(near.size(), 3072));
      far.resize(std::min<size_t>(far.size(), 1024));
      probe = near;
      probe.insert(probe.end(), far.begin(), far.end());
      std::sort(probe.begin(), probe.end());
    }
    const ReconstructionTarget fullTarget = makeTarget(start, workImage, W, H);
    std::vector<float> probeRGBA;
    std::vector<RayRecord> probeRecords;
    auto photometricLoss =
      [&](const ReconstructionResult& tf, const CameraParams& c, const RenderOptions& how)
    {
      View v = c.view(start);
      v.width = W;
      v.height = H;
      const auto& t = tf.table1D;
      renderer.forward(
        t.rgba.data(), t.width, t.min, t.max, v, how, probe, probeRGBA, probeRecords);
      double loss = 0;
      for (size_t q = 0; q < probe.size(); ++q)
      {
        const size_t i = static_cast<size_t>(probe[q]);
        const float* p = &probeRGBA[4 * q];
        const float* want = &workImage.pixels[i * workImage.channels];
        double l = 0;
        if (pic.alpha)
        {
          for (int k = 0; k < 3; ++k)
            l += std::abs(p[k] - want[k] * want[3]);
          l += std::abs(p[3] - want[3]);
        }
        else
        {
          const auto bgc = v.backgroundAt(static_cast<int>(i) / W);
          for (int k = 0; k < 3; ++k)
            l += std::abs(p[k] + (1 - p[3]) * bgc[k] - want[k]);
          if (!fullTarget.empty.empty() && fullTarget.empty.pixels[i] > 0)
            for (int k = 0; k < 4; ++k)
              l += 0.75 * fullTarget.emptyWeight * std::abs(p[k]);
        }
        loss += l;
      }
      return loss / static_cast<double>(probe.size());
    };
    auto refine = [&](const ReconstructionResult& tf, const CameraParams& c, int evaluations,
                    const RenderOptions& how)
    {
      CameraParams r = nelderMead(
        c, [&](const CameraParams& p) { return -photometricLoss(tf, p, how); }, evaluations, 0.3);
      r.level = c.level;
      return r;
    };
    // every candidate: a short fit; the best ones (below): the camera refined on the picture's
    // colours with that TF, refitted, and refined once more; the lowest loss wins
    struct Scored
    {
      CameraParams camera;
      ReconstructionResult tf;
      double loss;
    };
    std::vector<Scored> fits;
    for (size_t i = 0; i < scored.size(); ++i)
    {
      auto [tf, loss] = shortFit(scored[i], std::nullopt);
      fits.push_back({ scored[i], std::move(tf), loss });
      report("camera", 0.45 + 0.05 * (i + 1) / scored.size(), nullptr);
    }
    std::sort(
      fits.begin(), fits.end(), [](const Scored& a, const Scored& b) { return a.loss < b.loss; });
    // refined: every candidate within 10 % of the best short fit, up to 4 (views of a translucent
    // object fit alike at first), and the runner-up unless the best is 25 % better
    size_t refined = 1;
    while (refined < std::min<size_t>(fits.size(), 4) && fits[refined].loss < 1.1 * fits[0].loss)
      ++refined;
    fits.resize(
      std::max<size_t>(refined, fits.size() > 1 && fits[1].loss < 1.25 * fits[0].loss ? 2 : 1));
    for (size_t i = 0; i < fits.size(); ++i)
    {
      // a hop first (MatchCamera.h), judged with the short fit's TF
      fits[i].camera = hopAround(fits[i].camera,
        [&](const CameraParams& c) { return photometricLoss(fits[i].tf, c, sopt.render); });
      for (int round = 0; round < std::max(1, opt.cameraRounds); ++round)
      {
        fits[i].camera = refine(fits[i].tf, fits[i].camera, round == 0 ? 80 : 40, sopt.render);
        auto [tf, loss] = shortFit(fits[i].camera, fits[i].tf.table1D);
        fits[i].tf = std::move(tf);
        fits[i].loss = loss;
      }
      report("camera", 0.5 + 0.1 * (i + 1) / fits.size(), nullptr);
    }
    const auto winner = std::min_element(
      fits.begin(), fits.end(), [](const Scored& a, const Scored& b) { return a.loss < b.loss; });
    best = winner->camera;
    result.cameraStages.candidates = lap();
    // a polish: a longer fit at the winner (more rays, all the bins, full sampling), the camera
    // refined with it; up to 3 times, until the camera moves by less than 0.25 degrees (and a
    // quarter of a percent in distance and pan)
    {
      ReconstructionOptions o = sopt;
      o.iterations = o.patience = 120;
      o.raysPerIteration = 1024;
      o.bins = opt.reconstruction.bins;
      o.render.sampleDistance = opt.reconstruction.render.sampleDistance;
      auto fitAt = [&](const CameraParams& c, const ReconstructionOptions& how)
      {
        return reconstructTransferFunction(
          renderer, { makeTarget(c.view(start), workImage, W, H) }, how);
      };
      // up to `rounds` of a fit (the first of `steps`) and the camera refined with it
      auto polish = [&](CameraParams c, const TransferTable1D& init, int rounds, int steps)
      {
        ReconstructionOptions p = o;
        p.initial1D = init;
        p.iterations = p.patience = steps;
        ReconstructionResult tf;
        for (int round = 0; round < rounds; ++round)
        {
          tf = fitAt(c, p);
          const CameraParams before = c;
          c = refine(tf, c, 150, p.render); // fine rims need full sampling
          p.initial1D = tf.table1D;
          p.iterations = p.patience = 60; // warm: a shorter refit
          // again while the camera still moves (a better TF places it better, and back)
          if (orientationDistance(before.view(start), c.view(start)) < 0.25 &&
            std::abs(before.logZoom - c.logZoom) < 0.0025 &&
            std::hypot(before.panX - c.panX, before.panY - c.panY) < 0.0025)
            break;
        }
        return std::make_pair(c, std::move(tf));
      };
      std::tie(best, winner->tf) = polish(best, winner->tf.table1D, 3, 120);
      // the other projection (an unknown camera): the winner's twin in parallel projection,
      // framed alike at the focal point, its camera refined once with a warm refit; then both
      // refitted from the winner's TF with the same steps, the twin polished and kept when its
      // loss is lower (else the winner stays as polished). ParaView draws either; silhouettes
      // hardly tell them apart, a settled camera's colours do
      if (!opt.view)
      {
        CameraParams twin = best;
        twin.parallel = true;
        twin.logZoom += std::log(std::cos(start.camera.viewAngle * M_PI / 360.0));
        twin = polish(twin, winner->tf.table1D, 1, 60).first;
        ReconstructionOptions p = o;
        p.initial1D = winner->tf.table1D;
        p.iterations = p.patience = 60;
        if (auto b = fitAt(twin, p); tailLoss(b) < tailLoss(fitAt(best, p)))
          std::tie(best, winner->tf) = polish(twin, b.table1D, 3, 60); // settled as the winner
      }
    }
    // the overlap: at the level whose silhouette fits best (a colours' camera kept its seed's)
    best.score = std::max(0.0, atBestLevel(best).score);
    if (!opt.reconstruction.twoD)
      warm = winner->tf.table1D; // started from the given initial TF, if any
  }
  result.cameraStages.polish = lap();
  result.cameraEstimated = search;
  result.overlap = best.score;
  result.orbit = { std::remainder(best.az, 360.0), best.el, std::remainder(best.roll, 360.0) };
  result.zoom = std::exp(best.logZoom);
  result.pan = { best.panX, best.panY };
  View found = best.view(start);
  found.width = W;
  found.height = H;
  result.cameraSeconds = secondsSince(tCamera);
  report("fit", 0.5, nullptr);

  // --- the fit ------------------------------------------------------------------------------
  const auto tFit = Clock::now();
  const ReconstructionTarget target0 = makeTarget(found, pic.alpha ? pic.rgba : pic.rgb, W, H);
  ReconstructionOptions ropt = opt.reconstruction;
  if (warm)
    ropt.initial1D = warm;
  View preview = found;
  preview.width = std::max(8, W / std::max(1, opt.previewDivisor));
  preview.height = std::max(8, H / std::max(1, opt.previewDivisor));
  const int iterations = std::max(1, ropt.iterations);
  result.tf = reconstructTransferFunction(renderer, { target0 }, ropt,
    [&](int step, double, const ReconstructionResult* snapshot)
    {
      Image shot;
      if (snapshot)
        shot = renderResult(renderer, *snapshot, preview, ropt.render);
      report(
        "fit", 0.5 + 0.4 * std::min(1.0, (step + 1.0) / iterations), snapshot ? &shot : nullptr);
      return true;
    });

  // the fit's PSNR over the object (the picture's foreground, or what the render shows) at the
  // preview's size, overlays left out: the background, matched by construction, does not count;
  // and each object pixel's residual (largest channel difference; -1 elsewhere). The render is
  // made at the picture's size and reduced as the picture is: rendered at the preview's size, one
  // ray a pixel, fine structure (a chest's ribs) aliases against the picture's filtered pixels
  // (a chest at its true camera: 23.7 dB so, 35.9 dB reduced alike)
  const Image theirs =
    resizeImage(pic.alpha ? premultiplyAlpha(pic.rgba) : pic.rgb, preview.width, preview.height);
  const Image object = resizeImage(
    toImage(dilate(pic.foreground, std::max(1, W / 200))), preview.width, preview.height);
  std::vector<double> residual;
  Mask edge; // the render's silhouette edge (opacity across 0.5), 2 preview pixels either side
  auto assess = [&](const ReconstructionResult& tf)
  {
    const Image render =
      resizeImage(renderResult(renderer, tf, found, ropt.render), preview.width, preview.height);
    Mask inside(preview.width, preview.height), outside(preview.width, preview.height);
    for (size_t i = 0; i < inside.m.size(); ++i)
      (render.pixels[4 * i + 3] > 0.5f ? inside : outside).m[i] = 1;
    edge = dilate(inside, 2);
    const Mask out = dilate(outside, 2);
    for (size_t i = 0; i < edge.m.size(); ++i)
      edge.m[i] = edge.m[i] && out.m[i];
    const Image ours = pic.alpha
      ? render
      : (preview.background2
            ? compositeOverBackground(render, preview.background, *preview.background2)
            : compositeOverBackground(render, preview.background));
    const Image weight = resizeImage(weightFull, preview.width, preview.height);
    const size_t np = static_cast<size_t>(preview.width) * preview.height;
    residual.assign(np, -1.0);
    double se = 0, n = 0;
    for (size_t i = 0; i < np; ++i)
    {
      if (weight.pixels[i] < 0.99f ||
        (object.pixels[i] < 0.01f && render.pixels[4 * i + 3] < 0.01f))
        continue;
      double largest = 0;
      for (int c = 0; c < ours.channels; ++c)
      {
        const double d =
          ours.pixels[i * ours.channels + c] - theirs.pixels[i * theirs.channels + c];
        se += d * d;
        n += 1;
        largest = std::max(largest, std::abs(d));
      }
      residual[i] = largest;
    }
    return se > 0 ? 10.0 * std::log10(n / se) : 100.0;
  };
  if (opt.reconstruction.initial1D && !opt.reconstruction.twoD)
  {
    ReconstructionResult start1D;
    start1D.table1D = *opt.reconstruction.initial1D;
    result.initialPSNR = assess(start1D);
  }
  result.fitPSNR = assess(result.tf);
  // outliers: what the fit cannot explain on the object (text, arrows or marks drawn over it):
  // residuals above 6 times the median and above 0.2, on at least 0.2 % of the object, are
  // masked as overlays and the TF refitted without them (1D). Not along the render's silhouette
  // edge: a rim the fit misses is the object's, not a mark over it (and masking it would let a
  // picture of another volume pass as explained)
  if (opt.maskOverlays && !result.tf.twoD)
  {
    std::vector<double> onObject;
    for (double r : residual)
      if (r >= 0)
        onObject.push_back(r);
    const double limit = std::max(0.2, 6.0 * median(onObject));
    Mask outliers(preview.width, preview.height);
    size_t count = 0;
    for (size_t i = 0; i < residual.size(); ++i)
      if (residual[i] > limit && !edge.m[i])
        outliers.m[i] = 1, ++count;
    if (count > 3 && static_cast<double>(count) >= 0.002 * static_cast<double>(onObject.size()))
    {
      const Mask wide = dilate(outliers, 1);
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
          if (wide(std::min(preview.width - 1, x * preview.width / W),
                std::min(preview.height - 1, y * preview.height / H)))
          {
            overlayFull(x, y) = 1;
            weightFull.pixels[static_cast<size_t>(y) * W + x] = 0.0f;
            emptyImage.pixels[static_cast<size_t>(y) * W + x] = 0.0f;
          }
      ReconstructionOptions again = ropt;
      again.initial1D = result.tf.table1D;
      again.iterations = std::min(ropt.iterations, 150);
      const ReconstructionTarget masked = makeTarget(found, pic.alpha ? pic.rgba : pic.rgb, W, H);
      result.tf = reconstructTransferFunction(renderer, { masked }, again,
        [&](int step, double, const ReconstructionResult*)
        {
          report("fit", 0.9 + 0.1 * std::min(1.0, (step + 1.0) / again.iterations), nullptr);
          return true;
        });
      result.fitPSNR = assess(result.tf);
    }
  }
  result.fitSeconds = secondsSince(tFit);
  if (search && result.fitPSNR < opt.minimumFitPSNR)
  {
    throw Error(noCameraExplains(result.fitPSNR, opt.minimumFitPSNR, result.overlap, ""));
  }
  result.view = found;
  result.view.width = result.crop[2];
  result.view.height = result.crop[3];
  result.masks.foreground = toImage(pic.foreground);
  result.masks.overlay = toImage(overlayFull);
  if (W != result.crop[2] || H != result.crop[3])
  {
    result.masks.foreground = resizeImage(result.masks.foreground, result.crop[2], result.crop[3]);
    result.masks.overlay = resizeImage(result.masks.overlay, result.crop[2], result.crop[3]);
  }
  result.seconds = secondsSince(t0);
  report("fit", 1.0, nullptr);
  return result;
}

} // namespace ddg
