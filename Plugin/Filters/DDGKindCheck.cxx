// DDGKindCheck.cxx: the kind check's field and warning (see DDGKindCheck.h).
#include "DDGKindCheck.h"

#include "Common/Error.h"
#include "DDGPieces.h"
#ifdef DDG_WITH_TORCH
#include "Neural/KindNetwork.h"
#include "Render/RayCaster.h" // ddg::Cancelled
#endif

#include <vtkAlgorithm.h>
#include <vtkFieldData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>

#include <algorithm>
#include <optional>

namespace ddg
{
#ifdef DDG_WITH_TORCH
namespace
{
/// The filter's progress text is "kind" while it lives, whatever ends the check.
struct Stage
{
  vtkAlgorithm* filter;
  std::string before;
  explicit Stage(vtkAlgorithm* f)
    : filter(f)
    , before(f->GetProgressText() ? f->GetProgressText() : "")
  {
    filter->SetProgressText("kind");
  }
  ~Stage() { filter->SetProgressText(before.empty() ? nullptr : before.c_str()); }
};

/// The check's progress f in [0, 1] as the rest of the filter's run, from where it stands (the
/// bar does not start again at 0).
std::function<bool(double)> progressOf(vtkAlgorithm* filter)
{
  const double from = std::clamp(filter->GetProgress(), 0.0, 1.0);
  return [filter, from](double f)
  {
    filter->UpdateProgress(from + (1.0 - from) * f);
    return !filter->GetAbortExecute();
  };
}

void notChecked(vtkAlgorithm* filter, const std::string& why)
{
  vtkWarningWithObjectMacro(filter, << "the kind of the picture was not checked: " << why);
}

/// The field and the warning of `check`'s result; the user's Abort ends the filter's run as
/// cancelled, any other failure (an unreadable network, a full disk) is a warning and the result
/// stands.
void report(vtkAlgorithm* filter, vtkFieldData* fd, const std::function<KindCheck()>& check)
{
  try
  {
    const KindCheck c = check();
    auto a = vtkSmartPointer<vtkStringArray>::New();
    a->SetName("Kind");
    a->InsertNextValue(kindCheckToJson(c));
    fd->AddArray(a);
    if (c.differs)
      vtkWarningWithObjectMacro(filter, << describeKindCheck(c));
  }
  catch (const Cancelled&)
  {
    throw;
  }
  catch (const std::exception& e)
  {
    notChecked(filter, firstLine(e.what()));
  }
}
} // namespace
#endif

// (the parameters are unused in a build without libtorch)
void addKindCheck([[maybe_unused]] vtkAlgorithm* filter, [[maybe_unused]] vtkFieldData* fd,
  [[maybe_unused]] std::shared_ptr<KindChecker>& checker, [[maybe_unused]] const std::string& dir,
  [[maybe_unused]] const Image& picture, [[maybe_unused]] const Volume& volume,
  [[maybe_unused]] const std::string& fingerprint)
{
#ifdef DDG_WITH_TORCH
  if (dir.empty())
    return;
  if (!checker)
    checker = std::make_shared<KindChecker>();
  const Stage stage(filter);
  report(filter, fd,
    [&] { return checker->check(dir, picture, volume, fingerprint, 0, progressOf(filter)); });
#endif
}

void addKindCheckOnRanks([[maybe_unused]] vtkAlgorithm* filter, [[maybe_unused]] vtkFieldData* fd,
  [[maybe_unused]] std::shared_ptr<KindChecker>& checker, [[maybe_unused]] const std::string& dir,
  [[maybe_unused]] const Image& picture, [[maybe_unused]] const RankGroup& ranks,
  [[maybe_unused]] const RankVolume& pieces,
  [[maybe_unused]] const std::string& firstRankFingerprint)
{
#ifdef DDG_WITH_TORCH
  if (dir.empty())
    return;
  if (!checker)
    checker = std::make_shared<KindChecker>();
  const bool first = ranks.rank() == 0;
  std::optional<Stage> stage;
  if (first)
    stage.emplace(filter);
  std::string failure; // the first rank's: why the check was not made
  // collective: `work` on the first rank, its failure kept as `failure`; the user's Abort stops
  // every rank (RankGroup::step)
  auto onFirst = [&](const std::function<void()>& work)
  {
    ranks.step(
      [&]
      {
        if (!first || !failure.empty())
          return;
        try
        {
          work();
        }
        catch (const Cancelled&)
        {
          throw;
        }
        catch (const std::exception& e)
        {
          failure = firstLine(e.what());
        }
      });
  };
  // a reference drawn from a volume averaged down is not one process's of the whole: kept apart
  const int factor = designSpaceFactor(pieces.brick.wholeDims, kMaxDesignSpaceVoxels);
  const std::string fingerprint = factor == 1
    ? firstRankFingerprint
    : firstRankFingerprint + " averaged down by " + std::to_string(factor);
  std::string need;
  onFirst([&] { need = checker->hasReference(dir, fingerprint) ? "" : "new"; });
  if (!ranks.broadcast(need).empty())
  {
    // the reference's exemplars are drawn on the first rank from the design-space volume (the
    // whole volume itself up to kMaxDesignSpaceVoxels: then the same reference as one process's)
    DesignSpaceInput input;
    try
    {
      input = designSpaceInputOnRanks(ranks, pieces, kMaxDesignSpaceVoxels);
    }
    catch (const RankFailed&) // the first rank says why
    {
      failure = "another rank failed";
    }
    catch (const std::exception& e)
    {
      failure = firstLine(e.what());
    }
    if (failure.empty()) // every rank agrees: the assembly fails on all of them together
      onFirst(
        [&] { checker->addReference(dir, fingerprint, input.volume, 0, progressOf(filter)); });
  }
  if (!first)
    return;
  if (!failure.empty())
    notChecked(filter, failure);
  else
    report(filter, fd, [&] { return checker->check(dir, picture, fingerprint); });
#endif
}

const std::string& RanksFingerprint::get(
  const RankGroup& ranks, const RankVolume& pieces, vtkImageData* input, vtkDataArray* array)
{
  if (Stamp.changedOnAnyRank(ranks, input, array))
  {
    Stamp.clear();
    Value = fingerprintOnRanks(ranks, pieces);
    Stamp.keep(input, array);
  }
  return Value;
}

} // namespace ddg
