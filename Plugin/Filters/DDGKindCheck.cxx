// DDGKindCheck.cxx: the kind check's field and warning (see DDGKindCheck.h).
#include "DDGKindCheck.h"

#include "Common/Error.h"
#ifdef DDG_WITH_TORCH
#include "Neural/KindNetwork.h"
#include "Render/RayCaster.h" // ddg::Cancelled
#endif

#include <nlohmann/json.hpp>

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
  const char* stage = filter->GetProgressText();
  const std::string before = stage ? stage : "";
  filter->SetProgressText("kind");
  try
  {
    const KindCheck c = checker->check(dir, picture, volume, 0,
      [&](double f)
      {
        filter->UpdateProgress(f);
        return !filter->GetAbortExecute();
      });
    const nlohmann::json j{ { "agreement", c.agreement }, { "threshold", c.threshold },
      { "differs", c.differs }, { "picture_like", c.pictureLike },
      { "volume_like", c.volumeLike } };
    auto a = vtkSmartPointer<vtkStringArray>::New();
    a->SetName("Kind");
    a->InsertNextValue(j.dump());
    fd->AddArray(a);
    if (c.differs)
      vtkWarningWithObjectMacro(filter,
        << "the picture may show a volume of another kind: kind agreement " << c.agreement
        << " < " << c.threshold << " (the picture is most like " << c.pictureLike
        << ", this volume like " << c.volumeLike << ")");
  }
  catch (const Error& e)
  {
    vtkWarningWithObjectMacro(filter, << "the kind of the picture was not checked: " << e.what());
  }
  filter->SetProgressText(before.empty() ? nullptr : before.c_str());
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
