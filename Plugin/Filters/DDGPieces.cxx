// DDGPieces.cxx: pieces of a volume over the ranks, agreed and rendered sort-last.
#include "DDGPieces.h"

#include "DDGVolumeAdaptor.h"

#include "Render/PieceExchange.h"
#include "Render/SortLast.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkImageData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>

namespace ddg
{

VolumeBrick brickOf(vtkImageData* image, const int wholeExtent[6])
{
  VolumeBrick b;
  double origin[3] = { 0, 0, 0 }, spacing[3] = { 1, 1, 1 };
  int extent[6] = { 0, -1, 0, -1, 0, -1 };
  if (image)
  {
    image->GetOrigin(origin);
    image->GetSpacing(spacing);
    image->GetExtent(extent);
  }
  for (int a = 0; a < 3; ++a)
  {
    b.wholeDims[a] = wholeExtent[2 * a + 1] - wholeExtent[2 * a] + 1;
    b.wholeOrigin[a] = origin[a] + wholeExtent[2 * a] * spacing[a];
    b.offset[a] = extent[2 * a] - wholeExtent[2 * a];
    b.spacing[a] = spacing[a];
  }
  const bool empty = !image || image->GetNumberOfPoints() == 0 || extent[1] < extent[0] ||
    extent[3] < extent[2] || extent[5] < extent[4];
  if (empty)
    return b; // owns nothing (ownedMin = ownedMax = 0)
  // The owned points: a box (ghosts come as slabs on the sides); found from one owned point
  // along the three axes through it.
  int owned[6];
  std::copy(extent, extent + 6, owned);
  if (vtkUnsignedCharArray* ghosts = image->GetPointGhostArray())
  {
    int dims[3];
    image->GetDimensions(dims);
    auto ghost = [&](int i, int j, int k)
    {
      const vtkIdType id =
        i + static_cast<vtkIdType>(dims[0]) * (j + static_cast<vtkIdType>(dims[1]) * k);
      return (ghosts->GetValue(id) & vtkDataSetAttributes::DUPLICATEPOINT) != 0;
    };
    int p[3] = { dims[0] / 2, dims[1] / 2, dims[2] / 2 };
    bool found = !ghost(p[0], p[1], p[2]);
    for (int k = 0; k < dims[2] && !found; ++k)
      for (int j = 0; j < dims[1] && !found; ++j)
        for (int i = 0; i < dims[0] && !found; ++i)
          if (!ghost(i, j, k))
          {
            p[0] = i;
            p[1] = j;
            p[2] = k;
            found = true;
          }
    if (!found)
      return b; // all ghosts: owns nothing
    for (int a = 0; a < 3; ++a)
    {
      int q[3] = { p[0], p[1], p[2] };
      int lo = p[a], hi = p[a];
      for (q[a] = p[a]; q[a] >= 0 && !ghost(q[0], q[1], q[2]); --q[a])
        lo = q[a];
      for (q[a] = p[a]; q[a] < dims[a] && !ghost(q[0], q[1], q[2]); ++q[a])
        hi = q[a];
      owned[2 * a] = extent[2 * a] + lo;
      owned[2 * a + 1] = extent[2 * a] + hi;
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    b.ownedMin[a] = owned[2 * a] - wholeExtent[2 * a];
    b.ownedMax[a] = owned[2 * a + 1] - wholeExtent[2 * a];
  }
  return b;
}

RankVolume RankVolume::gather(const RankGroup& ranks, vtkImageData* piece, vtkDataArray* array,
  const int wholeExtent[6], bool caster, bool gradientRange)
{
  RankVolume out;
  std::unique_ptr<Volume> local;
  double range[2] = { std::numeric_limits<double>::infinity(),
    -std::numeric_limits<double>::infinity() };
  double nonFinite = 0, gradientMax = 0;
  ranks.step(
    [&]
    {
      out.brick = brickOf(piece, wholeExtent);
      if (out.brick.ownsNothing())
        return; // an empty piece, or one plane thick: contributes nothing
      local = std::make_unique<Volume>(toCoreVolume(piece, array));
      range[0] = local->range()[0];
      range[1] = local->range()[1];
      nonFinite = static_cast<double>(local->nonFiniteCount());
      if (gradientRange)
        gradientMax = out.brick.gradientMagnitudeMax(*local);
    });
  ranks.allMin(&range[0], 1);
  ranks.allMax(&range[1], 1);
  // the whole's origin and spacing as the ranks with cells have them (an empty piece's image
  // may not say)
  double geometry[6];
  for (int a = 0; a < 3; ++a)
  {
    const bool owns = !out.brick.ownsNothing();
    geometry[a] = owns ? out.brick.wholeOrigin[a] : -std::numeric_limits<double>::infinity();
    geometry[3 + a] = owns ? out.brick.spacing[a] : -std::numeric_limits<double>::infinity();
  }
  ranks.allMax(geometry, 6);
  for (int a = 0; a < 3; ++a)
    if (std::isfinite(geometry[a]) && std::isfinite(geometry[3 + a]))
    {
      out.brick.wholeOrigin[a] = geometry[a];
      out.brick.spacing[a] = geometry[3 + a];
    }
  if (gradientRange)
    ranks.allMax(&gradientMax, 1);
  ranks.allSum(&nonFinite, 1);
  // every rank's piece, to check that they partition the whole
  int mine[12];
  for (int a = 0; a < 3; ++a)
  {
    mine[a] = out.brick.wholeDims[a];
    mine[3 + a] = out.brick.offset[a];
    mine[6 + a] = out.brick.ownedMin[a];
    mine[9 + a] = out.brick.ownedMax[a];
  }
  const std::vector<int> all = ranks.allGather(mine, 12);
  ranks.step(
    [&]
    {
      out.brick.wholeRange = { range[0], range[1] };
      if (gradientRange) // as Volume::gradientMagnitudeRange
        out.brick.wholeGradientRange = { 0.0, std::max(1e-6, gradientMax) };
      for (int r = 0; r < ranks.size(); ++r)
      {
        VolumeBrick b = out.brick;
        const int* m = all.data() + 12 * r;
        for (int a = 0; a < 3; ++a)
        {
          b.wholeDims[a] = m[a];
          b.offset[a] = m[3 + a];
          b.ownedMin[a] = m[6 + a];
          b.ownedMax[a] = m[9 + a];
        }
        out.all.push_back(b);
      }
      checkBricksTile(out.all);
      out.nonFiniteCount = static_cast<std::int64_t>(nonFinite);
      if (local)
      {
        out.piece = *local;
        if (caster)
          out.caster = std::make_unique<RayCaster>(*local, out.brick);
      }
    });
  return out;
}

namespace
{
// The pieces' exchange over the ranks (VTK's controller).
class RankExchange : public PieceExchange
{
public:
  explicit RankExchange(const RankGroup& ranks)
    : Ranks(ranks)
  {
  }
  int piece() const override { return Ranks.rank(); }
  int pieces() const override { return Ranks.size(); }
  void allGather(const float* local, std::int64_t count, float* all) const override
  {
    Ranks.allGather(local, count, all);
  }

private:
  const RankGroup& Ranks;
};
} // namespace

std::unique_ptr<DifferentiableRenderer> differentiableOnRanks(
  const RankGroup& ranks, const RankVolume& volume)
{
  std::unique_ptr<DifferentiableRenderer> out;
  ranks.step(
    [&]
    {
      out = std::make_unique<DifferentiableRenderer>(volume.piece ? *volume.piece : Volume(),
        volume.brick, std::make_shared<RankExchange>(ranks));
    });
  return out;
}

namespace
{
// Every rank renders its piece with `renderPiece` (inside one collective step), the first rank
// composites the parts front to back: the image there, empty elsewhere.
Image compositeOnRanks(const RankGroup& ranks, const RankVolume& volume, const View& view,
  const std::function<Image(const RayCaster& caster)>& renderPiece)
{
  Image part;
  ranks.step(
    [&]
    {
      if (volume.caster)
        part = renderPiece(*volume.caster);
      else // owns nothing: transparent, behind every piece
      {
        part = Image(view.width, view.height, 5, 0.0f);
        for (size_t p = 4; p < part.pixels.size(); p += 5)
          part.pixels[p] = std::numeric_limits<float>::infinity();
      }
    });
  // each rank sends only its footprint: the rectangle of pixels where its piece shows
  const PixelRect rect = footprint(part);
  const int mine[4] = { rect.x, rect.y, rect.width, rect.height };
  const std::vector<int> rects = ranks.allGather(mine, 4);
  std::vector<PixelRect> where;
  std::vector<long long> counts;
  for (int r = 0; r < ranks.size(); ++r)
  {
    const int* q = rects.data() + 4 * r;
    where.push_back(PixelRect{ q[0], q[1], q[2], q[3] });
    counts.push_back(where.back().pixels() * 5);
  }
  const std::vector<float> parts = ranks.gatherToFirst(cropPixels(part, rect), counts);
  if (ranks.rank() != 0)
    return Image();
  part = Image();
  std::vector<const float*> each;
  size_t offset = 0;
  for (long long n : counts)
  {
    each.push_back(parts.data() + offset);
    offset += static_cast<size_t>(n);
  }
  return compositeBricks(each, where, view.width, view.height);
}

// A render request of the first rank: the view and the table's shape (its entries follow).
std::string requestText(const DesignTable& t, const View& view)
{
  char shape[512];
  const bool two = t.dimensions == 2;
  std::snprintf(shape, sizeof(shape), "%d %d %d %.17g %.17g %.17g %.17g\n", t.dimensions,
    two ? t.twoD.width : t.oneD.width, two ? t.twoD.height : 1,
    two ? t.twoD.valueRange[0] : t.oneD.min, two ? t.twoD.valueRange[1] : t.oneD.max,
    two ? t.twoD.gradientRange[0] : 0.0, two ? t.twoD.gradientRange[1] : 0.0);
  return shape + viewToJson(view);
}

void parseRequest(const std::string& text, std::vector<float> rgba, DesignTable& t, View& view)
{
  const auto line = text.find('\n');
  int width = 0, height = 0;
  double v0 = 0, v1 = 0, g0 = 0, g1 = 0;
  if (line == std::string::npos ||
    std::sscanf(text.c_str(), "%d %d %d %lg %lg %lg %lg", &t.dimensions, &width, &height, &v0, &v1,
      &g0, &g1) != 7 ||
    rgba.size() != 4 * static_cast<size_t>(width) * static_cast<size_t>(height))
    throw Error("a render request from the first rank did not parse");
  view = parseView(text.substr(line + 1), "the first rank's view");
  if (t.dimensions == 2)
  {
    t.twoD.width = width;
    t.twoD.height = height;
    t.twoD.valueRange = { v0, v1 };
    t.twoD.gradientRange = { g0, g1 };
    t.twoD.rgba = std::move(rgba);
  }
  else
  {
    t.oneD.width = width;
    t.oneD.min = v0;
    t.oneD.max = v1;
    t.oneD.rgba = std::move(rgba);
  }
}
} // namespace

Image renderOnRanks(const RankGroup& ranks, const RankVolume& volume,
  const TransferFunctionFile& tf, const View& view, const RenderOptions& options,
  const ProgressCallback& progress)
{
  return compositeOnRanks(ranks, volume, view,
    [&](const RayCaster& caster)
    { return caster.render(caster.resolve(tf, view), view, options, progress); });
}

Image renderOnRanks(
  const RankGroup& ranks, const RankVolume& volume, const DesignTable& table, const View& view)
{
  return compositeOnRanks(
    ranks, volume, view, [&](const RayCaster& caster) { return renderTable(caster, table, view); });
}

void streamToFirstRank(const RankGroup& ranks, const RankVolume& volume, int planes,
  const std::function<void(int z0, int planes, const std::vector<float>& slab)>& visit)
{
  const VolumeBrick& whole = volume.brick;
  const auto& d = whole.wholeDims;
  // the points a brick owns along an axis: [first, last]
  auto ownedPoints = [&](const VolumeBrick& b, int a, int& first, int& last)
  {
    first = b.ownedMin[a];
    last = b.ownedMax[a] == d[a] - 1 ? d[a] - 1 : b.ownedMax[a] - 1;
  };
  const std::int64_t plane = static_cast<std::int64_t>(d[0]) * d[1];
  const int slab = std::max(1, planes);
  std::vector<float> values, assembled;
  std::string failure; // the first rank's visit's: every rank goes on to the end, then throws
  for (int z0 = 0; z0 < d[2]; z0 += slab)
  {
    const int z1 = std::min(d[2], z0 + slab) - 1; // planes z0 .. z1
    // what each rank sends: its owned points in these planes, x fastest
    std::vector<long long> counts;
    std::vector<std::array<int, 6>> boxes;
    for (const VolumeBrick& b : volume.all)
    {
      std::array<int, 6> box{ 0, -1, 0, -1, 0, -1 };
      if (!b.ownsNothing())
      {
        for (int a = 0; a < 3; ++a)
          ownedPoints(b, a, box[2 * a], box[2 * a + 1]);
        box[4] = std::max(box[4], z0);
        box[5] = std::min(box[5], z1);
      }
      boxes.push_back(box);
      counts.push_back(box[1] < box[0] || box[3] < box[2] || box[5] < box[4]
          ? 0
          : static_cast<long long>(box[1] - box[0] + 1) * (box[3] - box[2] + 1) *
            (box[5] - box[4] + 1));
    }
    const auto& mine = boxes[static_cast<size_t>(ranks.rank())];
    values.assign(static_cast<size_t>(counts[static_cast<size_t>(ranks.rank())]), 0.0f);
    if (!values.empty())
    {
      const Volume& p = *volume.piece;
      const auto& pd = p.dims();
      const auto& off = volume.brick.offset;
      p.visit(
        [&](const auto* v)
        {
          size_t n = 0;
          for (int z = mine[4]; z <= mine[5]; ++z)
            for (int y = mine[2]; y <= mine[3]; ++y)
            {
              const std::int64_t row =
                (static_cast<std::int64_t>(z - off[2]) * pd[1] + (y - off[1])) * pd[0] - off[0];
              for (int x = mine[0]; x <= mine[1]; ++x)
                values[n++] = static_cast<float>(v[row + x]);
            }
        });
    }
    const std::vector<float> parts = ranks.gatherToFirst(values, counts);
    if (ranks.rank() != 0 || !failure.empty())
      continue;
    assembled.assign(static_cast<size_t>(plane) * (z1 - z0 + 1), 0.0f);
    size_t at = 0;
    for (const auto& box : boxes)
      for (int z = box[4]; z <= box[5] && box[1] >= box[0] && box[3] >= box[2]; ++z)
        for (int y = box[2]; y <= box[3]; ++y)
          for (int x = box[0]; x <= box[1]; ++x)
            assembled[static_cast<size_t>(
              (z - z0) * plane + static_cast<std::int64_t>(y) * d[0] + x)] = parts[at++];
    try
    {
      visit(z0, z1 - z0 + 1, assembled);
    }
    catch (const std::exception& e)
    {
      failure = e.what();
    }
  }
  ranks.step(
    [&]
    {
      if (!failure.empty())
        throw Error(failure);
    });
}

std::string fingerprintOnRanks(const RankGroup& ranks, const RankVolume& volume)
{
  const VolumeBrick& whole = volume.brick;
  const auto& d = whole.wholeDims;
  const std::int64_t plane = static_cast<std::int64_t>(d[0]) * d[1];
  VolumeHash hash;
  streamToFirstRank(ranks, volume,
    static_cast<int>(std::max<std::int64_t>(1, (std::int64_t(1) << 22) / plane)),
    [&](int, int, const std::vector<float>& slab)
    { hash.add(slab.data(), static_cast<std::int64_t>(slab.size())); });
  if (ranks.rank() != 0)
    return std::string();
  return volumeFingerprint(d, whole.spacing, whole.wholeRange, hash.value());
}

DesignSpaceInput designSpaceInputOnRanks(
  const RankGroup& ranks, const RankVolume& volume, std::int64_t maxVoxels)
{
  const VolumeBrick& whole = volume.brick;
  // the scalar type of the ranks with a piece (the same array everywhere)
  double type = volume.piece ? static_cast<double>(volume.piece->originalType()) : -1;
  ranks.allMax(&type, 1);
  ranks.step(
    [&]
    {
      checkBuildVolume(whole.wholeDims, whole.wholeRange);
      if (maxVoxels < 1)
        throw Error("the design space's voxel cap (maxVoxels) must be positive");
    });
  DesignSpaceAssembler assembler(whole.wholeDims, whole.wholeOrigin, whole.spacing,
    static_cast<ScalarType>(static_cast<int>(type)), maxVoxels);
  VolumeHash hash;
  streamToFirstRank(ranks, volume, assembler.slabPlanes(std::int64_t(1) << 22),
    [&](int z0, int planes, const std::vector<float>& slab)
    {
      hash.add(slab.data(), static_cast<std::int64_t>(slab.size()));
      assembler.add(z0, planes, slab.data());
    });
  DesignSpaceInput input;
  ranks.step( // the first rank's volume may fail (memory): every rank stops with it
    [&]
    {
      if (ranks.rank() == 0)
        input = assembler.finish(
          volumeFingerprint(whole.wholeDims, whole.spacing, whole.wholeRange, hash.value()));
    });
  return input;
}

void renderForFirstRank(const RankGroup& ranks, const RankVolume& volume,
  const std::function<void(const RanksTableRender& render)>& work)
{
  if (ranks.rank() == 0)
  {
    bool together = false; // inside a collective render: every rank throws with it
    std::exception_ptr failure;
    try
    {
      work(
        [&](const DesignTable& table, const View& view)
        {
          ranks.broadcast(requestText(table, view));
          std::vector<float> rgba = table.dimensions == 2 ? table.twoD.rgba : table.oneD.rgba;
          ranks.broadcast(rgba);
          together = true;
          Image out = renderOnRanks(ranks, volume, table, view);
          together = false;
          return out;
        });
    }
    catch (...)
    {
      if (together)
        throw;
      failure = std::current_exception();
    }
    ranks.broadcast(std::string()); // no more renders
    ranks.step(
      [&]
      {
        if (failure)
          std::rethrow_exception(failure);
      });
    return;
  }
  for (;;)
  {
    const std::string request = ranks.broadcast(std::string());
    if (request.empty())
      break;
    std::vector<float> rgba;
    ranks.broadcast(rgba);
    DesignTable table;
    View view;
    std::string error;
    try
    {
      parseRequest(request, std::move(rgba), table, view);
    }
    catch (const std::exception& e)
    {
      error = e.what();
    }
    compositeOnRanks(ranks, volume, view,
      [&](const RayCaster& caster)
      {
        if (!error.empty())
          throw Error(error);
        return renderTable(caster, table, view);
      });
  }
  ranks.step([] {});
}

bool InputStamp::changed(vtkImageData* input, vtkDataArray* array) const
{
  return !Known || Version != volumeVersion(input, array) || Array != array;
}

bool InputStamp::changedOnAnyRank(
  const RankGroup& ranks, vtkImageData* input, vtkDataArray* array) const
{
  double stale = changed(input, array) ? 1.0 : 0.0;
  ranks.allMax(&stale, 1);
  return stale > 0;
}

void InputStamp::keep(vtkImageData* input, vtkDataArray* array)
{
  Version = volumeVersion(input, array);
  Array = array;
  Known = true;
}

const RankVolume& RankVolumeCache::get(
  const RankGroup& ranks, vtkImageData* piece, vtkDataArray* array, const int wholeExtent[6])
{
  if (Stamp.changedOnAnyRank(ranks, piece, array))
  {
    Stamp.clear();
    Pieces.reset();
    Fingerprint.clear();
    auto pieces = std::make_unique<RankVolume>(
      RankVolume::gather(ranks, piece, array, wholeExtent, true, true));
    Fingerprint = fingerprintOnRanks(ranks, *pieces);
    Pieces = std::move(pieces);
    Stamp.keep(piece, array);
  }
  return *Pieces;
}

const RankVolume& RanksDesignVolume::pieces() const
{
  if (!Volume)
    throw Error("the volume's pieces are used only inside a request of every rank");
  return *Volume;
}

std::array<double, 2> RanksDesignVolume::range() const
{
  return pieces().brick.wholeRange;
}

std::array<double, 2> RanksDesignVolume::gradientRange() const
{
  return pieces().brick.wholeGradientRange;
}

std::array<double, 6> RanksDesignVolume::bounds() const
{
  return pieces().brick.wholeBounds(pieces().brick.spacing);
}

Image RanksDesignVolume::render(const DesignTable& table, const View& view) const
{
  if (!Render)
    throw Error("the volume's pieces render only inside a request of every rank");
  return (*Render)(table, view);
}

const RayCaster& RanksDesignVolume::firstCaster() const
{
  if (!pieces().caster)
    throw Error("the first rank's piece is empty: its ray caster gives ParaView's mapping of the "
                "whole volume");
  return *pieces().caster;
}

double RanksDesignVolume::opacityUnitDistance(const View& view) const
{
  return firstCaster().opacityUnitDistance(view);
}

ParaViewTransfer2DMapping RanksDesignVolume::paraviewMapping2D(const View& view) const
{
  return firstCaster().paraviewMapping2D(view);
}

} // namespace ddg
