// TestShippedGallery.cxx: the gallery operations on a shipped bundle with its outline.
//
// What is compared with what:
//  - Interpolation: the navigation grid's corner cells render exactly the anchor designs
//    (identical images) and the middle of a two-design line differs from both.
//  - Recolour edit: for 20 designs spread over the outline, the largest colour cluster of the
//    design's render is rotated by +90 degrees of hue and re-analyzed; the decoded primitive of
//    the region that showed that colour (nearest in CIELAB among visible regions) must move its
//    hue towards the requested one, compared with re-analyzing the unedited render (so only the
//    edit differs). Passes when >= 75 % of the designs move the right way (measured: see the
//    printed fraction; random moves would give ~50 %).
//  - Feature lock: a locked region's primitive is the lock's, whatever the latent.
//  - Query against the picture: the figure is the better of the design unlit and lit, whatever
//    the view's lighting (designs' own renders as pictures, unlit and lit).
//  - Designs against a picture in one call: each figure equals the call for that design alone,
//    and a design's own render as the picture scores it above two others.
//  - The filters' bundle cache: a volume handed over again (a shallow copy) keeps its version,
//    a changed array or spacing does not; a bundle rewritten in place is opened again.
//  - Fidelity: a design's neural image (the decoder's ray cast) against ParaView's table of its
//    exported preset: PSNR >= 35 dB (the preset's control points reproduce the design).
// Usage: TestShippedGallery MODEL_DIR VOLUME
#include "DDGVolumeAdaptor.h"

#include "Gallery/BundleSession.h"
#include "Gallery/Gallery.h"
#include "Image/ImageMetrics.h"
#include "TransferFunction/ColorSpace.h"

#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLImageDataReader.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include <unistd.h>

namespace
{
std::string gModel, gVolume;

struct Shipped
{
  ddg::Volume volume;
  ddg::NeuralDesignModel model;
  ddg::DesignGallery gallery;
  Shipped()
    : volume(ddg::readVolumeFile(gVolume))
    , model(ddg::NeuralDesignModel::loadBundle(gModel, ddg::volumeFingerprint(volume)))
    , gallery(model, volume, ddg::readLatentSet(ddg::outlineFile(gModel)))
  {
  }
};

Shipped& shipped()
{
  static Shipped s;
  return s;
}

double hueOf(const std::array<double, 3>& rgb)
{
  return ddg::rgbToHsv(rgb)[0] * 360.0;
}

double hueDistance(double a, double b)
{
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}
} // namespace

TEST(ShippedGallery, InterpolationEndpointsAreTheDesigns)
{
  auto& s = shipped();
  const ddg::View view = ddg::defaultView(s.volume, 64, 64);
  const auto a = s.gallery.latent(10), b = s.gallery.latent(20000);
  const auto cells = ddg::navigationGrid({ a, b }, 1, 3);
  const auto ia = s.gallery.render(a, view), ib = s.gallery.render(b, view);
  EXPECT_EQ(s.gallery.render(cells[0].latent, view).pixels, ia.pixels);
  EXPECT_EQ(s.gallery.render(cells[2].latent, view).pixels, ib.pixels);
  const auto mid = s.gallery.render(cells[1].latent, view);
  EXPECT_NE(mid.pixels, ia.pixels);
  EXPECT_NE(mid.pixels, ib.pixels);
}

TEST(ShippedGallery, RecolourMovesTheRegionsHue)
{
  auto& s = shipped();
  if (s.model.config().kind != "decoder")
    GTEST_SKIP() << "the U-Net model has no explicit TF to check";
  const ddg::View view = ddg::defaultView(s.volume, 128, 128);
  const int designs = 20, step = s.gallery.outline().count() / designs;
  int moved = 0, counted = 0;
  for (int k = 0; k < designs; ++k)
  {
    const auto z = s.gallery.latent(k * step);
    const ddg::Image image = s.gallery.render(z, view);
    const auto clusters = ddg::colorClusters(image, 3);
    const auto colour = ddg::labToRgb(clusters.lab[0]);
    if (ddg::rgbToHsv(colour)[1] < 0.15)
      continue; // a grey feature has no hue to rotate
    const std::array<double, 3> black{ 0, 0, 0 };
    const auto before = s.gallery.regionPrimitives(s.gallery.analyzeEdit(image, black));
    const auto after = s.gallery.regionPrimitives(
      s.gallery.analyzeEdit(ddg::recolour(image, clusters, { 0, {} }, 90), black));
    // the region that showed the cluster's colour
    int region = -1;
    double best = 1e9;
    for (size_t r = 0; r < before.size(); ++r)
    {
      if (before[r].opacity < 0.05)
        continue;
      const auto lab = ddg::rgbToLab(before[r].rgb);
      double d = 0;
      for (int c = 0; c < 3; ++c)
        d += (lab[c] - clusters.lab[0][c]) * (lab[c] - clusters.lab[0][c]);
      if (d < best)
      {
        best = d;
        region = static_cast<int>(r);
      }
    }
    if (region < 0)
      continue;
    const double target = hueOf(colour) + 90;
    const double d0 = hueDistance(hueOf(before[region].rgb), target);
    const double d1 = hueDistance(hueOf(after[region].rgb), target);
    ++counted;
    moved += d1 < d0;
  }
  const double fraction = counted ? static_cast<double>(moved) / counted : 0;
  std::printf("recolour +90 deg: %d of %d designs moved their region's hue towards the target "
              "(%.0f %%)\n",
    moved, counted, 100 * fraction);
  ASSERT_GE(counted, 10) << "too few coloured designs to judge";
  EXPECT_GE(fraction, 0.75);
}

