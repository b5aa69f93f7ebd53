// Volume.cxx: construction, validation, trilinear sampling and gradient magnitude.
#include "Volume/Volume.h"

#include "Common/Error.h"
#include "Common/Parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>
#include <type_traits>

namespace ddg
{

const char* scalarTypeName(ScalarType type)
{
  switch (type)
  {
    case ScalarType::UInt8:
      return "uint8";
    case ScalarType::Int8:
      return "int8";
    case ScalarType::UInt16:
      return "uint16";
    case ScalarType::Int16:
      return "int16";
    case ScalarType::UInt32:
      return "uint32";
    case ScalarType::Int32:
      return "int32";
    case ScalarType::Float32:
      return "float32";
    case ScalarType::Float64:
      return "float64";
  }
  return "unknown";
}

ScalarType parseScalarType(const std::string& name)
{
  if (name == "uint8" || name == "uchar")
    return ScalarType::UInt8;
  if (name == "int8" || name == "char")
    return ScalarType::Int8;
  if (name == "uint16" || name == "ushort")
    return ScalarType::UInt16;
  if (name == "int16" || name == "short")
    return ScalarType::Int16;
  if (name == "uint32" || name == "uint")
    return ScalarType::UInt32;
  if (name == "int32" || name == "int")
    return ScalarType::Int32;
  if (name == "float32" || name == "float")
    return ScalarType::Float32;
  if (name == "float64" || name == "double")
    return ScalarType::Float64;
  throw Error("unknown scalar type '" + name +
    "' (expected uint8, int8, uint16, int16, uint32, int32, float32 or float64)");
}

int scalarTypeSize(ScalarType type)
{
  switch (type)
  {
    case ScalarType::UInt8:
    case ScalarType::Int8:
      return 1;
    case ScalarType::UInt16:
    case ScalarType::Int16:
      return 2;
    case ScalarType::UInt32:
    case ScalarType::Int32:
    case ScalarType::Float32:
      return 4;
    case ScalarType::Float64:
      return 8;
  }
  return 0;
}

ScalarType storageTypeFor(ScalarType original)
{
  switch (original)
  {
    case ScalarType::UInt8:
    case ScalarType::Int8:
    case ScalarType::UInt16:
    case ScalarType::Int16:
    case ScalarType::Float32:
      return original;
    default:
      return ScalarType::Float32;
  }
}

namespace
{

template <ScalarType>
struct StorageOf;
template <>
struct StorageOf<ScalarType::UInt8>
{
  using type = std::uint8_t;
};
template <>
struct StorageOf<ScalarType::Int8>
{
  using type = std::int8_t;
};
template <>
struct StorageOf<ScalarType::UInt16>
{
  using type = std::uint16_t;
};
template <>
struct StorageOf<ScalarType::Int16>
{
  using type = std::int16_t;
};
template <>
struct StorageOf<ScalarType::Float32>
{
  using type = float;
};

// Calls f(S{}) with a value of the C++ type S the scalars of `storage` are kept in.
template <typename F>
decltype(auto) withStorage(ScalarType storage, F&& f)
{
  switch (storage)
  {
    case ScalarType::UInt8:
      return f(std::uint8_t{});
    case ScalarType::Int8:
      return f(std::int8_t{});
    case ScalarType::UInt16:
      return f(std::uint16_t{});
    case ScalarType::Int16:
      return f(std::int16_t{});
    default:
      return f(float{});
  }
}

// `scalars` converted to S: moved when T is S; integer S refuses values that are not one of it.
template <typename S, typename T>
std::vector<S> convertTo(std::vector<T>&& scalars, ScalarType originalType)
{
  if constexpr (std::is_same_v<S, T>)
  {
    (void)originalType;
    return std::move(scalars);
  }
  else
  {
    std::vector<S> out(scalars.size());
    for (size_t i = 0; i < scalars.size(); ++i)
    {
      const T x = scalars[i];
      if constexpr (std::is_integral_v<S>)
      {
        const double d = static_cast<double>(x);
        if (!(d >= static_cast<double>(std::numeric_limits<S>::lowest()) &&
              d <= static_cast<double>(std::numeric_limits<S>::max()) &&
              static_cast<double>(static_cast<S>(x)) == d))
        {
          std::ostringstream msg;
          msg << "volume value " << d << " at voxel " << i << " is not a "
              << scalarTypeName(originalType) << " (the volume's scalar type)";
          throw Error(msg.str());
        }
      }
      out[i] = static_cast<S>(x);
    }
    return out;
  }
}

} // namespace

struct Volume::Cache
{
  std::once_flag GradientOnce;
  std::array<double, 2> GradientRange{ 0, 0 };
};

void Volume::checkGeometry(std::int64_t count) const
{
  std::int64_t n = 1;
  for (int a = 0; a < 3; ++a)
  {
    if (Dims[a] < 1)
    {
      std::ostringstream msg;
      msg << "volume is empty: dimensions are " << Dims[0] << " x " << Dims[1] << " x " << Dims[2];
      throw Error(msg.str());
    }
    if (!std::isfinite(Spacing[a]) || Spacing[a] <= 0)
    {
      throw Error("volume spacing must be finite and positive along every axis");
    }
    if (!std::isfinite(Origin[a]))
    {
      throw Error("volume origin must be finite");
    }
    n *= Dims[a];
  }
  if (count != n)
  {
    std::ostringstream msg;
    msg << "volume has " << count << " values but its dimensions " << Dims[0] << " x " << Dims[1]
        << " x " << Dims[2] << " need " << n;
    throw Error(msg.str());
  }
}

template <typename T>
void Volume::adopt(std::shared_ptr<const void> owner, const T* data)
{
  Data = data;
  Owner = std::move(owner);
  Cached = std::make_shared<Cache>();
  T lo = data[0], hi = data[0];
  for (std::int64_t i = 1; i < Count; ++i)
  {
    lo = std::min(lo, data[i]);
    hi = std::max(hi, data[i]);
  }
  Range = { static_cast<double>(lo), static_cast<double>(hi) };
}

namespace
{

// Finite range of float scalars; non-finite values replaced by the smallest finite one.
std::int64_t replaceNonFinite(std::vector<float>& v)
{
  float lo = std::numeric_limits<float>::infinity();
  std::int64_t bad = 0;
  for (float x : v)
  {
    if (std::isfinite(x))
      lo = std::min(lo, x);
    else
      ++bad;
  }
  if (bad == static_cast<std::int64_t>(v.size()))
  {
    throw Error("volume has no finite value (all voxels are NaN or infinite)");
  }
  if (bad > 0)
  {
    for (float& x : v)
      if (!std::isfinite(x))
        x = lo;
  }
  return bad;
}

} // namespace

template <typename T>
Volume Volume::make(std::array<int, 3> dims, std::array<double, 3> origin,
  std::array<double, 3> spacing, ScalarType originalType, std::vector<T> scalars)
{
  Volume v;
  v.Dims = dims;
  v.Origin = origin;
  v.Spacing = spacing;
  v.OriginalType = originalType;
  v.StorageType = storageTypeFor(originalType);
  v.checkGeometry(static_cast<std::int64_t>(scalars.size()));
  v.Count = static_cast<std::int64_t>(scalars.size());
  withStorage(v.StorageType,
    [&](auto tag)
    {
      using S = decltype(tag);
      auto owned = std::make_shared<std::vector<S>>(convertTo<S>(std::move(scalars), originalType));
      if constexpr (std::is_same_v<S, float>)
      {
        v.NonFiniteCount = replaceNonFinite(*owned);
      }
      const S* data = owned->data();
      v.adopt<S>(std::move(owned), data);
    });
  return v;
}

Volume::Volume(std::array<int, 3> dims, std::array<double, 3> origin, std::array<double, 3> spacing,
  std::vector<float> values, ScalarType originalType)
{
  *this = make(dims, origin, spacing, originalType, std::move(values));
}

template <typename T>
Volume Volume::fromScalars(std::array<int, 3> dims, std::array<double, 3> origin,
  std::array<double, 3> spacing, const T* data, ScalarType originalType)
{
  std::int64_t n = 1;
  for (int d : dims)
  {
    n *= d > 0 ? d : 0;
  }
  if (storageTypeFor(originalType) == ScalarType::Float32 && !std::is_same_v<T, float>)
  {
    std::vector<float> f(static_cast<size_t>(n)); // straight to float: no copy of T first
    for (std::int64_t i = 0; i < n; ++i)
      f[static_cast<size_t>(i)] = static_cast<float>(data[i]);
    return make(dims, origin, spacing, originalType, std::move(f));
  }
  return make(
    dims, origin, spacing, originalType, std::vector<T>(data, data + static_cast<size_t>(n)));
}

Volume Volume::sharing(std::array<int, 3> dims, std::array<double, 3> origin,
  std::array<double, 3> spacing, ScalarType type, const void* data,
  std::shared_ptr<const void> owner)
{
  std::int64_t n = 1;
  for (int d : dims)
  {
    n *= d > 0 ? d : 0;
  }
  auto copy = [&](auto tag)
  {
    using T = decltype(tag);
    return fromScalars(dims, origin, spacing, static_cast<const T*>(data), type);
  };
  auto share = [&](auto tag)
  {
    using T = decltype(tag);
    const T* p = static_cast<const T*>(data);
    if constexpr (std::is_same_v<T, float>)
    {
      for (std::int64_t i = 0; i < n; ++i)
        if (!std::isfinite(p[i]))
          return copy(tag); // non-finite values are replaced in a copy of the volume's own
    }
    Volume v;
    v.Dims = dims;
    v.Origin = origin;
    v.Spacing = spacing;
    v.OriginalType = type;
    v.StorageType = type;
    v.checkGeometry(n);
    v.Count = n;
    v.Shared = true;
    v.adopt<T>(std::move(owner), p);
    return v;
  };
  switch (type)
  {
    case ScalarType::UInt8:
      return share(std::uint8_t{});
    case ScalarType::Int8:
      return share(std::int8_t{});
    case ScalarType::UInt16:
      return share(std::uint16_t{});
    case ScalarType::Int16:
      return share(std::int16_t{});
    case ScalarType::Float32:
      return share(float{});
    case ScalarType::UInt32:
      return copy(std::uint32_t{});
    case ScalarType::Int32:
      return copy(std::int32_t{});
    case ScalarType::Float64:
      return copy(double{});
  }
  throw Error("unknown scalar type");
}

#define DDG_VOLUME_INSTANTIATE(T)                                                                  \
  template Volume Volume::make<T>(                                                                 \
    std::array<int, 3>, std::array<double, 3>, std::array<double, 3>, ScalarType, std::vector<T>); \
  template Volume Volume::fromScalars<T>(                                                          \
    std::array<int, 3>, std::array<double, 3>, std::array<double, 3>, const T*, ScalarType);
DDG_VOLUME_INSTANTIATE(std::uint8_t)
DDG_VOLUME_INSTANTIATE(std::int8_t)
DDG_VOLUME_INSTANTIATE(std::uint16_t)
DDG_VOLUME_INSTANTIATE(std::int16_t)
DDG_VOLUME_INSTANTIATE(std::uint32_t)
DDG_VOLUME_INSTANTIATE(std::int32_t)
DDG_VOLUME_INSTANTIATE(float)
DDG_VOLUME_INSTANTIATE(double)
#undef DDG_VOLUME_INSTANTIATE

std::vector<float> Volume::floatValues() const
{
  std::vector<float> out(static_cast<size_t>(Count));
  visit(
    [&](const auto* p)
    {
      for (std::int64_t i = 0; i < Count; ++i)
        out[static_cast<size_t>(i)] = static_cast<float>(p[i]);
    });
  return out;
}

std::array<double, 6> Volume::bounds() const
{
  std::array<double, 6> b{};
  for (int a = 0; a < 3; ++a)
  {
    b[2 * a] = Origin[a];
    b[2 * a + 1] = Origin[a] + (Dims[a] - 1) * Spacing[a];
  }
  return b;
}

double Volume::sampleIndex(double x, double y, double z) const
{
  const double p[3] = { x, y, z };
  int i0[3];
  int i1[3];
  double f[3];
  for (int a = 0; a < 3; ++a)
  {
    const double c = std::clamp(p[a], 0.0, static_cast<double>(Dims[a] - 1));
    i0[a] = std::min(static_cast<int>(c), Dims[a] - 1);
    i1[a] = std::min(i0[a] + 1, Dims[a] - 1);
    f[a] = c - i0[a];
  }
  auto v = [&](int i, int j, int k) { return static_cast<double>(at(i, j, k)); };
  const double c00 = v(i0[0], i0[1], i0[2]) * (1 - f[0]) + v(i1[0], i0[1], i0[2]) * f[0];
  const double c10 = v(i0[0], i1[1], i0[2]) * (1 - f[0]) + v(i1[0], i1[1], i0[2]) * f[0];
  const double c01 = v(i0[0], i0[1], i1[2]) * (1 - f[0]) + v(i1[0], i0[1], i1[2]) * f[0];
  const double c11 = v(i0[0], i1[1], i1[2]) * (1 - f[0]) + v(i1[0], i1[1], i1[2]) * f[0];
  const double c0 = c00 * (1 - f[1]) + c10 * f[1];
  const double c1 = c01 * (1 - f[1]) + c11 * f[1];
  return c0 * (1 - f[2]) + c1 * f[2];
}

double Volume::sampleWorld(double x, double y, double z) const
{
  return sampleIndex(
    (x - Origin[0]) / Spacing[0], (y - Origin[1]) / Spacing[1], (z - Origin[2]) / Spacing[2]);
}

namespace
{

// Calls f(index, |g|) for every point of k-slices [k0, k1) (rows j and columns i in
// [lo, hi] when given): ParaView's gradient magnitude (Volume::gradientMagnitude) from the
// scalars p, with the N/(N-1) offset of a whole of scaleDims points (the volume's own, or the
// whole's for a piece).
template <typename T, typename F>
void forGradientMagnitudes(const T* p, const std::array<int, 3>& dims,
  const std::array<double, 3>& spacing, int k0, int k1, F&& f,
  const std::array<int, 3>* scaleDims = nullptr, const std::array<int, 3>* lo = nullptr,
  const std::array<int, 3>* hi = nullptr)
{
  const int nx = dims[0], ny = dims[1], nz = dims[2];
  const std::array<int, 3>& sd = scaleDims ? *scaleDims : dims;
  double scale[3];
  for (int a = 0; a < 3; ++a)
  {
    // ParaView's: the texture clamps at the faces, its offset is N/(N-1) voxels, and it divides
    // by twice the spacing whatever the offset; 0 along an axis of extent 1
    scale[a] = sd[a] > 1 ? sd[a] / ((sd[a] - 1) * 2.0 * spacing[a]) : 0.0;
  }
  const int j0 = lo ? (*lo)[1] : 0, j1 = hi ? (*hi)[1] : ny - 1;
  const int i0 = lo ? (*lo)[0] : 0, i1 = hi ? (*hi)[0] : nx - 1;
  const size_t sy = static_cast<size_t>(nx), sz = static_cast<size_t>(nx) * ny;
  for (int k = k0; k < k1; ++k)
  {
    const int kl = std::max(k - 1, 0), kh = std::min(k + 1, nz - 1);
    for (int j = j0; j <= j1; ++j)
    {
      const int jl = std::max(j - 1, 0), jh = std::min(j + 1, ny - 1);
      const size_t row = sy * j + sz * k;
      for (int i = i0; i <= i1; ++i)
      {
        const int il = std::max(i - 1, 0), ih = std::min(i + 1, nx - 1);
        const double gx = (static_cast<double>(p[row + ih]) - p[row + il]) * scale[0];
        const double gy =
          (static_cast<double>(p[sy * jh + sz * k + i]) - p[sy * jl + sz * k + i]) * scale[1];
        const double gz =
          (static_cast<double>(p[sy * j + sz * kh + i]) - p[sy * j + sz * kl + i]) * scale[2];
        f(row + i, std::sqrt(gx * gx + gy * gy + gz * gz));
      }
    }
  }
}

} // namespace

std::vector<float> Volume::gradientMagnitude() const
{
  std::vector<float> out(static_cast<size_t>(Count));
  visit(
    [&](const auto* p)
    {
      parallelFor(Dims[2], 0,
        [&](std::int64_t k, int)
        {
          forGradientMagnitudes(p, Dims, Spacing, static_cast<int>(k), static_cast<int>(k) + 1,
            [&](size_t i, double g) { out[i] = static_cast<float>(g); });
        });
    });
  return out;
}

std::array<double, 2> Volume::gradientMagnitudeRange() const
{
  if (!Cached)
  {
    return { 0.0, 1e-6 };
  }
  std::call_once(Cached->GradientOnce,
    [this]
    {
      // the maximum of the float magnitudes, as gradientMagnitude() stores them
      const double top =
        gradientMagnitudeMax({ 0, 0, 0 }, { Dims[0] - 1, Dims[1] - 1, Dims[2] - 1 }, Dims);
      Cached->GradientRange = { 0.0, std::max(1e-6, top) };
    });
  return Cached->GradientRange;
}

double Volume::gradientMagnitudeMax(const std::array<int, 3>& lo, const std::array<int, 3>& hi,
  const std::array<int, 3>& wholeDims) const
{
  for (int a = 0; a < 3; ++a)
    if (lo[a] < 0 || hi[a] >= Dims[a] || lo[a] > hi[a])
      throw Error("gradient magnitude: the points asked for lie outside the volume");
  std::vector<double> maxima(static_cast<size_t>(resolveThreadCount(0, hi[2] - lo[2] + 1)), 0.0);
  visit(
    [&](const auto* p)
    {
      parallelFor(hi[2] - lo[2] + 1, 0,
        [&](std::int64_t k, int t)
        {
          double& m = maxima[static_cast<size_t>(t)];
          const int kk = lo[2] + static_cast<int>(k);
          forGradientMagnitudes(
            p, Dims, Spacing, kk, kk + 1, [&](size_t, double g) { m = std::max(m, g); }, &wholeDims,
            &lo, &hi);
        });
    });
  return static_cast<float>(*std::max_element(maxima.begin(), maxima.end()));
}

} // namespace ddg
