// Volume.cxx: construction, validation, trilinear sampling and gradient magnitude.
#include "Volume/Volume.h"

#include "Common/Error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

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

Volume::Volume(std::array<int, 3> dims, std::array<double, 3> origin, std::array<double, 3> spacing,
  std::vector<float> values, ScalarType originalType)
  : Dims(dims)
  , Origin(origin)
  , Spacing(spacing)
  , Values(std::move(values))
  , OriginalType(originalType)
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
  if (static_cast<std::int64_t>(Values.size()) != n)
  {
    std::ostringstream msg;
    msg << "volume has " << Values.size() << " values but its dimensions " << Dims[0] << " x "
        << Dims[1] << " x " << Dims[2] << " need " << n;
    throw Error(msg.str());
  }
  float lo = std::numeric_limits<float>::infinity();
  float hi = -std::numeric_limits<float>::infinity();
  for (float v : Values)
  {
    if (std::isfinite(v))
    {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    else
    {
      ++NonFiniteCount;
    }
  }
  if (NonFiniteCount == n)
  {
    throw Error("volume has no finite value (all voxels are NaN or infinite)");
  }
  if (NonFiniteCount > 0)
  {
    for (float& v : Values)
    {
      if (!std::isfinite(v))
      {
        v = lo;
      }
    }
  }
  Range = { lo, hi };
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

std::vector<float> Volume::gradientMagnitude() const
{
  std::vector<float> out(Values.size());
  const int nx = Dims[0], ny = Dims[1], nz = Dims[2];
  auto diff = [&](int a, int i, int j, int k) -> double
  {
    int idx[3] = { i, j, k };
    const int n = Dims[a];
    if (n == 1)
    {
      return 0.0;
    }
    int lo = std::max(idx[a] - 1, 0);
    int hi = std::min(idx[a] + 1, n - 1);
    int ilo[3] = { i, j, k };
    int ihi[3] = { i, j, k };
    ilo[a] = lo;
    ihi[a] = hi;
    // ParaView's: the texture clamps at the faces, its offset is N/(N-1) voxels, and it divides
    // by twice the spacing whatever the offset
    return (static_cast<double>(at(ihi[0], ihi[1], ihi[2])) - at(ilo[0], ilo[1], ilo[2])) * n /
      ((n - 1) * 2.0 * Spacing[a]);
  };
  for (int k = 0; k < nz; ++k)
  {
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        const double gx = diff(0, i, j, k), gy = diff(1, i, j, k), gz = diff(2, i, j, k);
        out[static_cast<size_t>(i) + static_cast<size_t>(nx) * (j + static_cast<size_t>(ny) * k)] =
          static_cast<float>(std::sqrt(gx * gx + gy * gy + gz * gz));
      }
    }
  }
  return out;
}

std::array<double, 2> Volume::gradientMagnitudeRange() const
{
  const auto g = gradientMagnitude();
  return { 0.0, std::max(1e-6, static_cast<double>(*std::max_element(g.begin(), g.end()))) };
}

} // namespace ddg
