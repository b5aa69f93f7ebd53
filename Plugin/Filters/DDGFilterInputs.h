// DDGFilterInputs.h: the inputs the filters take either as a file (scripts, the command line) or
// as text in a property (the Design Gallery panel: nothing on the server's disk needed, so the
// same in client/server): a view as view JSON, an image as a base64-encoded image file.
#pragma once

#include "DDGFiltersModule.h" // export macro

#include "Image/Image.h"
#include "Render/View.h"

#include <string>

namespace ddg
{

/// The view of `viewJson` (view JSON text) when it is not empty, else of `viewFile`. Throws
/// ddg::Error when both are empty ("no ViewFile or ViewJSON set") or the view is invalid.
DDGFILTERS_EXPORT View filterView(const std::string& viewJson, const std::string& viewFile);

/// The lighting of the view of `viewJson` or else `viewFile` (its other keys not read: the
/// carried look's view gives only the lighting); unlit when both are empty. Throws ddg::Error
/// for text that is not a JSON object or a lighting out of range.
DDGFILTERS_EXPORT Lighting filterLighting(const std::string& viewJson, const std::string& viewFile);

/// (width, height) of that view, or (0, 0) when none is set or it is unreadable (the error is
/// reported by RequestData).
DDGFILTERS_EXPORT void filterViewSize(
  const std::string& viewJson, const std::string& viewFile, int& width, int& height);

/// The image of `base64` (an image file's contents, base64-encoded: PNG, JPEG, TIFF, BMP, GIF or
/// WebP) when it is not empty, else of `file`. Throws ddg::Error naming `what` when both are empty
/// or the text is not base64, and "the picture" (the file, when read from one) when it cannot be
/// read. With `longest` > 0 the picture is as shrinkPicture(picture, longest) gives it (a file read
/// strip by strip: readShrunkPicture).
DDGFILTERS_EXPORT Image filterImage(
  const std::string& base64, const std::string& file, const std::string& what, int longest = 0);

} // namespace ddg
