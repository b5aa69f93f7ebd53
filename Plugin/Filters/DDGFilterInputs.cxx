// DDGFilterInputs.cxx: views and images from files or property text.
#include "DDGFilterInputs.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"

#include <vtkBase64Utilities.h>

#include <algorithm>
#include <cctype>
#include <utility>
#include <vector>

namespace ddg
{

View filterView(const std::string& viewJson, const std::string& viewFile)
{
  if (!viewJson.empty())
    return parseView(viewJson, "ViewJSON");
  if (viewFile.empty())
    throw Error("no ViewFile or ViewJSON set");
  return readView(viewFile);
}

Lighting filterLighting(const std::string& viewJson, const std::string& viewFile)
{
  if (!viewJson.empty())
    return viewLighting(viewJson, "ViewJSON");
  if (viewFile.empty())
    return Lighting();
  return viewLighting(readTextFile(viewFile, "view"), "view '" + viewFile + "'");
}

void filterViewSize(
  const std::string& viewJson, const std::string& viewFile, int& width, int& height)
{
  width = height = 0;
  try
  {
    const View view = filterView(viewJson, viewFile);
    width = view.width;
    height = view.height;
  }
  catch (const std::exception&)
  {
  }
}

Image filterImage(
  const std::string& base64, const std::string& file, const std::string& what, int longest)
{
  if (base64.empty())
  {
    if (file.empty())
      throw Error("no " + what + "File or " + what + "Data set");
    return longest > 0 ? readShrunkPicture(file, longest) : readImage(file);
  }
  std::string text;
  text.reserve(base64.size());
  std::copy_if(base64.begin(), base64.end(), std::back_inserter(text),
    [](unsigned char c) { return !std::isspace(c); });
  const bool valid = text.size() % 4 == 0 &&
    std::all_of(text.begin(), text.end(),
      [](unsigned char c) { return std::isalnum(c) || c == '+' || c == '/' || c == '='; });
  if (!valid)
    throw Error(what + "Data is not base64 text (" + std::to_string(text.size()) + " characters)");
  std::vector<unsigned char> bytes(text.size() / 4 * 3);
  const size_t n = vtkBase64Utilities::DecodeSafely(
    reinterpret_cast<const unsigned char*>(text.data()), text.size(), bytes.data(), bytes.size());
  // errors say "the picture", not the property: the panel and pvpython name its file
  Image image =
    decodeImage(std::string(bytes.begin(), bytes.begin() + static_cast<long>(n)), "the picture");
  if (longest > 0)
    return shrinkPicture(std::move(image), longest);
  return image;
}

} // namespace ddg
