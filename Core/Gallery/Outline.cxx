// Outline.cxx: PCA plane, thumbnail coverage, neighbours, navigation state, latent files.
#include "Gallery/Outline.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>

namespace ddg
{

// ---- latent sets --------------------------------------------------------------------------

void LatentSet::validate() const
{
  if (dim < 1)
    throw Error("a latent set needs dim >= 1");
  if (values.size() != indices.size() * static_cast<size_t>(dim))
    throw Error("a latent set has " + std::to_string(values.size()) + " values for " +
      std::to_string(indices.size()) + " latents of " + std::to_string(dim));
  for (float v : values)
    if (!std::isfinite(v))
      throw Error("a latent set holds a non-finite value");
}

namespace
{
constexpr char kMagic[8] = { 'D', 'D', 'G', 'L', 'A', 'T', 'N', 'T' };

template <typename T>
void put(std::string& out, const T& v)
{
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
} // namespace

void writeLatentSet(const LatentSet& set, const std::string& path)
{
  set.validate();
  std::string out(kMagic, 8);
  put(out, std::uint32_t(1));
  put(out, static_cast<std::uint32_t>(set.dim));
  put(out, static_cast<std::uint32_t>(set.count()));
  put(out, std::uint32_t(0));
  put(out, set.seed);
  for (auto i : set.indices)
    put(out, i);
  for (float v : set.values)
    put(out, Eigen::numext::bit_cast<std::uint16_t>(Eigen::half(v)));
  writeFileAtomic(path, out, "latent set");
}

LatentSet readLatentSet(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error("cannot open the latent set " + path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string data = buffer.str();
  const size_t header = 8 + 4 * 4 + 8;
  if (data.size() < header || std::memcmp(data.data(), kMagic, 8) != 0)
    throw Error(path + " is not a ddg latent set (bad header)");
  std::uint32_t version, dim, count, reserved;
  std::uint64_t seed;
  std::memcpy(&version, data.data() + 8, 4);
  std::memcpy(&dim, data.data() + 12, 4);
  std::memcpy(&count, data.data() + 16, 4);
  std::memcpy(&reserved, data.data() + 20, 4);
  std::memcpy(&seed, data.data() + 24, 8);
  if (version != 1)
    throw Error(path + ": latent set version " + std::to_string(version) + " is not supported");
  const size_t expected =
    header + static_cast<size_t>(count) * 8 + static_cast<size_t>(count) * dim * 2;
  if (dim < 1 || data.size() != expected)
    throw Error(path + " is truncated or corrupt: " + std::to_string(data.size()) + " bytes, " +
      std::to_string(expected) + " expected for " + std::to_string(count) + " latents of " +
      std::to_string(dim));
  LatentSet set;
  set.dim = static_cast<int>(dim);
  set.seed = seed;
  set.indices.resize(count);
  std::memcpy(set.indices.data(), data.data() + header, static_cast<size_t>(count) * 8);
  set.values.resize(static_cast<size_t>(count) * dim);
  const char* p = data.data() + header + static_cast<size_t>(count) * 8;
  for (size_t i = 0; i < set.values.size(); ++i)
  {
    std::uint16_t bits;
    std::memcpy(&bits, p + 2 * i, 2);
    set.values[i] = static_cast<float>(Eigen::numext::bit_cast<Eigen::half>(bits));
  }
  set.validate();
  return set;
}

// ---- PCA ----------------------------------------------------------------------------------

bool OutlineBox::valid() const
{
  return std::isfinite(x0) && std::isfinite(y0) && std::isfinite(x1) && std::isfinite(y1) &&
    x0 < x1 && y0 < y1;
}

DesignOutline::DesignOutline(LatentSet latents)
  : Latents(std::move(latents))
{
  Latents.validate();
  const int n = Latents.count(), d = Latents.dim;
  if (n < 3 || d < 2)
    throw Error("an outline needs at least 3 latents of at least 2 values (got " +
      std::to_string(n) + " of " + std::to_string(d) + ")");
  using MatrixRF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const MatrixRF> z(Latents.values.data(), n, d);
  const Eigen::VectorXd mean = z.cast<double>().colwise().mean().transpose();
  // covariance in float over the centred rows (n x d by d x n), accumulated in double
  const MatrixRF centred = z.rowwise() - mean.cast<float>().transpose();
  const Eigen::MatrixXd cov =
    (centred.transpose() * centred).cast<double>() / static_cast<double>(n - 1);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(cov);
  if (solver.info() != Eigen::Success)
    throw Error("the PCA of the latents did not converge");
  Mean.assign(mean.data(), mean.data() + d);
  Axes.resize(static_cast<size_t>(d) * d);
  Eigenvalues.resize(d);
  for (int k = 0; k < d; ++k)
  {
    const int src = d - 1 - k; // Eigen sorts ascending
    Eigenvalues[k] = std::max(0.0, solver.eigenvalues()(src));
    for (int c = 0; c < d; ++c)
      Axes[static_cast<size_t>(k) * d + c] = solver.eigenvectors()(c, src);
  }
  Eigen::Matrix<float, Eigen::Dynamic, 2> plane(d, 2);
  for (int c = 0; c < d; ++c)
  {
    plane(c, 0) = static_cast<float>(Axes[c]);
    plane(c, 1) = static_cast<float>(Axes[d + c]);
  }
  Points.resize(static_cast<size_t>(n) * 2);
  Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, 2, Eigen::RowMajor>>(Points.data(), n, 2) =
    centred * plane;
}

std::array<double, 2> DesignOutline::point(int row) const
{
  return { Points[2 * static_cast<size_t>(row)], Points[2 * static_cast<size_t>(row) + 1] };
}

std::array<double, 2> DesignOutline::project(const float* latent) const
{
  const int d = Latents.dim;
  std::array<double, 2> p{ 0, 0 };
  for (int c = 0; c < d; ++c)
  {
    const double v = latent[c] - Mean[c];
    p[0] += v * Axes[c];
    p[1] += v * Axes[d + c];
  }
  return p;
}

OutlineBox DesignOutline::bounds() const
{
  OutlineBox b{ std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest() };
  for (int i = 0; i < count(); ++i)
  {
    const auto p = point(i);
    b.x0 = std::min(b.x0, p[0]);
    b.x1 = std::max(b.x1, p[0]);
    b.y0 = std::min(b.y0, p[1]);
    b.y1 = std::max(b.y1, p[1]);
  }
  const double mx = 0.02 * std::max(1e-9, b.x1 - b.x0), my = 0.02 * std::max(1e-9, b.y1 - b.y0);
  return { b.x0 - mx, b.y0 - my, b.x1 + mx, b.y1 + my };
}

std::vector<int> DesignOutline::inside(const OutlineBox& box) const
{
  std::vector<int> rows;
  for (int i = 0; i < count(); ++i)
    if (box.contains(Points[2 * static_cast<size_t>(i)], Points[2 * static_cast<size_t>(i) + 1]))
      rows.push_back(i);
  return rows;
}

double DesignOutline::axisStddev(int k) const
{
  if (k < 0 || k >= Latents.dim)
    throw Error("principal axis " + std::to_string(k) + " does not exist (0.." +
      std::to_string(Latents.dim - 1) + ")");
  return std::sqrt(Eigenvalues[k]);
}

double DesignOutline::explainedVariance(int k) const
{
  axisStddev(k); // range check
  const double total = std::accumulate(Eigenvalues.begin(), Eigenvalues.end(), 0.0);
  return total > 0 ? Eigenvalues[k] / total : 0.0;
}

std::vector<float> DesignOutline::moveAlongAxes(
  const std::vector<float>& latent, const std::vector<double>& steps) const
{
  const int d = Latents.dim;
  if (static_cast<int>(latent.size()) != d)
    throw Error("the latent has " + std::to_string(latent.size()) + " values, the outline's " +
      std::to_string(d));
  if (static_cast<int>(steps.size()) > d)
    throw Error("more principal-axis steps than axes (" + std::to_string(d) + ")");
  std::vector<float> out = latent;
  for (size_t k = 0; k < steps.size(); ++k)
  {
    if (!std::isfinite(steps[k]))
      throw Error("a principal-axis step is not finite");
    const double s = steps[k] * axisStddev(static_cast<int>(k));
    for (int c = 0; c < d; ++c)
      out[c] += static_cast<float>(s * Axes[k * d + c]);
  }
  return out;
}

std::vector<Neighbour> nearestLatents(const LatentSet& set, const float* latent, int k)
{
  const int n = set.count(), d = set.dim;
  k = std::max(0, std::min(k, n));
  std::vector<Neighbour> all(n);
  for (int i = 0; i < n; ++i)
  {
    const float* r = set.row(i);
    double s = 0;
    for (int c = 0; c < d; ++c)
      s += (r[c] - latent[c]) * (r[c] - latent[c]);
    all[i] = { i, s };
  }
  std::partial_sort(all.begin(), all.begin() + k, all.end(),
    [](const Neighbour& a, const Neighbour& b)
    { return a.distance < b.distance || (a.distance == b.distance && a.row < b.row); });
  all.resize(k);
  for (auto& nb : all)
    nb.distance = std::sqrt(nb.distance);
  return all;
}

std::vector<Neighbour> DesignOutline::nearest(const float* latent, int k) const
{
  if (Key.empty())
    return nearestLatents(Latents, latent, k);
  const std::vector<float> key = Key.apply(latent, 1, Latents.dim);
  return nearestLatents(Keys, key.data(), k);
}

void DesignOutline::setQueryKey(QueryKey key)
{
  LatentSet keys;
  if (!key.empty())
  {
    keys.dim = key.components;
    keys.seed = Latents.seed;
    keys.indices = Latents.indices;
    keys.values = key.apply(Latents.values.data(), static_cast<size_t>(count()), Latents.dim);
  }
  Key = std::move(key);
  Keys = std::move(keys);
}

// ---- thumbnails ---------------------------------------------------------------------------

std::vector<int> selectThumbnails(
  const DesignOutline& outline, const OutlineBox& box, int k, std::uint64_t seed)
{
  if (k < 0)
    throw Error("the thumbnail count must be >= 0 (got " + std::to_string(k) + ")");
  if (!box.valid())
    throw Error("the outline box must be finite with x0 < x1 and y0 < y1");
  const std::vector<int> rows = outline.inside(box);
  if (k == 0 || rows.empty())
    return {};
  // farthest-point sampling; the box's aspect is normalised so coverage is even on screen
  const double sx = 1.0 / (box.x1 - box.x0), sy = 1.0 / (box.y1 - box.y0);
  std::vector<double> dist(rows.size(), std::numeric_limits<double>::max());
  std::mt19937_64 rng(seed);
  size_t next = std::uniform_int_distribution<size_t>(0, rows.size() - 1)(rng);
  std::vector<int> chosen;
  const int want = std::min<int>(k, static_cast<int>(rows.size()));
  while (static_cast<int>(chosen.size()) < want)
  {
    chosen.push_back(rows[next]);
    const auto c = outline.point(rows[next]);
    size_t far = 0;
    double farDist = -1;
    for (size_t i = 0; i < rows.size(); ++i)
    {
      const auto p = outline.point(rows[i]);
      const double dx = (p[0] - c[0]) * sx, dy = (p[1] - c[1]) * sy;
      dist[i] = std::min(dist[i], dx * dx + dy * dy);
      if (dist[i] > farDist)
      {
        farDist = dist[i];
        far = i;
      }
    }
    if (farDist <= 0)
      break; // every remaining point coincides with a chosen one
    next = far;
  }
  return chosen;
}

double dispersion(const DesignOutline& outline, const OutlineBox& box, const std::vector<int>& rows)
{
  if (rows.empty())
    return std::numeric_limits<double>::infinity();
  const double sx = 1.0 / (box.x1 - box.x0), sy = 1.0 / (box.y1 - box.y0);
  double worst = 0;
  for (int i : outline.inside(box))
  {
    const auto p = outline.point(i);
    double best = std::numeric_limits<double>::max();
    for (int r : rows)
    {
      const auto q = outline.point(r);
      const double dx = (p[0] - q[0]) * sx, dy = (p[1] - q[1]) * sy;
      best = std::min(best, dx * dx + dy * dy);
    }
    worst = std::max(worst, best);
  }
  return std::sqrt(worst);
}

// ---- view state ---------------------------------------------------------------------------

const OutlineBox& OutlineViewState::current() const
{
  if (boxes.empty())
    throw Error("the outline view has no box");
  return boxes.back();
}

void OutlineViewState::drillIn(const OutlineBox& box)
{
  const OutlineBox& c = current();
  if (!box.valid())
    throw Error("the drill-in box must be finite with x0 < x1 and y0 < y1");
  OutlineBox clipped{ std::max(box.x0, c.x0), std::max(box.y0, c.y0), std::min(box.x1, c.x1),
    std::min(box.y1, c.y1) };
  if (!clipped.valid())
    throw Error("the drill-in box lies outside the box shown");
  boxes.push_back(clipped);
}

void OutlineViewState::back()
{
  if (boxes.size() > 1)
    boxes.pop_back();
}

void OutlineViewState::zoom(double factor, double cx, double cy)
{
  if (!(factor > 0) || !std::isfinite(factor) || !std::isfinite(cx) || !std::isfinite(cy))
    throw Error("zoom needs a positive factor and a finite centre");
  OutlineBox& b = boxes.empty() ? throw Error("the outline view has no box") : boxes.back();
  b = { cx + (b.x0 - cx) / factor, cy + (b.y0 - cy) / factor, cx + (b.x1 - cx) / factor,
    cy + (b.y1 - cy) / factor };
}

void OutlineViewState::pan(double dx, double dy)
{
  if (!std::isfinite(dx) || !std::isfinite(dy))
    throw Error("pan needs finite offsets");
  OutlineBox& b = boxes.empty() ? throw Error("the outline view has no box") : boxes.back();
  b = { b.x0 + dx, b.y0 + dy, b.x1 + dx, b.y1 + dy };
}

std::string OutlineViewState::toJson() const
{
  nlohmann::json j;
  j["boxes"] = nlohmann::json::array();
  for (const auto& b : boxes)
    j["boxes"].push_back({ b.x0, b.y0, b.x1, b.y1 });
  j["count"] = count;
  j["seed"] = seed;
  return j.dump(2);
}

OutlineViewState OutlineViewState::fromJson(const std::string& text)
{
  OutlineViewState s;
  try
  {
    const auto j = nlohmann::json::parse(text);
    for (const auto& b : j.at("boxes"))
    {
      const auto v = b.get<std::vector<double>>();
      if (v.size() != 4)
        throw Error("an outline box has 4 numbers [x0, y0, x1, y1]");
      OutlineBox box{ v[0], v[1], v[2], v[3] };
      if (!box.valid())
        throw Error("an outline box must be finite with x0 < x1 and y0 < y1");
      s.boxes.push_back(box);
    }
    s.count = j.value("count", 64);
    s.seed = j.value("seed", std::uint64_t(1));
  }
  catch (const nlohmann::json::exception& e)
  {
    throw Error(std::string("outline view state: ") + e.what());
  }
  if (s.boxes.empty())
    throw Error("outline view state: no boxes");
  if (s.count < 0)
    throw Error("outline view state: count must be >= 0");
  return s;
}

} // namespace ddg
