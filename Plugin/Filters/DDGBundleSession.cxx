// DDGBundleSession.cxx: the input's version and volume for Core's bundle session cache; a
// filter's gallery in one process or over the ranks' pieces.
#include "DDGBundleSession.h"

#include "DDGVolumeAdaptor.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>

#include <algorithm>

namespace ddg
{

DesignGallery& galleryFor(BundleSessionCache& cache, const std::string& modelDirectory,
  vtkImageData* input, vtkDataArray* array)
{
  return cache
    .get(modelDirectory, volumeVersion(input, array), [&] { return toCoreVolume(input, array); })
    .gallery();
}

void FilterGallery::run(const RankGroup* ranks, vtkImageData* input, vtkDataArray* array,
  const int wholeExtent[6], const std::string& bundleDir,
  const std::function<void(DesignGallery& gallery)>& work)
{
  if (!ranks)
  {
    work(galleryFor(Sessions, bundleDir, input, array));
    return;
  }
  const RankVolume& volume = Pieces.get(*ranks, input, array, wholeExtent);
  renderForFirstRank(*ranks, volume,
    [&](const RanksTableRender& render)
    {
      struct Use // the space renders through this request only
      {
        RanksDesignVolume& space;
        ~Use() { space.use(nullptr, nullptr); }
      } use{ *Space };
      Space->use(&volume, &render);
      work(Sessions.get(bundleDir, Pieces.fingerprint(), Space).gallery());
    });
}

const std::string& FilterGallery::fingerprint(const RankGroup* ranks) const
{
  static const std::string none;
  if (ranks)
    return Pieces.fingerprint();
  return Sessions.current() ? Sessions.current()->fingerprint() : none;
}

} // namespace ddg
