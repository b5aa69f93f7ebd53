// BenchGallery.cxx: the design gallery's interactive costs on 2 cores, against the bars of
// issue 5 (median of N runs, printed with the ratio to the bar; asserts nothing):
//  (a) PCA + layout of the outline's latents (the shipped bundle's outline.bin, >= 50 000)  <= 0.5
//  s (b) K = 64 thumbnails chosen over the whole outline (farthest-point sampling)           (no
//  bar) (c) one query: image -> analyzer -> latent -> outline position + 5 neighbours -> preview
//      at 128 x 128                                                                        <= 50 ms
//      and side by side its steps: the picture read for the analyzer and for the check, the
//      analyzer, the design lit and unlit from one march (and beside it, the two renders it
//      replaces: the view's lighting and the other), their figures
//  (d) screenshot -> explicit TF file: (c) plus the decoded TF written as a ParaView preset <= 3 s
//  (e) (c) with a GUI screenshot: 1024 x 768 over ParaView's palette grey-blue with orientation
//      axes in the corner (no bar), and side by side its steps on that picture: the analyzer's
//      input (prepareQueryImage), the picture's check (checkQueryPicture), the figure against the
//      picture of one render (framedPSNR); the picture's check at 800 x 600 and 1000 x 700
// Usage: BenchGallery [MODEL_DIR [VOLUME [RUNS]]]   (default: the shipped Tooth bundle)
#include "DDGVolumeAdaptor.h"

#include "Gallery/Export.h"
#include "Gallery/Gallery.h"
#include "Gallery/QueryImage.h"
#include "Reconstruct/CarryLook.h"
#include "Render/View.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

using namespace ddg;
namespace
{
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
// The median milliseconds of `runs` calls of f.
template <typename F>
double medianMs(int runs, const F& f)
{
  std::vector<double> t;
  for (int r = 0; r < runs; ++r)
  {
    const auto t0 = Clock::now();
    f();
    t.push_back(msSince(t0));
  }
  return median(t);
}
void row(const char* what, double ms, double barMs)
{
  if (barMs > 0)
    std::printf("%-58s %9.2f ms   bar %6.0f ms   ratio %.3f\n", what, ms, barMs, ms / barMs);
  else
    std::printf("%-58s %9.2f ms\n", what, ms);
}
} // namespace

