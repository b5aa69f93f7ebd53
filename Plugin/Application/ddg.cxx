// ddg.cxx: the command-line program — the project's public interface for rendering and (later)
// reconstruction, generation, training and gallery operations. See `ddg --help`.
#include "DDGVolumeAdaptor.h"
#include "GalleryCommands.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Design/ExemplarGenerator.h"
#include "Image/Image.h"
#ifdef DDG_WITH_TORCH
#include "Gallery/BuildDesignSpace.h"
#include "Neural/DesignValidity.h"
#include "Neural/NeuralModel.h"
#endif
#include "Image/ImageMetrics.h"
#include "Reconstruct/Reconstruction.h"
#include "Reconstruct/ViewEstimation.h"
#include "Render/DifferentiableRenderer.h"
#include "Render/RayCaster.h"
#include "Render/View.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace
{

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// --- ddg render -----------------------------------------------------------------------------

struct RenderArgs
{
  std::string volume, tf, view, out, array;
  bool alpha = false, jitter = false, noSkip = false;
  double sampleDistance = 0, sampleOffset = 0.5;
  int threads = 0;
};

int runRender(const RenderArgs& a)
{
  const auto t0 = Clock::now();
  const ddg::View view = ddg::readView(a.view);
  const ddg::TransferFunctionFile tf = ddg::readTransferFunctionFile(a.tf);
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  if (volume.nonFiniteCount() > 0)
  {
    std::cerr << "ddg render: warning: " << volume.nonFiniteCount()
              << " NaN/infinite voxels were set to the minimum value " << volume.range()[0] << "\n";
  }
  const ddg::RayCaster caster(volume);
  const double tLoad = msSince(t0);
  ddg::RenderOptions opt;
  opt.jitter = a.jitter;
  opt.sampleDistance = a.sampleDistance;
  opt.sampleOffset = a.sampleOffset;
  opt.emptySpaceSkipping = !a.noSkip;
  opt.threads = a.threads;
  const auto t1 = Clock::now();
  const ddg::Image rgba = tf.is2D ? caster.render(tf.tf2D.bake(), view, opt)
                                  : caster.render(caster.paraviewTable(tf.tf1D), view, opt);
  const double tRender = msSince(t1);
  if (a.alpha)
  {
    // PNG convention: straight (unpremultiplied) alpha.
    ddg::Image straight = rgba;
    for (size_t i = 0; i < straight.pixels.size(); i += 4)
    {
      const float al = straight.pixels[i + 3];
      for (int c = 0; c < 3; ++c)
      {
        straight.pixels[i + c] = al > 0 ? std::min(1.0f, straight.pixels[i + c] / al) : 0.0f;
      }
    }
    ddg::writeImage(straight, a.out);
  }
  else
  {
    ddg::writeImage(ddg::compositeOverBackground(rgba, view.background), a.out);
  }
  std::printf("wrote %s (%d x %d) load %.0f ms, render %.1f ms\n", a.out.c_str(), view.width,
    view.height, tLoad, tRender);
  return 0;
}

// --- ddg compare ----------------------------------------------------------------------------

struct CompareArgs
{
  std::string a, b;
  double minPsnr = -1;
  bool json = false;
};

int runCompare(const CompareArgs& c)
{
  const ddg::Image a = ddg::readImage(c.a);
  const ddg::Image b = ddg::readImage(c.b);
  const double p = ddg::psnr(a, b);
  const double s = ddg::ssim(a, b);
  const double emd = ddg::colorHistogramEMD(a, b);
  if (c.json)
  {
    std::printf(
      "{\"psnr\": %.4f, \"ssim\": %.6f, \"emd\": %.6f}\n", std::isinf(p) ? 999.0 : p, s, emd);
  }
  else
  {
    std::printf("PSNR %.2f dB  SSIM %.5f  EMD %.4f\n", std::isinf(p) ? 999.0 : p, s, emd);
  }
  if (c.minPsnr >= 0 && p < c.minPsnr)
  {
    std::fprintf(stderr, "ddg compare: PSNR %.2f dB is below the required %.2f dB\n", p, c.minPsnr);
    return 3;
  }
  return 0;
}

// --- ddg view -------------------------------------------------------------------------------

struct ViewArgs
{
  std::string volume, out, array;
  std::vector<int> size{ 512, 512 };
  double azimuth = 0, elevation = 0, zoom = 1;
  bool parallel = false;
  std::vector<double> background;
};

int runView(const ViewArgs& a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  ddg::View v = ddg::defaultView(volume, a.size[0], a.size[1]);
  auto& cam = v.camera;
  // vtkCamera::Azimuth (about view up through the focal point), then Elevation (about the
  // right vector), then OrthogonalizeViewUp.
  const Eigen::Vector3d up = cam.viewUp.normalized();
  Eigen::Vector3d offset = cam.position - cam.focalPoint;
  offset = Eigen::AngleAxisd(a.azimuth * M_PI / 180.0, up) * offset;
  const Eigen::Vector3d right = (-offset).normalized().cross(up).normalized();
  offset = Eigen::AngleAxisd(-a.elevation * M_PI / 180.0, right) * offset;
  cam.position = cam.focalPoint + offset / (a.parallel ? 1.0 : a.zoom);
  const Eigen::Vector3d forward = (-offset).normalized();
  cam.viewUp = forward.cross(up).normalized().cross(forward).normalized();
  if (cam.viewUp.norm() < 0.5 || !std::isfinite(cam.viewUp[0]))
  {
    throw ddg::Error("elevation of +-90 degrees makes view_up parallel to the view direction");
  }
  cam.parallelProjection = a.parallel;
  cam.parallelScale /= a.zoom;
  if (!a.background.empty())
  {
    if (a.background.size() != 3)
    {
      throw ddg::Error("--background needs three numbers r g b");
    }
    v.background = { a.background[0], a.background[1], a.background[2] };
  }
  v.validate();
  ddg::writeView(v, a.out);
  std::printf("wrote %s\n", a.out.c_str());
  return 0;
}

// --- ddg reconstruct ------------------------------------------------------------------------

struct ReconstructArgs
{
  std::string volume, out, outImage, init, array, loss = "l1";
  std::vector<std::string> targets, views, masks;
  std::vector<double> background;
  bool twoD = false, resample = false, quiet = false, estimateView = false;
  std::string outView;
  int bins = 128, gradientBins = 32, iterations = 500, rays = 2048, threads = 0, primitives = 0;
  double smoothness = 0.01, learningRate = 0.2, ssimWeight = 0.0;
  unsigned seed = 1;
};

// Reads a target image for reconstruction and checks what the reconstruction can use.
ddg::Image readTarget(const std::string& path, const ddg::View& view, bool resample)
{
  ddg::ImageFileInfo info;
  ddg::Image img = ddg::readImage(path, &info);
  if (img.channels != 3 && img.channels != 4)
  {
    throw ddg::Error("target '" + path + "' has " + std::to_string(img.channels) +
      " channels; an RGB screenshot or an RGBA image (straight alpha) is needed");
  }
  if (info.format != "uint8")
  {
    for (float v : img.pixels)
    {
      if (!std::isfinite(v) || v < 0.0f || v > 1.0f)
      {
        throw ddg::Error("target '" + path + "' is a " + info.format +
          " image with values outside [0, 1] (or NaN): tone-map it to [0, 1] first");
      }
    }
    std::fprintf(stderr,
      "ddg reconstruct: note: target '%s' is %s per channel; using its values in [0, 1]\n",
      path.c_str(), info.format.c_str());
  }
  if (img.width != view.width || img.height != view.height)
  {
    if (!resample)
    {
      throw ddg::Error("target '" + path + "' is " + std::to_string(img.width) + " x " +
        std::to_string(img.height) + " but its view is " + std::to_string(view.width) + " x " +
        std::to_string(view.height) + " (pass --resample to resize the target to the view)");
    }
    img = ddg::resizeImage(img, view.width, view.height);
  }
  return img;
}

int runReconstruct(const ReconstructArgs& a)
{
  const auto t0 = Clock::now();
  if (a.views.size() != a.targets.size())
  {
    throw ddg::Error("give one --view per --target (" + std::to_string(a.targets.size()) +
      " targets, " + std::to_string(a.views.size()) + " views)");
  }
  if (!a.masks.empty() && a.masks.size() != a.targets.size())
  {
    throw ddg::Error("give one --mask per --target, or none");
  }
  std::vector<ddg::ReconstructionTarget> targets(a.targets.size());
  for (size_t i = 0; i < a.targets.size(); ++i)
  {
    targets[i].view = ddg::readView(a.views[i]);
    if (!a.background.empty())
    {
      targets[i].view.background = { a.background[0], a.background[1], a.background[2] };
    }
    targets[i].image = readTarget(a.targets[i], targets[i].view, a.resample);
    if (!a.masks.empty())
    {
      targets[i].mask = readTarget(a.masks[i], targets[i].view, a.resample);
    }
  }
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  const ddg::DifferentiableRenderer renderer(volume);
  ddg::ReconstructionOptions opt;
  opt.twoD = a.twoD;
  opt.bins = a.bins;
  opt.gradientBins = a.gradientBins;
  opt.primitives = a.primitives;
  opt.loss = a.loss == "l2" ? ddg::ReconstructionLoss::L2 : ddg::ReconstructionLoss::L1;
  opt.smoothness = a.smoothness;
  opt.ssimWeight = a.ssimWeight;
  opt.iterations = a.iterations;
  opt.learningRate = a.learningRate;
  opt.raysPerIteration = a.rays;
  opt.seed = a.seed;
  opt.render.threads = a.threads;
  if (!a.init.empty())
  {
    const ddg::TransferFunction1D init = ddg::readPreset(a.init);
    opt.initial1D = ddg::bakeTable(init, volume.range()[0], volume.range()[1], 1024);
  }
  if (a.estimateView)
  {
    for (size_t i = 0; i < targets.size(); ++i)
    {
      ddg::ViewEstimationOptions vopt;
      vopt.render.threads = a.threads;
      ddg::ViewEstimationReport report;
      targets[i].view = ddg::estimateView(renderer, targets[i], vopt, &report);
      std::printf(
        "estimated view of target %zu: azimuth %.1f, elevation %.1f, zoom %.3f from the given view "
        "(%d short fits, %.1f s)\n",
        i, report.azimuth, report.elevation, report.zoom, report.evaluations, report.seconds);
      if (!a.outView.empty())
      {
        ddg::writeView(targets[i].view,
          targets.size() == 1 ? a.outView : a.outView + "." + std::to_string(i) + ".json");
      }
    }
  }
  const double tLoad = msSince(t0);
  const auto result = ddg::reconstructTransferFunction(renderer, targets, opt,
    [&](int step, double loss, const ddg::ReconstructionResult*)
    {
      if (!a.quiet && (step % 50 == 0))
      {
        std::printf("step %4d  loss %.6f\n", step, loss);
        std::fflush(stdout);
      }
      return true;
    });
  if (result.twoD)
  {
    ddg::TransferFunction2D tf;
    tf.name = "ddg reconstruct";
    tf.table = result.table2D;
    ddg::writeTransferFunction2D(tf, a.out);
  }
  else
  {
    ddg::writePreset(
      ddg::tableToTransferFunction(result.table1D, 1.0 / 512.0, "ddg reconstruct"), a.out);
  }
  std::printf("%s after %d steps (%.2f s, load %.0f ms); wrote %s\n",
    result.converged ? "converged" : "did NOT converge (iteration limit)", result.iterations,
    result.seconds, tLoad, a.out.c_str());
  for (size_t i = 0; i < targets.size(); ++i)
  {
    const auto& t = targets[i];
    const ddg::Image render = ddg::renderResult(renderer.caster(), result, t.view, {});
    ddg::Image ours, target;
    if (t.image.channels == 4)
    {
      // compare over the view's background, as a person sees them
      ddg::Image premult = t.image;
      for (size_t p = 0; p < premult.pixels.size(); p += 4)
        for (int c = 0; c < 3; ++c)
          premult.pixels[p + c] *= premult.pixels[p + 3];
      target = ddg::compositeOverBackground(premult, t.view.background);
    }
    else
    {
      target = t.image;
    }
    ours = ddg::compositeOverBackground(render, t.view.background);
    std::printf("target %zu (%s): PSNR %.2f dB  SSIM %.4f  EMD %.3f\n", i, a.targets[i].c_str(),
      ddg::psnr(ours, target), ddg::ssim(ours, target), ddg::colorHistogramEMD(ours, target));
    if (i == 0 && !a.outImage.empty())
    {
      ddg::writeImage(ours, a.outImage);
    }
  }
  return 0;
}

// --- ddg generate ---------------------------------------------------------------------------

struct GenerateArgs
{
  std::string volume, spec, out, array, preview;
  int count = 1000, size = 64, threads = 0, shardSize = 256;
  std::uint64_t seed = 1, firstIndex = 0;
  bool quiet = false;
};

int runGenerate(const GenerateArgs& a)
{
  const ddg::DesignSpaceSpec spec =
    a.spec.empty() ? ddg::DesignSpaceSpec{} : ddg::readDesignSpaceSpec(a.spec);
  const ddg::Volume volume = ddg::readVolumeFile(a.volume, a.array);
  ddg::GenerateOptions opt;
  opt.count = a.count;
  opt.size = a.size;
  opt.seed = a.seed;
  opt.firstIndex = a.firstIndex;
  opt.threads = a.threads;
  opt.shardSize = a.shardSize;
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(a.volume, ec);
  opt.volumeFile = ec ? a.volume : absolute.lexically_normal().string();
  int lastPercent = -1;
  const auto report = ddg::generateExemplars(volume, spec, a.out, opt,
    [&](double f)
    {
      const int percent = static_cast<int>(100 * f);
      if (!a.quiet && percent / 10 != lastPercent / 10)
      {
        std::printf("generated %3d %%\n", percent);
        std::fflush(stdout);
      }
      lastPercent = percent;
      return true;
    });
  for (const auto& r : report.regions)
  {
    if (r.twoD())
      std::printf("region value [%g, %g] peak %g, gradient magnitude [%g, %g] peak %g (%.1f %% of "
                  "non-air voxels)\n",
        r.lo, r.hi, r.peak, r.gradientLo, r.gradientHi, r.gradientPeak, 100 * r.mass);
    else
      std::printf(
        "region [%g, %g] peak %g (%.1f %% of non-air voxels)\n", r.lo, r.hi, r.peak, 100 * r.mass);
  }
  std::printf("wrote %d exemplars of %d x %d to %s in %.2f s (%.1f exemplars/s)\n", report.count,
    a.size, a.size, a.out.c_str(), report.seconds, report.count / report.seconds);
  if (!a.preview.empty())
  {
    // contact sheet: up to 8 rows of (image at V_exp | viewport | ground truth over grey)
    const ddg::ExemplarDataset data(a.out);
    std::vector<ddg::Image> cells;
    for (int r = 0; r < std::min(8, data.count()); ++r)
    {
      const auto im = data.images(r);
      cells.push_back(im.rgbExp);
      cells.push_back(ddg::compositeOverBackground(im.viewport, { 0.5, 0.5, 0.5 }));
      cells.push_back(ddg::compositeOverBackground(im.truth, { 0.5, 0.5, 0.5 }));
    }
    const ddg::Image sheet = ddg::tileImages(cells, 3);
    ddg::writeImage(sheet, a.preview);
    std::printf("wrote preview %s\n", a.preview.c_str());
  }
  return 0;
}

#ifdef DDG_WITH_TORCH
// --- ddg train / ddg eval -------------------------------------------------------------------

struct TrainArgs
{
  std::string data, out, evalData, checkpoint, kind = "decoder";
  double minutes = 10, lr = 0, lambda = 1000, dropout = 0.5, imageWeight = 100;
  int width = 16, latent = 64, batch = 16, threads = 0, maxIterations = 0, evalCount = 1000;
  int imageRays = 512;
  std::uint64_t seed = 1;
  int checkCount = 100;
  bool resume = false, quiet = false, cosine = false;
  std::string volume;
};

void printEvaluation(const ddg::EvaluationReport& e)
{
  std::printf("held-out %d exemplars: PSNR %.2f dB  SSIM %.4f  EMD %.3f  invariance %.3f  analyzer "
              "%.2f ms  renderer %.2f ms\n",
    e.count, e.psnr, e.ssim, e.emd, e.invariance, e.analyzerMs, e.rendererMs);
}

int runTrain(const TrainArgs& a)
{
  const ddg::ExemplarDataset data(a.data);
  ddg::NetworkConfig cfg;
  cfg.imageSize = data.size();
  cfg.width = a.width;
  cfg.latent = a.latent;
  cfg.dropout = a.dropout;
  cfg.kind = a.kind;
  cfg.regions = static_cast<int>(data.regions().size());
  cfg.dimensions = data.spec().dimensions;
  ddg::NeuralDesignModel model(cfg, a.seed);
  std::unique_ptr<ddg::ExemplarDataset> heldout;
  if (!a.evalData.empty())
  {
    heldout = std::make_unique<ddg::ExemplarDataset>(a.evalData);
    if (heldout->fingerprint() != data.fingerprint())
      throw ddg::Error(
        "the held-out data '" + a.evalData + "' belongs to another volume than the training data");
  }
  ddg::TrainOptions opt;
  opt.batch = a.batch;
  opt.learningRate = a.lr > 0 ? a.lr : (a.kind == "decoder" ? 1e-3 : 2e-4);
  opt.lambdaL1 = a.lambda;
  opt.minutes = a.minutes;
  opt.maxIterations = a.maxIterations;
  opt.seed = a.seed;
  opt.threads = a.threads;
  opt.checkpoint = a.checkpoint;
  opt.resume = a.resume;
  opt.imageWeight = a.kind == "decoder" ? a.imageWeight : 0.0;
  opt.imageRays = a.imageRays;
  opt.cosineSchedule = a.cosine;
  // the decoder ray casts its TFs: the volume given, or the one the data was generated from
  const std::string volumeFile = a.volume.empty() ? data.volumeFile() : a.volume;
  if (a.kind == "decoder")
  {
    if (volumeFile.empty())
      throw ddg::Error("the decoder needs its volume: pass --volume (the dataset does not name it)");
    model.attachVolume(ddg::readVolumeFile(volumeFile));
  }
  std::printf("training %lld parameters on %d exemplars of %d x %d for up to %.1f min\n",
    static_cast<long long>(model.parameterCount()), data.count(), data.size(), data.size(),
    a.minutes);
  int lastPrint = -1000;
  const auto report = model.train(data, opt,
    [&](const ddg::TrainProgress& p)
    {
      if (!a.quiet && p.iteration - lastPrint >= 200)
      {
        if (a.kind == "decoder")
          std::printf("iteration %6d  parameter L1 %.4f  image L1 %.4f  %.0f s, ETA %.0f s\n",
            p.iteration, p.l1, p.image, p.seconds, p.eta);
        else
          std::printf("iteration %6d  G %.3f  D %.3f  L1 %.4f  %.0f s, ETA %.0f s\n", p.iteration,
            p.lossG, p.lossD, p.l1, p.seconds, p.eta);
        std::fflush(stdout);
        lastPrint = p.iteration;
      }
      return true;
    });
  std::printf("trained %d iterations in %.1f s (%.1f exemplars/s)\n", report.iterations,
    report.seconds, report.exemplarsPerSecond);
  ddg::EvaluationReport e;
  std::string metrics = ddg::metricsToJson(e, &report, model.parameterCount());
  if (heldout)
  {
    e = model.evaluate(*heldout, a.evalCount);
    printEvaluation(e);
    // the first checkCount held-out exemplars again: what a quick test can reproduce
    const auto check = model.evaluate(*heldout, a.checkCount);
    metrics = ddg::metricsToJson(e, &report, model.parameterCount());
    metrics.pop_back();
    metrics += ", \"check\": " + ddg::metricsToJson(check, nullptr, model.parameterCount()) + "}";
  }
  model.saveBundle(a.out, data, metrics);
  std::printf("wrote model bundle %s\n", a.out.c_str());
  return 0;
}

int runEval(const std::string& modelDir, const std::string& dataDir, int count, bool json,
  const std::string& volume, const std::string& perExemplar)
{
  const ddg::ExemplarDataset data(dataDir);
  auto model = ddg::NeuralDesignModel::loadBundle(modelDir, data.fingerprint());
  if (!volume.empty())
    model.attachVolume(ddg::readVolumeFile(volume));
  const auto e = model.evaluate(data, count);
  if (!perExemplar.empty())
  {
    std::string csv = "index,active_regions,background,psnr,ssim,emd\n";
    char line[160];
    for (size_t i = 0; i < e.items.size(); ++i)
    {
      const auto& x = data.exemplars()[i];
      std::snprintf(line, sizeof(line), "%zu,%zu,%d,%.4f,%.5f,%.5f\n", i, x.active.size(),
        x.background, e.items[i].psnr, e.items[i].ssim, e.items[i].emd);
      csv += line;
    }
    ddg::writeFileAtomic(perExemplar, csv, "per-exemplar figures");
  }
  if (json)
    std::printf("%s\n", ddg::metricsToJson(e, nullptr, model.parameterCount()).c_str());
  else
    printEvaluation(e);
  return 0;
}

struct ValidityArgs
{
  std::string model, volume, view, out;
  int count = 6, size = 128;
  std::uint64_t seed = 1;
};

int runValidity(const ValidityArgs& a)
{
  const ddg::Volume volume = ddg::readVolumeFile(a.volume);
  auto model = ddg::NeuralDesignModel::loadBundle(a.model, ddg::volumeFingerprint(volume));
  const ddg::View view = a.view.empty() ? ddg::defaultView(volume, a.size, a.size)
                                        : ddg::readView(a.view);
  const auto r = ddg::designSpaceValidity(model, volume, view, a.count, a.seed);
  for (size_t i = 0; i < r.rows.size(); ++i)
  {
    const auto& row = r.rows[i];
    std::printf("random latent %zu: nearest by cosine #%d (%.3f, PSNR %.2f dB), by distance #%d "
                "(%.3f, PSNR %.2f dB)\n",
      i, row.nearestCosine, row.cosine, row.psnrCosine, row.nearestEuclidean, row.euclidean,
      row.psnrEuclidean);
  }
  std::printf("mean PSNR of a random latent's design against its nearest training design: "
              "%.2f dB (cosine), %.2f dB (Euclidean)\n",
    r.meanPsnrCosine, r.meanPsnrEuclidean);
  ddg::writeImage(r.sheet, a.out);
  std::printf("wrote %s (rows: random latent | nearest by cosine | nearest by distance)\n",
    a.out.c_str());
  return 0;
}
#endif

// --- ddg info -------------------------------------------------------------------------------

int runInfo(const std::string& path, const std::string& array)
{
  const ddg::Volume v = ddg::readVolumeFile(path, array);
  const auto& d = v.dims();
  const auto& s = v.spacing();
  const auto& o = v.origin();
  std::printf("volume       %s\n", path.c_str());
  std::printf("dimensions   %d x %d x %d (%lld voxels)\n", d[0], d[1], d[2],
    static_cast<long long>(v.voxelCount()));
  std::printf("scalar type  %s\n", ddg::scalarTypeName(v.originalType()));
  std::printf("origin       %g %g %g\n", o[0], o[1], o[2]);
  std::printf("spacing      %g %g %g\n", s[0], s[1], s[2]);
  std::printf("range        %g .. %g\n", v.range()[0], v.range()[1]);
  if (v.nonFiniteCount() > 0)
  {
    std::printf("non-finite   %lld voxels (rendered as the minimum)\n",
      static_cast<long long>(v.nonFiniteCount()));
  }
  try
  {
    const ddg::RayCaster caster(v);
    std::printf("sample distance (ParaView default)        %.7g\n", caster.defaultSampleDistance());
    std::printf(
      "opacity unit distance (ParaView default)  %.7g\n", caster.defaultOpacityUnitDistance());
  }
  catch (const ddg::Error& e)
  {
    std::printf("not renderable: %s\n", e.what());
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  CLI::App app{
    "ddg — Differentiable Design Gallery: volume rendering and transfer functions.\n"
    "Files shared by every command (see README.md):\n"
    "  TF file   ParaView preset JSON [{\"Name\", \"ColorSpace\", \"RGBPoints\": [x,r,g,b,...],\n"
    "            \"Points\": [x,alpha,midpoint,sharpness,...]}], or the DDG 2D TF JSON\n"
    "            {\"Format\": \"ddg-transfer-function-2d\", ...}\n"
    "  view file {\"camera\": {\"position\", \"focal_point\", \"view_up\", \"view_angle\",\n"
    "            \"parallel_projection\", \"parallel_scale\"}, \"size\": [w,h],\n"
    "            \"background\": [r,g,b], \"opacity_unit_distance\": d (optional)}\n"
    "  volumes   .vti .vtk .nrrd .nhdr .mha .mhd .nii .nii.gz, or raw(.gz) + JSON sidecar",
    "ddg"
  };
  app.require_subcommand(1);
  app.set_version_flag("--version", "ddg 0.1.0");

  RenderArgs ra;
  auto* render = app.add_subcommand("render",
    "Render a volume with a TF file and a view file to an image (as ParaView's Volume "
    "representation would).");
  render->add_option("--volume", ra.volume, "Volume file")->required();
  render->add_option("--tf", ra.tf, "Transfer function file (ParaView preset JSON or DDG 2D JSON)")
    ->required();
  render
    ->add_option("--view", ra.view, "View JSON (camera, size, background, opacity_unit_distance)")
    ->required();
  render->add_option("--out", ra.out, "Output image (.png, .jpg, .tif, .exr, ...)")->required();
  render->add_option("--array", ra.array, "Point array to render (default: the active scalars)");
  render->add_flag(
    "--alpha", ra.alpha, "Write RGBA with straight alpha instead of RGB over the background");
  render->add_flag("--jitter", ra.jitter, "Jitter the first sample per pixel (default: off)");
  render
    ->add_option("--sample-distance", ra.sampleDistance,
      "Sample distance in world units (default 0: ParaView's rule, mean spacing / 2)")
    ->check(CLI::NonNegativeNumber);
  render
    ->add_option("--sample-offset", ra.sampleOffset,
      "First sample at entry + offset * step when not jittering (default 0.5)")
    ->check(CLI::Range(0.0, 1.0));
  render->add_flag("--no-skip", ra.noSkip, "Disable empty-space skipping (same image, slower)");
  render->add_option("--threads", ra.threads, "Worker threads (default 0: all cores)")
    ->check(CLI::Range(0, 256));

  CompareArgs ca;
  auto* compare = app.add_subcommand("compare",
    "Print PSNR (dB), SSIM and colour-histogram EMD (CIELAB, Berger et al.) of two images of the "
    "same size.");
  compare->add_option("a", ca.a, "First image")->required();
  compare->add_option("b", ca.b, "Second image")->required();
  compare->add_option("--min-psnr", ca.minPsnr, "Exit with status 3 when PSNR is below this (dB)");
  compare->add_flag("--json", ca.json, "Print {\"psnr\": ..., \"ssim\": ..., \"emd\": ...}");

  ViewArgs va;
  auto* viewCmd = app.add_subcommand("view",
    "Write a view JSON for a volume: ParaView's reset camera (looking down -z, +y up), then "
    "azimuth/elevation/zoom.");
  viewCmd->add_option("--volume", va.volume, "Volume file")->required();
  viewCmd->add_option("--out", va.out, "Output view JSON")->required();
  viewCmd->add_option("--array", va.array, "Point array (default: the active scalars)");
  viewCmd->add_option("--size", va.size, "Image width and height (default 512 512)")->expected(2);
  viewCmd->add_option("--azimuth", va.azimuth, "Degrees about the view up vector (default 0)");
  viewCmd->add_option("--elevation", va.elevation, "Degrees about the right vector (default 0)");
  viewCmd->add_option("--zoom", va.zoom, "Zoom factor > 0 (default 1)")->check(CLI::PositiveNumber);
  viewCmd->add_flag("--parallel", va.parallel, "Parallel projection");
  viewCmd->add_option("--background", va.background, "Background r g b in [0, 1]")->expected(3);

  ReconstructArgs rc;
  auto* reconstruct = app.add_subcommand("reconstruct",
    "Find a transfer function whose rendering matches target image(s) (differentiable ray caster + "
    "Adam).");
  reconstruct->add_option("--volume", rc.volume, "Volume file")->required();
  reconstruct
    ->add_option("--target", rc.targets,
      "Target image: RGB screenshot over the view's background, or RGBA with straight alpha "
      "(repeat for multi-view)")
    ->required();
  reconstruct->add_option("--view", rc.views, "View JSON of each target, in the same order")
    ->required();
  reconstruct
    ->add_option("--out", rc.out, "Output TF: ParaView preset JSON (1D) or DDG 2D JSON (--2d)")
    ->required();
  reconstruct->add_option(
    "--mask", rc.masks, "Per-target mask image (first channel = weight in [0, 1])");
  reconstruct
    ->add_option("--background", rc.background,
      "Background r g b of opaque targets (default: the view's background)")
    ->expected(3);
  reconstruct->add_flag("--2d", rc.twoD, "Reconstruct a 2D TF (value x gradient magnitude)");
  reconstruct->add_option("--bins", rc.bins, "TF resolution along the value (default 128)")
    ->check(CLI::Range(2, 4096));
  reconstruct
    ->add_option(
      "--gradient-bins", rc.gradientBins, "2D: bins along gradient magnitude (default 32)")
    ->check(CLI::Range(2, 1024));
  reconstruct
    ->add_option("--primitives", rc.primitives,
      "Fit K Gaussian primitives (mean, width, colour, opacity each) instead of free bins; "
      "rasterized at --bins, no smoothness prior (default 0: bins)")
    ->check(CLI::Range(0, 64));
  reconstruct->add_option("--loss", rc.loss, "l1 (default) or l2")
    ->check(CLI::IsMember({ "l1", "l2" }));
  reconstruct->add_option(
    "--smoothness", rc.smoothness, "Weight of the smoothness prior (default 0.01)");
  reconstruct->add_option("--iterations", rc.iterations, "Maximum Adam steps (default 500)")
    ->check(CLI::Range(1, 1000000));
  reconstruct
    ->add_option("--lr", rc.learningRate, "Adam learning rate in logit space (default 0.2)")
    ->check(CLI::PositiveNumber);
  reconstruct
    ->add_option("--rays", rc.rays, "Random pixels per target and step, 0 = all (default 2048)")
    ->check(CLI::NonNegativeNumber);
  reconstruct->add_option("--init", rc.init, "Initial TF (ParaView preset JSON; 1D only)");
  reconstruct->add_flag("--resample", rc.resample,
    "Resize targets to their view's size instead of refusing a size mismatch");
  reconstruct->add_option(
    "--out-image", rc.outImage, "Also write our render of the result at the first view");
  reconstruct->add_option("--seed", rc.seed, "Seed of the pixel sampling (default 1)");
  reconstruct->add_option("--threads", rc.threads, "Worker threads (default 0: all cores)")
    ->check(CLI::Range(0, 256));
  reconstruct->add_option("--array", rc.array, "Point array (default: the active scalars)");
  reconstruct->add_flag("--quiet", rc.quiet, "Do not print progress");
  reconstruct
    ->add_option("--ssim-weight", rc.ssimWeight,
      "Weight of an extra (1 - SSIM) loss on a random 32x32 patch per view and step (default 0: "
      "off)")
    ->check(CLI::NonNegativeNumber);
  reconstruct->add_flag("--estimate-view", rc.estimateView,
    "The views are only approximate (size, background, view angle, up vector, distance): search "
    "the camera "
    "(orbit azimuth/elevation/zoom about the focal point) before reconstructing");
  reconstruct->add_option(
    "--out-view", rc.outView, "With --estimate-view: write the estimated view JSON");

  GenerateArgs ga;
  auto* generate = app.add_subcommand("generate",
    "Render design exemplars (paper 4.3.1): random Gaussian-primitive TFs over the volume's "
    "feature regions, "
    "each at a random view on black or white, with a viewport image and the ground truth at "
    "another view.");
  generate->add_option("--volume", ga.volume, "Volume file")->required();
  generate->add_option(
    "--spec", ga.spec, "Design space spec JSON (default: the documented defaults)");
  generate->add_option("--count", ga.count, "Exemplars (default 1000)")
    ->check(CLI::Range(1, 10000000));
  generate->add_option("--size", ga.size, "Image side in pixels (default 64)")
    ->check(CLI::Range(8, 1024));
  generate->add_option("--out", ga.out, "Output directory (shards + dataset.json)")->required();
  generate->add_option(
    "--seed", ga.seed, "Seed (default 1): the dataset is a function of volume, spec and seed");
  generate->add_option("--first-index", ga.firstIndex,
    "Index of the first exemplar (default 0; use another range for held-out sets)");
  generate->add_option("--shard-size", ga.shardSize, "Exemplars per shard (default 256)")
    ->check(CLI::Range(1, 1000000));
  generate->add_option("--threads", ga.threads, "Worker threads (default 0: all cores)")
    ->check(CLI::Range(0, 256));
  generate->add_option(
    "--preview", ga.preview, "Also write a contact sheet of the first exemplars");
  generate->add_option("--array", ga.array, "Point array (default: the active scalars)");
  generate->add_flag("--quiet", ga.quiet, "Do not print progress");

#ifdef DDG_WITH_TORCH
  TrainArgs ta;
  auto* train = app.add_subcommand("train",
    "Train a model on generated exemplars and write a model bundle: the Neural DVR Analyzer "
    "with the explicit-TF decoder (default; TF-parameter loss + image L1 through the "
    "differentiable ray caster, Adam 1e-3) or with the paper's U-Net renderer and PatchGAN "
    "discriminator (L = L_adv + lambda L1, Adam 2e-4, beta 0.5/0.999).");
  train->add_option("--data", ta.data, "Exemplar directory from ddg generate")->required();
  train->add_option("--out", ta.out, "Output model bundle directory")->required();
  train->add_option("--minutes", ta.minutes, "Wall-clock budget (default 10)")
    ->check(CLI::PositiveNumber);
  train->add_option("--max-iterations", ta.maxIterations,
    "Stop after this many iterations (default 0: budget only)");
  train->add_option(
    "--eval-data", ta.evalData, "Held-out exemplars to evaluate on and record in the bundle");
  train->add_option("--eval-count", ta.evalCount, "Held-out exemplars used (default 1000)");
  train->add_option("--check-count", ta.checkCount,
    "Also record the figures of the first N held-out exemplars, for quick reproduction tests "
    "(default 100)");
  train
    ->add_option("--kind", ta.kind,
      "decoder (default): latent -> explicit Gaussian-primitive TF, ray cast (what ParaView is "
      "given); unet: the paper's U-Net renderer with a PatchGAN discriminator")
    ->check(CLI::IsMember({ "unet", "decoder" }));
  train->add_option("--volume", ta.volume,
    "The volume the decoder ray casts (default: the file the data was generated from)");
  train->add_option("--image-weight", ta.imageWeight,
    "Decoder: weight of the image L1 through the differentiable ray caster, added to the "
    "TF-parameter loss (default 100; 0: parameters only)");
  train->add_option("--image-rays", ta.imageRays, "Decoder: random pixels per exemplar in the "
                                                  "image loss (default 512)")
    ->check(CLI::Range(1, 1 << 20));
  train->add_option("--width", ta.width, "Channels of the first block (default 16)")
    ->check(CLI::Range(2, 256));
  train->add_option("--latent", ta.latent, "Latent TF size (default 64)")
    ->check(CLI::Range(2, 1024));
  train->add_option("--dropout", ta.dropout, "Dropout in the renderer's up blocks (default 0.5)");
  train->add_option("--batch", ta.batch, "Batch size (default 16)")->check(CLI::Range(1, 4096));
  train->add_option("--lr", ta.lr, "Adam learning rate (default 1e-3 decoder, 2e-4 unet)")
    ->check(CLI::PositiveNumber);
  train->add_option("--lambda", ta.lambda, "Weight of the L1 term (default 1000)");
  train->add_option("--seed", ta.seed, "Seed of initialisation and batch order (default 1)");
  train->add_option("--threads", ta.threads, "libtorch threads (default 0: all cores)");
  train->add_option(
    "--checkpoint", ta.checkpoint, "Checkpoint file, written every 500 iterations and at the end");
  train->add_flag("--resume", ta.resume, "Continue from --checkpoint");
  train->add_flag("--cosine", ta.cosine,
    "Cosine learning-rate schedule down to 5 % at --max-iterations (which it needs)");
  train->add_flag("--quiet", ta.quiet, "Do not print progress");

  std::string evalModel, evalData, evalPerExemplar;
  int evalCount = 1000;
  bool evalJson = false;
  std::string evalVolume;
  auto* evalCmd = app.add_subcommand(
    "eval", "Evaluate a model bundle on held-out exemplars: PSNR, SSIM, EMD, invariance, latency.");
  evalCmd->add_option("--model", evalModel, "Model bundle directory")->required();
  evalCmd->add_option("--data", evalData, "Held-out exemplar directory (same volume)")->required();
  evalCmd->add_option("--count", evalCount, "Exemplars used (default 1000)");
  evalCmd->add_flag("--json", evalJson, "Print the figures as JSON");
  evalCmd->add_option("--per-exemplar", evalPerExemplar,
    "Also write every exemplar's PSNR, SSIM and EMD to this CSV file");
  evalCmd->add_option(
    "--volume", evalVolume, "The volume (needed for decoder bundles, which ray cast their TFs)");

  ValidityArgs vda;
  auto* validity = app.add_subcommand("validity",
    "Design-space validity (paper 7.2.2): random latents rendered by the model next to the "
    "nearest training designs (cosine and Euclidean), as a PNG sheet with PSNRs.");
  validity->add_option("--model", vda.model, "Model bundle directory")->required();
  validity->add_option("--volume", vda.volume, "The bundle's volume")->required();
  validity->add_option("--out", vda.out, "Output sheet (PNG)")->required();
  validity->add_option("--count", vda.count, "Random latents (rows; default 6)")
    ->check(CLI::Range(1, 1000));
  validity->add_option("--view", vda.view, "View JSON (default: the volume's default view)");
  validity->add_option("--size", vda.size, "Image size without --view (default 128)")
    ->check(CLI::Range(8, 4096));
  validity->add_option("--seed", vda.seed, "Seed of the random latents (default 1)");
#endif

  std::string infoVolume, infoArray;
  auto* info = app.add_subcommand(
    "info", "Print a volume's dimensions, spacing, type, range and ParaView's defaults.");
  info->add_option("--volume", infoVolume, "Volume file")->required();
  info->add_option("--array", infoArray, "Point array (default: the active scalars)");

  const auto runGalleryCommand = addGalleryCommands(app);

  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::ParseError& e)
  {
    return app.exit(e);
  }

  const std::string name = app.get_subcommands().front()->get_name();
  try
  {
    if (*render)
      return runRender(ra);
    if (*compare)
      return runCompare(ca);
    if (*viewCmd)
      return runView(va);
    if (*info)
      return runInfo(infoVolume, infoArray);
    if (*reconstruct)
      return runReconstruct(rc);
    if (*generate)
      return runGenerate(ga);
#ifdef DDG_WITH_TORCH
    if (*train)
      return runTrain(ta);
    if (*evalCmd)
      return runEval(evalModel, evalData, evalCount, evalJson, evalVolume, evalPerExemplar);
    if (*validity)
      return runValidity(vda);
#endif
    const int code = runGalleryCommand();
    if (code >= 0)
      return code;
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "ddg %s: error: %s\n", name.c_str(), e.what());
    return 1;
  }
  return 0;
}
