// BenchRayCaster.cxx: our forward render vs VTK's CPU ray caster (vtkFixedPointVolumeRayCastMapper,
// ParaView's "Ray Cast Only"), same volume, TF, camera, image size and sample distance, timed in
// one process; median of N runs each. Prints both times, the ratio and samples/second per core.
//
// Usage (needs an X display for VTK's render window: run under xvfb-run -a):
//   BenchRayCaster [--volume Data/Volumes/engine.vti] [--tf
//   Data/TransferFunctions/engine_block.json]
//                  [--view Data/Views/engine_oblique.json] [--size 512] [--runs 7] [--threads 0]
#include "DDGVolumeAdaptor.h"

#include "Common/Parallel.h"
#include "Image/ImageMetrics.h"
#include "Render/RayCaster.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <vtkCamera.h>
#include <vtkColorTransferFunction.h>
#include <vtkFixedPointVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkLightKit.h>
#include <vtkNew.h>
#include <vtkPiecewiseFunction.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkUnsignedCharArray.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>
#include <vtkXMLImageDataReader.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

template <typename F>
double timeOnce(F&& f)
{
  const auto t0 = Clock::now();
  f();
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

template <typename F>
std::vector<double> timeRuns(int runs, F&& f)
{
  f(); // warm-up
  std::vector<double> ms;
  for (int i = 0; i < runs; ++i)
    ms.push_back(timeOnce(f));
  return ms;
}
} // namespace

