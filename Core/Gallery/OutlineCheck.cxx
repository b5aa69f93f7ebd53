// OutlineCheck.cxx: a sample of outline designs judged empty / flat box / showing structure.
#include "Gallery/OutlineCheck.h"

#include "Common/Error.h"
#include "Common/Parallel.h"

#include <algorithm>
#include <numeric>
#include <random>

namespace ddg
{

OutlineCheck checkOutline(
  DesignGallery& gallery, int count, std::uint64_t seed, int size, int threads)
{
  if (count < 1)
    throw Error("an outline check needs at least one design");
  const int n = gallery.outline().count();
  std::vector<int> rows(static_cast<size_t>(n));
  std::iota(rows.begin(), rows.end(), 0);
  std::mt19937_64 rng(seed);
  std::shuffle(rows.begin(), rows.end(), rng);
  rows.resize(static_cast<size_t>(std::min(count, n)));
  std::sort(rows.begin(), rows.end());

  const auto& volume = gallery.volume();
  const int dims = gallery.model().spec().dimensions;
  const auto gradientRange =
    dims == 2 ? volume.gradientMagnitudeRange() : std::array<double, 2>{ 0.0, 1.0 };
  const bool explicitTf = gallery.model().config().kind == "decoder";
  OutlineCheck check;
  check.rows = rows;
  check.verdicts.resize(rows.size());
  std::vector<Image> cells(rows.size());
  const View front = orbitView(volume, size, 0, 20, 1);
  const BoxCorners corners(volume, dims, gallery.caster().defaultOpacityUnitDistance());
  // the TFs first, on this thread (the model's decoder); then the renders in parallel
  std::vector<std::vector<GaussianPrimitive>> tfs;
  for (int row : rows)
    tfs.push_back(
      explicitTf ? gallery.primitives(gallery.latent(row)) : gallery.exemplar(row).primitives);
  parallelFor(static_cast<std::int64_t>(rows.size()), threads,
    [&](std::int64_t i, int)
    {
      const auto& tf = tfs[static_cast<size_t>(i)];
      check.verdicts[i] = judgeDesign(gallery.caster(), corners, tf, dims, gradientRange, size);
      RenderOptions options;
      options.threads = 1;
      Image cell = compositeOverBackground(
        renderDesign(gallery.caster(), tf, dims, gradientRange, front, options), { 0.5, 0.5, 0.5 });
      if (check.verdicts[i].junk())
      {
        const std::array<float, 3> frame = check.verdicts[i].empty
          ? std::array<float, 3>{ 0.2f, 0.4f, 1.0f }
          : std::array<float, 3>{ 1.0f, 0.15f, 0.1f };
        for (int y = 0; y < size; ++y)
          for (int x = 0; x < size; ++x)
            if (x < 2 || y < 2 || x >= size - 2 || y >= size - 2)
              for (int c = 0; c < 3; ++c)
                cell.at(x, y, c) = frame[c];
      }
      cells[i] = std::move(cell);
    });
  // the boundary faces' values, and each 1D design's mean opacity over them
  if (dims == 1)
  {
    const auto& n = volume.dims();
    std::vector<float> faces;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i)
          if (i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1)
            faces.push_back(volume.at(i, j, k));
    const auto range = volume.range();
    for (const auto& tf : tfs)
    {
      check.hazyFaces += meanOpacity(rasterize1D(tf, range[0], range[1], 256), faces) > 0.01;
    }
  }
  for (const auto& v : check.verdicts)
  {
    check.empty += v.empty;
    check.flatBox += v.flatBox;
  }
  check.sheet = tileImages(cells, 8);
  return check;
}

} // namespace ddg
