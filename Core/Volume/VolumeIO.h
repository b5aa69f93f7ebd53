// VolumeIO.h: reads the project's raw(.gz) + JSON volume pairs (no VTK needed).
#pragma once

#include "Volume/Volume.h"

#include <string>

namespace ddg
{

/// Reads a headerless raw volume described by a JSON sidecar, the format of ../shared/data:
///   { "dims": [nx, ny, nz], "dtype": "uint8", "spacing": [sx, sy, sz],
///     "origin": [ox, oy, oz] (optional, default 0), "endian": "little" (optional),
///     "file": "name.raw.gz" (optional, default: the JSON's name with .raw.gz or .raw) }
/// `path` may name the JSON or the raw file (then NAME.json beside NAME.raw[.gz] is used).
/// Raw files ending in .gz are gunzipped. Voxels are x fastest. Throws ddg::Error with the
/// path in the message when anything is missing, malformed or the size does not match.
Volume readRawVolume(const std::string& path);

/// True when `path` looks like a raw+JSON volume (.json, .raw or .raw.gz).
bool isRawVolumePath(const std::string& path);

} // namespace ddg