TEST(ShippedGallery, LockedRegionsStayFixed)
{
  auto& s = shipped();
  if (s.model.config().kind != "decoder")
    GTEST_SKIP();
  const auto lock = s.gallery.lockRegions(s.gallery.latent(7), { 0 });
  for (int row : { 100, 30000 })
  {
    const auto prims = s.gallery.regionPrimitives(s.gallery.latent(row), &lock);
    EXPECT_EQ(prims[0].rgb, lock.primitives[0].rgb);
    EXPECT_EQ(prims[0].mean, lock.primitives[0].mean);
    EXPECT_EQ(prims[0].opacity, lock.primitives[0].opacity);
  }
  EXPECT_THROW(s.gallery.lockRegions(s.gallery.latent(7), { 99 }), ddg::Error);
}

TEST(ShippedGallery, ExportedPresetReproducesTheDesign)
{
  auto& s = shipped();
  const ddg::View view = ddg::defaultView(s.volume, 96, 96);
  for (int row : { 5, 12345, 40000 })
  {
    const auto f = s.gallery.fidelity(s.gallery.latent(row), view);
    std::printf("design %d: neural vs ParaView table of its preset: PSNR %.2f dB, SSIM %.4f\n", row,
      f.psnr, f.ssim);
    EXPECT_GE(f.psnr, 35.0);
  }
}

// The query's figure against the picture does not depend on the lighting of the view it is
// asked at (a lit scene queried with an unlit picture scored the lighting, not the design): it
// is the better of the design unlit and lit, and says which. The pictures are designs' own
// renders, unlit and lit with ParaView's coefficients. (Which lighting scores better is not an
// estimate of the picture's: the query's design is near the picture's, not the same, and the
// two figures are often within a decibel.)
TEST(ShippedGallery, QueryAgainstThePictureTakesTheBetterLighting)
{
  auto& s = shipped();
  const ddg::View unlit = ddg::defaultView(s.volume, 128, 128);
  ddg::View lit = unlit;
  lit.lighting.shade = true;
  int litWins = 0;
  for (int row : { 5, 12345, 40000 })
  {
    for (const bool pictureLit : { false, true })
    {
      const ddg::View& shown = pictureLit ? lit : unlit;
      const ddg::Image picture = ddg::compositeOverBackground(
        s.gallery.render(s.gallery.latent(row), shown), shown.background);
      const auto atUnlit = s.gallery.query(picture, unlit, 0);
      const auto atLit = s.gallery.query(picture, lit, 0);
      // each preview is at its view's lighting; the figure is the better of the two
      const double unlitOnly = ddg::framedPSNR(picture, atUnlit.preview);
      const double litOnly = ddg::framedPSNR(picture, atLit.preview);
      std::printf("design %d, picture %s: against the picture %.2f dB (design %s) at an unlit "
                  "view, %.2f dB (design %s) at a lit one; the previews alone: unlit %.2f dB, lit "
                  "%.2f dB\n",
        row, pictureLit ? "lit" : "unlit", atUnlit.picturePSNR,
        atUnlit.pictureLit ? "lit" : "unlit", atLit.picturePSNR, atLit.pictureLit ? "lit" : "unlit",
        unlitOnly, litOnly);
      EXPECT_NE(unlitOnly, litOnly); // the lighting shows in the previews
      EXPECT_DOUBLE_EQ(atUnlit.picturePSNR, std::max(unlitOnly, litOnly));
      EXPECT_DOUBLE_EQ(atLit.picturePSNR, atUnlit.picturePSNR);
      EXPECT_EQ(atUnlit.pictureLit, litOnly > unlitOnly);
      EXPECT_EQ(atLit.pictureLit, atUnlit.pictureLit);
      litWins += atUnlit.pictureLit ? 1 : 0;
    }
  }
  std::printf("the lit design scored better on %d of 6 pictures\n", litWins);
}