int main(int argc, char** argv)
{
  std::string dataDir = DDG_DATA_DIR;
  std::string volumePath = dataDir + "/Volumes/engine.vti";
  std::string tfPath = dataDir + "/TransferFunctions/engine_block.json";
  std::string viewPath = dataDir + "/Views/engine_oblique.json";
  int size = 512, runs = 7, threads = 0;
  double samplesPerVoxel = 2; // ParaView's rule: sample distance = mean spacing / 2
  bool shade = false;
  for (int i = 1; i < argc; i += 2)
  {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h")
    {
      std::printf(
        "BenchRayCaster [--volume V.vti] [--tf PRESET.json] [--view VIEW.json] [--size N]\n"
        "               [--runs N>=5] [--threads N] [--samples-per-voxel S] [--shade on|off]\n"
        "Times ddg's ray caster and VTK's vtkFixedPointVolumeRayCastMapper on the same\n"
        "volume, TF, camera (VIEW.json at N x N) and sample distance; prints medians,\n"
        "the ratio and samples/s per core. Needs a display: run under xvfb-run -a.\n"
        "Sample distance = mean spacing / S (S = 2 is ParaView's rule).\n"
        "--shade on: also times ddg lit (the view's lighting coefficients, ParaView's light\n"
        "kit) against itself unlit at the same samples, and renders VTK's mapper with Shade\n"
        "on and ParaView's light kit (default: off).\n"
        "Defaults: Data/Volumes/engine.vti, engine_block.json, engine_oblique.json, 512, 7, all "
        "cores, 2.\n");
      return 0;
    }
    if (i + 1 >= argc)
    {
      std::fprintf(stderr, "option %s needs a value\n", a.c_str());
      return 2;
    }
    if (a == "--volume")
      volumePath = argv[i + 1];
    else if (a == "--tf")
      tfPath = argv[i + 1];
    else if (a == "--view")
      viewPath = argv[i + 1];
    else if (a == "--size")
      size = std::stoi(argv[i + 1]);
    else if (a == "--runs")
      runs = std::max(5, std::stoi(argv[i + 1]));
    else if (a == "--threads")
      threads = std::stoi(argv[i + 1]);
    else if (a == "--samples-per-voxel")
      samplesPerVoxel = std::stod(argv[i + 1]);
    else if (a == "--shade" &&
      (std::strcmp(argv[i + 1], "on") == 0 || std::strcmp(argv[i + 1], "off") == 0))
      shade = std::strcmp(argv[i + 1], "on") == 0;
    else
    {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const int nThreads = threads > 0 ? threads : ddg::defaultThreadCount();

  // --- shared inputs ---------------------------------------------------------------------------
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(volumePath.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  const ddg::Volume volume = ddg::toCoreVolume(image);
  const ddg::TransferFunction1D tf = ddg::readPreset(tfPath);
  ddg::View view = ddg::readView(viewPath);
  view.width = view.height = size;
  const ddg::Lighting lighting = view.lighting; // the coefficients of --shade on
  view.lighting.shade = false;
  const ddg::RayCaster caster(volume);
  if (!(samplesPerVoxel > 0))
  {
    std::fprintf(stderr, "--samples-per-voxel must be positive\n");
    return 2;
  }
  const double d = caster.defaultSampleDistance() * 2.0 / samplesPerVoxel;
  const double unit =
    view.opacityUnitDistance ? *view.opacityUnitDistance : caster.defaultOpacityUnitDistance();

  // --- ours -------------------------------------------------------------------------------------
  ddg::RenderOptions opt;
  opt.threads = nThreads;
  opt.sampleDistance = d;
  const ddg::TransferTable1D table = caster.paraviewTable(tf);
  ddg::Image ours;
  ddg::RenderStats stats;
  const auto oursMs = timeRuns(runs, [&] { ours = caster.render(table, view, opt, {}, &stats); });
  ddg::RenderOptions noSkip = opt;
  noSkip.emptySpaceSkipping = false;
  ddg::RenderStats statsNoSkip;
  const auto oursNoSkipMs =
    timeRuns(runs, [&] { caster.render(table, view, noSkip, {}, &statsNoSkip); });
  // Shade on: the first lit render alone, then lit and unlit alternated run by run (a slow spell
  // of the machine then hits both alike): the lit median, and the ratio of each pair
  ddg::View litView = view;
  litView.lighting = lighting;
  litView.lighting.shade = true;
  double firstLitMs = 0;
  std::vector<double> litMs, pairRatio;
  ddg::RenderStats litStats;
  ddg::Image oursLit;
  if (shade)
  {
    firstLitMs = timeOnce([&] { caster.render(table, litView, opt); });
    for (int r = 0; r < runs; ++r)
    {
      const double off = timeOnce([&] { caster.render(table, view, opt); });
      litMs.push_back(
        timeOnce([&] { oursLit = caster.render(table, litView, opt, {}, &litStats); }));
      pairRatio.push_back(litMs.back() / off);
    }
  }

  // --- VTK fixed-point ray caster ----------------------------------------------------------------
  vtkNew<vtkColorTransferFunction> ctf;
  for (const auto& n : tf.color)
    ctf->AddRGBPoint(n.x, n.r, n.g, n.b, n.midpoint, n.sharpness);
  switch (tf.colorSpace)
  {
    case ddg::ColorSpace::HSV:
      ctf->SetColorSpaceToHSV();
      break;
    case ddg::ColorSpace::Lab:
      ctf->SetColorSpaceToLab();
      break;
    case ddg::ColorSpace::Diverging:
      ctf->SetColorSpaceToDiverging();
      break;
    case ddg::ColorSpace::Step:
      ctf->SetColorSpaceToStep();
      break;
    default:
      ctf->SetColorSpaceToRGB();
  }
  vtkNew<vtkPiecewiseFunction> pwf;
  for (const auto& n : tf.opacity)
    pwf->AddPoint(n.x, n.alpha, n.midpoint, n.sharpness);
  vtkNew<vtkVolumeProperty> property;
  property->SetColor(ctf);
  property->SetScalarOpacity(pwf);
  property->SetScalarOpacityUnitDistance(unit);
  property->SetInterpolationTypeToLinear();
  if (shade)
  {
    property->ShadeOn();
    property->SetAmbient(view.lighting.ambient);
    property->SetDiffuse(view.lighting.diffuse);
    property->SetSpecular(view.lighting.specular);
    property->SetSpecularPower(view.lighting.specularPower);
  }
  else
  {
    property->ShadeOff();
  }
  vtkNew<vtkFixedPointVolumeRayCastMapper> mapper;
  mapper->SetInputData(image);
  mapper->SetAutoAdjustSampleDistances(0);
  mapper->SetLockSampleDistanceToInputSpacing(0);
  mapper->SetSampleDistance(static_cast<float>(d));
  mapper->SetImageSampleDistance(1.0f);
  mapper->SetNumberOfThreads(nThreads);
  vtkNew<vtkVolume> actor;
  actor->SetMapper(mapper);
  actor->SetProperty(property);
  vtkNew<vtkRenderer> renderer;
  renderer->AddVolume(actor);
  renderer->SetBackground(view.background[0], view.background[1], view.background[2]);
  vtkNew<vtkLightKit> lightKit; // ParaView's render view lights the scene with its light kit
  if (shade)
  {
    renderer->SetAutomaticLightCreation(0);
    lightKit->AddLightsToRenderer(renderer);
  }
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(size, size);
  window->AddRenderer(renderer);
  vtkCamera* cam = renderer->GetActiveCamera();
  cam->SetPosition(view.camera.position.data());
  cam->SetFocalPoint(view.camera.focalPoint.data());
  cam->SetViewUp(view.camera.viewUp.data());
  cam->SetViewAngle(view.camera.viewAngle);
  cam->SetParallelProjection(view.camera.parallelProjection);
  cam->SetParallelScale(view.camera.parallelScale);
  renderer->ResetCameraClippingRange();
  std::vector<double> vtkDrawMs;
  const auto vtkMs = timeRuns(runs,
    [&]
    {
      window->Render();
      vtkDrawMs.push_back(1000.0 * mapper->GetTimeToDraw());
    });
  vtkDrawMs.erase(vtkDrawMs.begin()); // warm-up

  // Agreement of the two images (both over the background, 8 bit).
  vtkNew<vtkUnsignedCharArray> pixels;
  window->GetPixelData(0, 0, size - 1, size - 1, 1, pixels);
  ddg::Image vtkImage(size, size, 3);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c)
        vtkImage.at(x, size - 1 - y, c) =
          pixels->GetValue((static_cast<vtkIdType>(y) * size + x) * 3 + c) / 255.0f;
  const ddg::Image oursRGB = ddg::compositeOverBackground(shade ? oursLit : ours, view.background);

  const double tOurs = median(oursMs), tOursNoSkip = median(oursNoSkipMs), tVtk = median(vtkMs),
               tVtkDraw = median(vtkDrawMs);
  const auto& dims = volume.dims();
  std::printf("volume %s (%d x %d x %d), TF %s, %d x %d, sample distance %.4g, %d threads, median "
              "of %d runs\n",
    volumePath.c_str(), dims[0], dims[1], dims[2], tfPath.c_str(), size, size, d, nThreads, runs);
  std::printf("ddg RayCaster                     %8.1f ms  (%.3g samples, %.3g skipped, %.1f "
              "Msamples/s/core)\n",
    tOurs, static_cast<double>(stats.samples), static_cast<double>(stats.skippedSamples),
    stats.samples / (tOurs * 1e3) / nThreads);
  std::printf("ddg RayCaster, no block skipping  %8.1f ms  (%.3g samples, %.1f Msamples/s/core)\n",
    tOursNoSkip, static_cast<double>(statsNoSkip.samples),
    statsNoSkip.samples / (tOursNoSkip * 1e3) / nThreads);
  if (shade)
  {
    const double tLit = median(litMs);
    std::printf("ddg RayCaster, Shade on           %8.1f ms  (%.3g samples, %.1f Msamples/s/core; "
                "first render %.1f ms; gradients per sample, no buffer)\n",
      tLit, static_cast<double>(litStats.samples), litStats.samples / (tLit * 1e3) / nThreads,
      firstLitMs);
    std::printf("Shade on / off, ddg, same samples  %.2fx\n", tLit / tOurs);
    std::printf("Shade on / off, alternated runs    %.2fx  (median of %d pairs; %.2f-%.2fx)\n",
      median(pairRatio), runs, *std::min_element(pairRatio.begin(), pairRatio.end()),
      *std::max_element(pairRatio.begin(), pairRatio.end()));
  }
  std::printf(
    "VTK FixedPointVolumeRayCastMapper %8.1f ms  (window Render%s); mapper draw time %.1f ms\n",
    tVtk, shade ? ", Shade on" : "", tVtkDraw);
  const double tCompared = shade ? median(litMs) : tOurs; // like against like
  std::printf("speed-up vs VTK (window Render)    %.2fx\n", tVtk / tCompared);
  std::printf("speed-up vs VTK (mapper draw time) %.2fx\n", tVtkDraw / tCompared);
  std::printf("image agreement ddg vs VTK fixed-point: PSNR %.2f dB, SSIM %.4f\n",
    ddg::psnr(oursRGB, vtkImage), ddg::ssim(oursRGB, vtkImage));
  return 0;
}
