// VolumePieces.h: test volumes and their pieces as ParaView splits them under MPI, and the
// pieces' exchange over threads (a PieceExchange without MPI).
#pragma once

#include "Render/DifferentiableRenderer.h"
#include "Render/PieceExchange.h"
#include "Render/View.h"
#include "Volume/Volume.h"
#include "Volume/VolumeBrick.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace ddg
{
namespace testing
{

// A smooth blob (24 x 20 x 28 points, anisotropic spacing, non-zero origin), 8-bit or float.
inline Volume blobVolume(ScalarType type, std::array<double, 3> spacing = { 1.0, 1.3, 0.8 },
  std::array<double, 3> origin = { -3.0, 2.0, 5.0 })
{
  const std::array<int, 3> dims{ 24, 20, 28 };
  std::vector<float> v(static_cast<size_t>(dims[0]) * dims[1] * dims[2]);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i)
      {
        const double x = (i - 11.5) / 8.0, y = (j - 9.5) / 7.0, z = (k - 13.5) / 9.0;
        const double r2 = x * x + y * y + z * z;
        double val = 255.0 * std::exp(-1.5 * r2) * (0.75 + 0.25 * std::sin(3 * x + 2 * y));
        if (type == ScalarType::UInt8)
          val = std::round(std::clamp(val, 0.0, 255.0));
        v[i + dims[0] * (j + static_cast<size_t>(dims[1]) * k)] = static_cast<float>(val);
      }
  return Volume(dims, origin, spacing, v, type);
}

inline View orbitView(const Volume& vol, double azimuthDeg, bool parallel, int w = 48, int h = 40)
{
  View v = defaultView(vol, w, h);
  const Eigen::Vector3d f = v.camera.focalPoint;
  const double dist = (v.camera.position - f).norm() * 0.8;
  const double a = azimuthDeg * M_PI / 180.0;
  v.camera.position = f + dist * Eigen::Vector3d(std::sin(a), 0.3, std::cos(a)).normalized();
  v.camera.parallelProjection = parallel;
  v.camera.parallelScale *= 0.7;
  return v;
}

// Owned point ranges [lo, hi] per axis of `pieces` pieces, split as vtkExtentTranslator does:
// bisection of the axis with the most cells (z first on ties), neighbours sharing a point plane.
using Box = std::array<int, 6>;
inline void bisect(const Box& box, int pieces, std::vector<Box>& out)
{
  if (pieces == 1)
  {
    out.push_back(box);
    return;
  }
  int axis = 2;
  for (int a : { 1, 0 })
    if (box[2 * a + 1] - box[2 * a] > box[2 * axis + 1] - box[2 * axis])
      axis = a;
  const int cells = box[2 * axis + 1] - box[2 * axis];
  Box low = box, high = box;
  low[2 * axis + 1] = high[2 * axis] = box[2 * axis] + cells * (pieces / 2) / pieces;
  bisect(low, pieces / 2, out);
  bisect(high, pieces - pieces / 2, out);
}

// The piece of `whole` owning `owned`, with `ghosts` points more on each side inside the whole.
inline std::pair<Volume, VolumeBrick> pieceOf(const Volume& whole, const Box& owned, int ghosts)
{
  const auto& d = whole.dims();
  VolumeBrick b;
  b.wholeDims = d;
  b.wholeOrigin = whole.origin();
  b.spacing = whole.spacing();
  b.wholeRange = whole.range();
  std::array<int, 3> n{}, o{};
  for (int a = 0; a < 3; ++a)
  {
    b.ownedMin[a] = owned[2 * a];
    b.ownedMax[a] = owned[2 * a + 1];
    b.offset[a] = std::max(0, owned[2 * a] - ghosts);
    n[a] = std::min(d[a] - 1, owned[2 * a + 1] + ghosts) - b.offset[a] + 1;
    o[a] = b.offset[a];
  }
  const std::vector<float> all = whole.floatValues();
  std::vector<float> v;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        v.push_back(all[(i + o[0]) + d[0] * ((j + o[1]) + static_cast<size_t>(d[1]) * (k + o[2]))]);
  std::array<double, 3> origin{};
  for (int a = 0; a < 3; ++a)
    origin[a] = whole.origin()[a] + o[a] * whole.spacing()[a];
  return { Volume(n, origin, whole.spacing(), v, whole.originalType()), b };
}

// The pieces of one volume in threads of one process: allGather waits for every piece (at most
// a minute: a piece that never comes fails the test instead of hanging it).
class ThreadBoard
{
public:
  explicit ThreadBoard(int pieces)
    : Slots(static_cast<size_t>(pieces))
  {
  }
  int pieces() const { return static_cast<int>(Slots.size()); }

  void allGather(int piece, const float* local, std::int64_t count, float* all)
  {
    std::unique_lock<std::mutex> lock(Mutex);
    Slots[static_cast<size_t>(piece)].assign(local, local + count);
    const long round = Round;
    if (++Arrived == pieces())
    {
      Gathered.clear();
      for (const auto& slot : Slots)
      {
        if (static_cast<std::int64_t>(slot.size()) != count)
          throw Error("the pieces gathered different counts");
        Gathered.insert(Gathered.end(), slot.begin(), slot.end());
      }
      Arrived = 0;
      ++Round;
      Changed.notify_all();
    }
    else if (!Changed.wait_for(lock, std::chrono::minutes(1), [&] { return Round != round; }))
      throw Error("a piece never reached the exchange");
    std::copy(Gathered.begin(), Gathered.end(), all);
  }

private:
  std::mutex Mutex;
  std::condition_variable Changed;
  std::vector<std::vector<float>> Slots;
  std::vector<float> Gathered;
  int Arrived = 0;
  long Round = 0;
};

class ThreadExchange : public PieceExchange
{
public:
  ThreadExchange(ThreadBoard& board, int piece)
    : Board(board)
    , Piece(piece)
  {
  }
  int piece() const override { return Piece; }
  int pieces() const override { return Board.pieces(); }
  void allGather(const float* local, std::int64_t count, float* all) const override
  {
    Board.allGather(Piece, local, count, all);
  }

private:
  ThreadBoard& Board;
  int Piece;
};

// Runs body(piece) for pieces 0 .. n-1, each in its own thread; every piece's exception (or
// null) in piece order.
inline std::vector<std::exception_ptr> runPieces(int n, const std::function<void(int)>& body)
{
  std::vector<std::exception_ptr> errors(static_cast<size_t>(n));
  std::vector<std::thread> threads;
  for (int p = 0; p < n; ++p)
    threads.emplace_back(
      [&, p]
      {
        try
        {
          body(p);
        }
        catch (...)
        {
          errors[static_cast<size_t>(p)] = std::current_exception();
        }
      });
  for (auto& t : threads)
    t.join();
  return errors;
}

// Calls body(p, renderer) for the pieces of `whole` owning `boxes` (one ghost level), each in its
// own thread with its DifferentiableRenderer over a ThreadExchange; rethrows a piece's error (the
// first, in piece order).
template <typename Body>
void onPieces(const Volume& whole, const std::vector<Box>& boxes, Body&& body)
{
  const int n = static_cast<int>(boxes.size());
  ThreadBoard board(n);
  const auto errors = runPieces(n,
    [&](int p)
    {
      auto [piece, brick] = pieceOf(whole, boxes[static_cast<size_t>(p)], 1);
      const DifferentiableRenderer r(piece, brick, std::make_shared<ThreadExchange>(board, p));
      body(p, r);
    });
  for (const auto& e : errors)
    if (e)
      std::rethrow_exception(e);
}

// The same for the `n` pieces ParaView splits `whole` into (bisect).
template <typename Body>
void onPieces(const Volume& whole, int n, Body&& body)
{
  const auto& d = whole.dims();
  std::vector<Box> boxes;
  bisect({ 0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1 }, n, boxes);
  onPieces(whole, boxes, body);
}

// An uneven split of `whole` (at least 21 points along z, 6 along x) with a piece one plane
// thick, which owns no cell.
inline std::vector<Box> unevenSplit(const Volume& whole)
{
  const auto& d = whole.dims();
  return { { 0, 5, 0, d[1] - 1, 0, 20 }, { 5, d[0] - 1, 0, d[1] - 1, 0, 20 },
    { 0, d[0] - 1, 0, d[1] - 1, 20, 20 }, { 0, d[0] - 1, 0, d[1] - 1, 20, d[2] - 1 } };
}

} // namespace testing
} // namespace ddg