// Designs against a picture in one call (the panel's nearest designs, DDG Query's
// NeighbourPicturePSNR column): each figure is the one a call for that design alone gives (the
// picture framed once for all), and the picture's own design scores above the others.
TEST(ShippedGallery, DesignsAgainstAPictureInOneCall)
{
  auto& s = shipped();
  const ddg::View view = ddg::defaultView(s.volume, 128, 128);
  const int own = 12345;
  const ddg::Image picture =
    ddg::compositeOverBackground(s.gallery.render(s.gallery.latent(own), view), view.background);
  const std::vector<int> rows{ 5, own, 40000 };
  std::vector<std::vector<float>> latents;
  for (int row : rows)
    latents.push_back(s.gallery.latent(row));
  std::vector<bool> lit;
  const auto figures = s.gallery.picturePSNR(picture, latents, view, &lit);
  ASSERT_EQ(figures.size(), 3u);
  ASSERT_EQ(lit.size(), 3u);
  for (size_t i = 0; i < rows.size(); ++i)
  {
    std::vector<bool> alone;
    EXPECT_DOUBLE_EQ(
      s.gallery.picturePSNR(picture, { latents[i] }, view, &alone).front(), figures[i]);
    EXPECT_EQ(alone.front(), lit[i]);
    std::printf("design %d against design %d's picture: %.2f dB (%s)\n", rows[i], own, figures[i],
      lit[i] ? "lit" : "unlit");
  }
  EXPECT_GT(figures[1], figures[0]);
  EXPECT_GT(figures[1], figures[2]);
  EXPECT_FALSE(lit[1]); // the picture is the design unlit
  EXPECT_TRUE(s.gallery.picturePSNR(picture, {}, view).empty());
}

// The filters open a bundle once per volume (BundleSessionCache keyed by volumeVersion): the
// input ParaView hands a filter is copied again at every request (a new modification time), so
// the version is of what the volume is made of: a shallow copy has the same version, a modified
// array or new spacing another. A bundle rewritten in place (a file's time changed) is opened
// again; the same bundle and version give the same session without loading the volume again.
TEST(ShippedGallery, FiltersOpenTheBundleOncePerVolume)
{
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(gVolume.c_str());
  reader->Update();
  vtkImageData* read = reader->GetOutput();
  vtkNew<vtkImageData> copy, again;
  copy->ShallowCopy(read);
  again->ShallowCopy(read);
  ASSERT_NE(copy->GetMTime(), again->GetMTime());
  const std::uint64_t version = ddg::volumeVersion(copy);
  EXPECT_NE(version, 0u);
  EXPECT_EQ(ddg::volumeVersion(again), version);
  EXPECT_EQ(ddg::volumeVersion(read, read->GetPointData()->GetScalars()), version);
  EXPECT_EQ(ddg::volumeVersion(nullptr), 0u);
  double spacing[3];
  again->GetSpacing(spacing);
  again->SetSpacing(2 * spacing[0], spacing[1], spacing[2]);
  EXPECT_NE(ddg::volumeVersion(again), version);
  again->ShallowCopy(read);
  again->GetPointData()->GetScalars()->Modified(); // the values changed in place
  const std::uint64_t modified = ddg::volumeVersion(again);
  EXPECT_NE(modified, version);
  vtkDataArray* scalars = again->GetPointData()->GetScalars();
  vtkSmartPointer<vtkDataArray> values =
    vtkSmartPointer<vtkDataArray>::Take(scalars->NewInstance());
  values->DeepCopy(scalars);
  scalars->ShallowCopy(values); // the same array object over new memory
  EXPECT_NE(ddg::volumeVersion(again), modified);

  namespace fs = std::filesystem;
  const fs::path bundle = fs::temp_directory_path() /
    ("ddg_bundle_cache_" + std::to_string(static_cast<long long>(::getpid())));
  fs::remove_all(bundle);
  struct Remove // the copy goes whatever fails below
  {
    fs::path path;
    ~Remove() { fs::remove_all(path); }
  } removeCopy{ bundle };
  fs::copy(gModel, bundle, fs::copy_options::recursive);
  int loads = 0;
  auto load = [&]
  {
    ++loads;
    return ddg::toCoreVolume(copy);
  };
  ddg::BundleSessionCache cache;
  ddg::BundleSession* first = &cache.get(bundle.string(), modified, load);
  EXPECT_EQ(&cache.get(bundle.string(), modified, load), first);
  EXPECT_EQ(loads, 1);
  const fs::path key = bundle / "query_key.json";
  fs::last_write_time(key, fs::last_write_time(key) + std::chrono::seconds(2));
  cache.get(bundle.string(), modified, load);
  EXPECT_EQ(loads, 2); // rewritten in place: opened again
  cache.get(bundle.string(), modified, load);
  EXPECT_EQ(loads, 2);
  cache.get(bundle.string(), version, load);
  EXPECT_EQ(loads, 3); // another volume version
  cache.clear();
}

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  if (argc < 3)
  {
    std::fprintf(stderr, "usage: TestShippedGallery MODEL_DIR VOLUME\n");
    return 2;
  }
  gModel = argv[1];
  gVolume = argv[2];
  return RUN_ALL_TESTS();
}
