// Volume.h: a scalar field on a regular grid (point data), with origin and anisotropic spacing.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ddg
{

/// Scalar type the volume was stored in. The values are kept in memory in their own type when it
/// is an 8- or 16-bit integer or float32 (storageTypeFor; no float copy: 1 or 2 bytes per voxel
/// for 8/16-bit data), and as float32 otherwise (int32/uint32/float64 values rounded to float32).
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
/// The type a volume of `original` scalars keeps them in: the same for uint8, int8, uint16, int16
/// and float32, float32 for the others.
ScalarType storageTypeFor(ScalarType original);

/// A volume of point samples: value(i, j, k) sits at world position origin + (i, j, k) * spacing,
/// x fastest (index = i + nx * (j + ny * k)), exactly as vtkImageData point data.
///
/// The scalars are immutable and shared: copying a Volume copies no voxel, and a volume made with
/// Volume::sharing reads memory owned by someone else (a VTK array) without copying it. Read them
/// with visit() (typed, for loops over many voxels) or value()/at() (converted to float).
///
/// Non-finite voxels (NaN, +-inf) are replaced by the smallest finite value when the volume is
/// built and counted in nonFiniteCount(); range() is over the finite values only.
class Volume
{
public:
  Volume() = default;

  /// Builds a volume from float values, kept in storageTypeFor(originalType); throws ddg::Error
  /// when a dimension is < 1, values.size() != nx*ny*nz, spacing is not finite and positive, the
  /// origin is not finite, no value is finite, or (8/16-bit types) a value is not one of the type.
  Volume(std::array<int, 3> dims, std::array<double, 3> origin, std::array<double, 3> spacing,
    std::vector<float> values, ScalarType originalType = ScalarType::Float32);

  /// Builds a volume that keeps `scalars` as they are (moved, not copied) when T is the storage
  /// type of `originalType`, else converts them (errors as above).
  template <typename T>
  static Volume fromVector(std::array<int, 3> dims, std::array<double, 3> origin,
    std::array<double, 3> spacing, std::vector<T> scalars, ScalarType originalType);

  /// Builds a volume from raw scalars of type T (copied into the storage type).
  template <typename T>
  static Volume fromScalars(std::array<int, 3> dims, std::array<double, 3> origin,
    std::array<double, 3> spacing, const T* data, ScalarType originalType);

  /// A volume over nx*ny*nz scalars of `type` at `data`, owned by `owner` (kept alive as long as
  /// any copy of the volume): no copy when `type` is its own storage type and every value is
  /// finite; otherwise the scalars are converted into a buffer of the volume's own.
  static Volume sharing(std::array<int, 3> dims, std::array<double, 3> origin,
    std::array<double, 3> spacing, ScalarType type, const void* data,
    std::shared_ptr<const void> owner);

  const std::array<int, 3>& dims() const { return Dims; }
  const std::array<double, 3>& origin() const { return Origin; }
  const std::array<double, 3>& spacing() const { return Spacing; }
  ScalarType originalType() const { return OriginalType; }
  /// The type the scalars are kept in (storageTypeFor(originalType())).
  ScalarType storageType() const { return StorageType; }
  std::int64_t voxelCount() const { return Count; }
  bool empty() const { return Count == 0; }
  /// Bytes the scalars take (voxelCount() x the storage type's size).
  std::int64_t scalarBytes() const { return Count * scalarTypeSize(StorageType); }
  /// True when the scalars are another owner's memory (Volume::sharing without a copy).
  bool sharesScalars() const { return Shared; }

  /// Calls f(const T* scalars) with the scalars in their storage type T (std::uint8_t,
  /// std::int8_t, std::uint16_t, std::int16_t or float) and returns what f returns.
  template <typename F>
  decltype(auto) visit(F&& f) const;

  /// Value at a flat index (x fastest), as float; no bounds check.
  float value(std::int64_t index) const;
  /// Value at integer point (i, j, k); no bounds check.
  float at(int i, int j, int k) const
  {
    return value(static_cast<std::int64_t>(i) +
      static_cast<std::int64_t>(Dims[0]) *
        (static_cast<std::int64_t>(j) + static_cast<std::int64_t>(Dims[1]) * k));
  }
  /// Every value as float (a copy of 4 bytes per voxel).
  std::vector<float> floatValues() const;

  /// [min, max] of the finite values (the "data range" ParaView maps transfer functions over).
  const std::array<double, 2>& range() const { return Range; }
  /// How many voxels were NaN or infinite on input (they now hold range()[0]).
  std::int64_t nonFiniteCount() const { return NonFiniteCount; }

  /// Point bounds (xmin, xmax, ymin, ymax, zmin, zmax) = origin .. origin + (dims-1)*spacing.
  std::array<double, 6> bounds() const;

  /// Trilinear interpolation at continuous index coordinates; positions outside
  /// [0, n-1] are clamped to the edge (as a texture with clamp-to-edge).
  double sampleIndex(double i, double j, double k) const;
  /// Trilinear interpolation at a world position (see sampleIndex for clamping).
  double sampleWorld(double x, double y, double z) const;

  /// Gradient magnitude at every point as ParaView's shader computes it for its 2D TFs' gradient
  /// axis (over the mean spacing; Render/Lighting.h, transferGradient): per axis
  /// (v[i+1] - v[i-1]) N / (N - 1) / (2 * spacing), indices clamped at the faces (where it is
  /// half the one-sided difference), 0 along an axis of extent 1. In value units per world unit,
  /// N/(N-1) above the central difference. Same layout as the scalars (4 bytes per voxel).
  std::vector<float> gradientMagnitude() const;
  /// [0, max gradientMagnitude()] (the max at least 1e-6): the gradient axis of 2D TFs. Computed
  /// without a per-voxel buffer on first use and kept with the scalars (shared by copies).
  std::array<double, 2> gradientMagnitudeRange() const;
  /// The largest gradientMagnitude() (as a float) over the points lo .. hi (inclusive), the
  /// N/(N-1) offset taken for a whole of `wholeDims` points: a piece's part of its whole's
  /// gradientMagnitudeRange when lo .. hi are the points it owns and it holds one ghost point
  /// beside them (VolumeBrick). Throws ddg::Error when lo .. hi leave the volume.
  double gradientMagnitudeMax(const std::array<int, 3>& lo, const std::array<int, 3>& hi,
    const std::array<int, 3>& wholeDims) const;

private:
  template <typename T>
  void adopt(std::shared_ptr<const void> owner, const T* data);
  template <typename T>
  static Volume make(std::array<int, 3> dims, std::array<double, 3> origin,
    std::array<double, 3> spacing, ScalarType originalType, std::vector<T> scalars);
  void checkGeometry(std::int64_t count) const;

  struct Cache;
  std::array<int, 3> Dims{ 0, 0, 0 };
  std::array<double, 3> Origin{ 0, 0, 0 };
  std::array<double, 3> Spacing{ 1, 1, 1 };
  ScalarType OriginalType = ScalarType::Float32;
  ScalarType StorageType = ScalarType::Float32;
  std::int64_t Count = 0;
  const void* Data = nullptr;        // the scalars, StorageType
  std::shared_ptr<const void> Owner; // keeps Data alive
  std::shared_ptr<Cache> Cached;     // values derived from the scalars, computed once
  bool Shared = false;
  std::array<double, 2> Range{ 0, 0 };
  std::int64_t NonFiniteCount = 0;
};

template <typename F>
decltype(auto) Volume::visit(F&& f) const
{
  switch (StorageType)
  {
    case ScalarType::UInt8:
      return f(static_cast<const std::uint8_t*>(Data));
    case ScalarType::Int8:
      return f(static_cast<const std::int8_t*>(Data));
    case ScalarType::UInt16:
      return f(static_cast<const std::uint16_t*>(Data));
    case ScalarType::Int16:
      return f(static_cast<const std::int16_t*>(Data));
    default:
      return f(static_cast<const float*>(Data));
  }
}

inline float Volume::value(std::int64_t index) const
{
  switch (StorageType)
  {
    case ScalarType::UInt8:
      return static_cast<const std::uint8_t*>(Data)[index];
    case ScalarType::Int8:
      return static_cast<const std::int8_t*>(Data)[index];
    case ScalarType::UInt16:
      return static_cast<const std::uint16_t*>(Data)[index];
    case ScalarType::Int16:
      return static_cast<const std::int16_t*>(Data)[index];
    default:
      return static_cast<const float*>(Data)[index];
  }
}

template <typename T>
Volume Volume::fromVector(std::array<int, 3> dims, std::array<double, 3> origin,
  std::array<double, 3> spacing, std::vector<T> scalars, ScalarType originalType)
{
  return make(dims, origin, spacing, originalType, std::move(scalars));
}

} // namespace ddg