int main(int argc, char** argv)
{
  const std::string data = DDG_DATA_DIR;
  const std::string modelDir = argc > 1 ? argv[1] : data + "/Models/tooth";
  const std::string volumePath = argc > 2 ? argv[2] : data + "/Volumes/tooth.vti";
  const int runs = argc > 3 ? std::max(1, std::atoi(argv[3])) : 5;
  try
  {
    const Volume volume = readVolumeFile(volumePath);
    auto model = NeuralDesignModel::loadBundle(modelDir, volumeFingerprint(volume));
    const LatentSet latents = readLatentSet(outlineFile(modelDir));
    std::printf("gallery benchmark: %s (%s, %d outline latents of %d), %d runs, median\n",
      modelDir.c_str(), model.config().kind.c_str(), latents.count(), latents.dim, runs);

    std::vector<double> pca, pick, query, file;
    std::unique_ptr<DesignGallery> gallery;
    for (int r = 0; r < runs; ++r)
    {
      const auto t0 = Clock::now();
      gallery = std::make_unique<DesignGallery>(model, volume, latents);
      const auto box = gallery->outline().bounds();
      pca.push_back(msSince(t0));
      const auto t1 = Clock::now();
      const auto rows = selectThumbnails(gallery->outline(), box, 64, r + 1);
      pick.push_back(msSince(t1));
    }
    row("(a) PCA + layout of the outline", median(pca), 500);
    row("(b) 64 thumbnails chosen (farthest-point sampling)", median(pick), 0);

    // the query image: a design of the outline rendered at another view, as a screenshot
    View view = defaultView(volume, 128, 128);
    const Exemplar e = gallery->exemplar(gallery->outline().count() / 2);
    View shot = e.viewView;
    shot.width = shot.height = 512;
    const RayCaster caster(volume);
    const int dims = model.spec().dimensions;
    const auto gradientRange =
      dims == 2 ? volume.gradientMagnitudeRange() : std::array<double, 2>{ 0.0, 1.0 };
    const Image screenshot = compositeOverBackground(
      renderDesign(caster, e.primitives, dims, gradientRange, shot), { 1.0, 1.0, 1.0 });
    const auto out = (std::filesystem::temp_directory_path() / "ddg_bench_query.json").string();
    for (int r = 0; r < runs; ++r)
    {
      const auto t0 = Clock::now();
      const auto q = gallery->query(screenshot, view, 5);
      query.push_back(msSince(t0));
      if (model.config().kind == "decoder")
      {
        exportTransferFunction(primitivesToTransferFunction(gallery->primitives(q.latent), dims,
                                 volume.range(), gradientRange, "bench"),
          out, "paraview", volume.range(), caster.defaultOpacityUnitDistance());
        file.push_back(msSince(t0));
      }
    }
    row("(c) query 512x512 screenshot -> latent, 5 neighbours, 128^2 preview", median(query), 50);
    // its steps side by side: the picture read twice (the analyzer's input, the check), the
    // analyzer, the design lit and unlit from one march (beside it, as two renders in the view's
    // lighting and the other), both framed against it
    std::vector<double> cPrepare, cCheck, cAnalyze, cRender, cOther, cBoth, cFramed;
    for (int r = 0; r < runs; ++r)
    {
      auto t0 = Clock::now();
      const Image input = prepareQueryImage(screenshot, model.config().imageSize);
      cPrepare.push_back(msSince(t0));
      t0 = Clock::now();
      (void)checkQueryPicture(screenshot);
      cCheck.push_back(msSince(t0));
      t0 = Clock::now();
      const std::vector<float> latent = model.analyze(input);
      cAnalyze.push_back(msSince(t0));
      View other = view;
      other.lighting.shade = !view.lighting.shade;
      // what the query does: both from one march; timed before the two renders on every other
      // run, so neither side always has the other's warm caches
      auto oneMarch = [&]
      {
        if (model.config().kind != "decoder")
          return;
        const auto m0 = Clock::now();
        (void)gallery->renderBothLightings(latent, view, other);
        cBoth.push_back(msSince(m0));
      };
      if (r % 2 == 0)
        oneMarch();
      t0 = Clock::now();
      const Image here = gallery->render(latent, view);
      cRender.push_back(msSince(t0));
      t0 = Clock::now();
      const Image there = gallery->render(latent, other);
      cOther.push_back(msSince(t0));
      if (r % 2 == 1)
        oneMarch();
      t0 = Clock::now();
      (void)framedPSNR(screenshot, std::vector<const Image*>{ &here, &there });
      cFramed.push_back(msSince(t0));
    }
    row("    of which: the analyzer's input (prepareQueryImage)", median(cPrepare), 0);
    row("    of which: the picture's check (checkQueryPicture)", median(cCheck), 0);
    row("    of which: the analyzer", median(cAnalyze), 0);
    if (!cBoth.empty())
      row("    of which: the design lit and unlit, one 128^2 march", median(cBoth), 0);
    const std::string first = cBoth.empty() ? "    of which: " : "      two renders instead: ";
    row((first + (view.lighting.shade ? "the view's lighting, lit" : "the view's lighting, unlit"))
          .c_str(),
      median(cRender), 0);
    row((first + (view.lighting.shade ? "the other lighting, unlit" : "the other lighting, lit"))
          .c_str(),
      median(cOther), 0);
    row("    of which: both renders against the picture (framedPSNR)", median(cFramed), 0);
    if (!file.empty())
      row("(d) screenshot -> explicit TF file (ParaView preset)", median(file), 3000);

    // (e) the same design as ParaView's GUI saves it: 1024 x 768, the palette's grey-blue, a
    // red and a green axis in the lower left corner
    auto overPalette = [&](int w, int h)
    {
      shot.width = w;
      shot.height = h;
      return compositeOverBackground(
        renderDesign(caster, e.primitives, dims, gradientRange, shot), { 0.32, 0.34, 0.43 });
    };
    Image gui = overPalette(1024, 768);
    for (int y = 700; y < 740; ++y)
      for (int x = 30; x < 34; ++x)
        gui.at(x, y, 1) = 0.8f;
    for (int y = 736; y < 740; ++y)
      for (int x = 30; x < 70; ++x)
        gui.at(x, y, 0) = 0.9f;
    QueryResult q;
    row("(e) query 1024x768 GUI screenshot (palette, axes), as (c)",
      medianMs(runs, [&] { q = gallery->query(gui, view, 5); }), 0);
    row("    of which: the analyzer's input (prepareQueryImage)",
      medianMs(runs, [&] { (void)prepareQueryImage(gui, model.config().imageSize); }), 0);
    row("    of which: the picture's check (checkQueryPicture)",
      medianMs(runs, [&] { (void)checkQueryPicture(gui); }), 0);
    row("    of which: one render against the picture (framedPSNR)",
      medianMs(runs, [&] { (void)framedPSNR(gui, q.preview); }), 0);
    // the picture's check at sizes that are not twice 512 (a filtered resize took 130-200 ms)
    for (const auto& [w, h] : { std::pair<int, int>{ 800, 600 }, { 1000, 700 } })
    {
      const Image other = overPalette(w, h);
      const std::string what =
        "    the picture's check of a " + std::to_string(w) + "x" + std::to_string(h) + " one";
      row(what.c_str(), medianMs(runs, [&] { (void)checkQueryPicture(other); }), 0);
    }
    std::filesystem::remove(out);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "BenchGallery: %s\n", e.what());
    return 1;
  }
  return 0;
}
