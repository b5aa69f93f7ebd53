// DDGKindCheck.cxx: the kind check's field and warning (see DDGKindCheck.h).
#include "DDGKindCheck.h"

#include "Common/Error.h"
#ifdef DDG_WITH_TORCH
#include "Neural/KindNetwork.h"
#include "Render/RayCaster.h" // ddg::Cancelled
#endif

#include <vtkAlgorithm.h>
#include <vtkFieldData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>

namespace ddg
{

void addKindCheck(vtkAlgorithm* filter, vtkFieldData* fd, std::shared_ptr<KindChecker>& checker,
  const std::string& dir, const Image& picture, const Volume& volume)
{
#ifdef DDG_WITH_TORCH
  if (dir.empty())
    return;
  if (!checker)
    checker = std::make_shared<KindChecker>();
  struct Stage // the filter's progress text is "kind" meanwhile, whatever ends the check
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
  } stage(filter);
  try
  {
    const KindCheck c = checker->check(dir, picture, volume, 0,
      [&](double f)
      {
        filter->UpdateProgress(f);
        return !filter->GetAbortExecute();
      });
    auto a = vtkSmartPointer<vtkStringArray>::New();
    a->SetName("Kind");
    a->InsertNextValue(kindCheckToJson(c));
    fd->AddArray(a);
    if (c.differs)
      vtkWarningWithObjectMacro(filter, << describeKindCheck(c));
  }
  catch (const Cancelled&) // the user's Abort: the filter's run ends as cancelled
  {
    throw;
  }
  catch (const std::exception& e) // an unreadable network, a full disk: the result stands
  {
    vtkWarningWithObjectMacro(
      filter, << "the kind of the picture was not checked: " << firstLine(e.what()));
  }
#else
  (void)filter;
  (void)fd;
  (void)checker;
  (void)dir;
  (void)picture;
  (void)volume;
#endif
}

} // namespace ddg
