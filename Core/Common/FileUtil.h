// FileUtil.h: whole-file reads and atomic writes (a failed write never clobbers the old file).
#pragma once

#include <string>

namespace ddg
{

/// Reads a whole file; throws ddg::Error("cannot read <what> '<path>'") on failure.
std::string readTextFile(const std::string& path, const std::string& what);

/// Writes `content` to `path` through a temporary file in the same directory and a rename,
/// so an existing file is replaced only by a complete new one. Throws ddg::Error on failure.
void writeFileAtomic(const std::string& path, const std::string& content, const std::string& what);

/// Lower-case extension including the dot(s) of interest: ".vti", ".png", ".raw.gz", ".nii.gz".
std::string fileExtension(const std::string& path);

} // namespace ddg
