// Volume.h: a scalar field on a regular grid (point data), with origin and anisotropic spacing.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddg
{

/// Scalar type the volume was stored in. Values are kept as float32 in memory (exact for
/// 8- and 16-bit integers and float32; int32/uint32/float64 values are rounded to float32).
enum class ScalarType
{
  UInt8,
  Int8,
  UInt16,
  Int16,
  UInt32,
  Int32,
  Float32,
  Float64
};

/// "uint8", "int16", "float32", ... (numpy-style names, as in the raw+JSON files).
const char* scalarTypeName(ScalarType type);
/// Parses the names above (also "float" and "double"); throws ddg::Error otherwise.
ScalarType parseScalarType(const std::string& name);
/// Bytes per voxel of a type.
int scalarTypeSize(ScalarType type);

/// A volume of point samples: value(i, j, k) sits at world position origin + (i, j, k) * spacing,
/// x fastest (index = i + nx * (j + ny * k)), exactly as vtkImageData point data.
///
/// Non-finite voxels (NaN, +-inf) are replaced by the smallest finite value when the volume is
/// built and counted in nonFiniteCount(); range() is over the finite values only.
class Volume
{
public:
  Volume() = default;

  /// Builds a volume; throws ddg::Error when a dimension is < 1, values.size() != nx*ny*nz,
  /// spacing is not finite and positive, the origin is not finite, or no value is finite.
  Volume(std::array<int, 3> dims, std::array<double, 3> origin, std::array<double, 3> spacing,
    std::vector<float> values, ScalarType originalType = ScalarType::Float32);

  /// Builds a volume from raw scalars of type T (converted to float32).
  template <typename T>
  static Volume fromScalars(std::array<int, 3> dims, std::array<double, 3> origin,
    std::array<double, 3> spacing, const T* data, ScalarType originalType);

  const std::array<int, 3>& dims() const { return Dims; }
  const std::array<double, 3>& origin() const { return Origin; }
  const std::array<double, 3>& spacing() const { return Spacing; }
  const std::vector<float>& values() const { return Values; }
  ScalarType originalType() const { return OriginalType; }
  std::int64_t voxelCount() const { return static_cast<std::int64_t>(Values.size()); }
  bool empty() const { return Values.empty(); }

  /// [min, max] of the finite values (the "data range" ParaView maps transfer functions over).
  const std::array<double, 2>& range() const { return Range; }
  /// How many voxels were NaN or infinite on input (they now hold range()[0]).
  std::int64_t nonFiniteCount() const { return NonFiniteCount; }

  /// Point bounds (xmin, xmax, ymin, ymax, zmin, zmax) = origin .. origin + (dims-1)*spacing.
  std::array<double, 6> bounds() const;

  /// Value at integer point (i, j, k); no bounds check.
  float at(int i, int j, int k) const
  {
    return Values[static_cast<size_t>(i) +
      static_cast<size_t>(Dims[0]) * (static_cast<size_t>(j) + static_cast<size_t>(Dims[1]) * k)];
  }

  /// Trilinear interpolation at continuous index coordinates; positions outside
  /// [0, n-1] are clamped to the edge (as a texture with clamp-to-edge).
  double sampleIndex(double i, double j, double k) const;
  /// Trilinear interpolation at a world position (see sampleIndex for clamping).
  double sampleWorld(double x, double y, double z) const;

  /// Gradient magnitude at every point as ParaView's shader computes it for its 2D TFs' gradient
  /// axis (over the mean spacing; Render/Lighting.h, transferGradient): per axis
  /// (v[i+1] - v[i-1]) N / (N - 1) / (2 * spacing), indices clamped at the faces (where it is
  /// half the one-sided difference), 0 along an axis of extent 1. In value units per world unit,
  /// N/(N-1) above the central difference. Same layout as values().
  std::vector<float> gradientMagnitude() const;
  /// [0, max gradientMagnitude()] (the max at least 1e-6): the gradient axis of 2D TFs.
  std::array<double, 2> gradientMagnitudeRange() const;

private:
  std::array<int, 3> Dims{ 0, 0, 0 };
  std::array<double, 3> Origin{ 0, 0, 0 };
  std::array<double, 3> Spacing{ 1, 1, 1 };
  std::vector<float> Values;
  ScalarType OriginalType = ScalarType::Float32;
  std::array<double, 2> Range{ 0, 0 };
  std::int64_t NonFiniteCount = 0;
};

template <typename T>
Volume Volume::fromScalars(std::array<int, 3> dims, std::array<double, 3> origin,
  std::array<double, 3> spacing, const T* data, ScalarType originalType)
{
  std::int64_t n = 1;
  for (int d : dims)
  {
    n *= d > 0 ? d : 0;
  }
  std::vector<float> values(static_cast<size_t>(n));
  for (std::int64_t i = 0; i < n; ++i)
  {
    values[static_cast<size_t>(i)] = static_cast<float>(data[i]);
  }
  return Volume(dims, origin, spacing, std::move(values), originalType);
}

} // namespace ddg
