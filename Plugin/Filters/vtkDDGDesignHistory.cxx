// vtkDDGDesignHistory.cxx: Core's history steps and JSON behind a wrapped VTK object.
#include "vtkDDGDesignHistory.h"

#include "Common/Error.h"
#include "Gallery/History.h"
#include "Gallery/Navigation.h"
#include "Render/View.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <vtkObjectFactory.h>

#include <nlohmann/json.hpp>

vtkStandardNewMacro(vtkDDGDesignHistory);

struct vtkDDGDesignHistory::Internals
{
  ddg::DesignHistory History;
  std::string Error;

  /// Runs `f`; false (and the message kept) when it throws.
  template <class F>
  bool attempt(F&& f)
  {
    try
    {
      f();
      Error.clear();
      return true;
    }
    catch (const std::exception& e)
    {
      Error = e.what();
      return false;
    }
  }
};

vtkDDGDesignHistory::vtkDDGDesignHistory()
  : Internal(new Internals)
{
}

vtkDDGDesignHistory::~vtkDDGDesignHistory() = default;

void vtkDDGDesignHistory::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Steps: " << this->GetNumberOfSteps() << "\n";
}

std::string vtkDDGDesignHistory::GetJSON() const
{
  return this->Internal->History.steps.empty() ? std::string() : this->Internal->History.toJson();
}

bool vtkDDGDesignHistory::SetJSON(const std::string& json)
{
  return this->Internal->attempt(
    [&]
    {
      this->Internal->History = json.empty()
        ? ddg::DesignHistory()
        : ddg::DesignHistory::fromJson(json, "the design's history");
      this->Modified();
    });
}

int vtkDDGDesignHistory::GetNumberOfSteps() const
{
  return static_cast<int>(this->Internal->History.steps.size());
}

std::string vtkDDGDesignHistory::GetAction(int i) const
{
  const auto& steps = this->Internal->History.steps;
  return i >= 0 && static_cast<size_t>(i) < steps.size() ? steps[static_cast<size_t>(i)].action
                                                         : std::string();
}

void vtkDDGDesignHistory::Clear()
{
  this->Internal->History.steps.clear();
  this->Modified();
}

void vtkDDGDesignHistory::RemoveLastStep()
{
  if (!this->Internal->History.steps.empty())
  {
    this->Internal->History.steps.pop_back();
    this->Modified();
  }
}

void vtkDDGDesignHistory::Append(vtkDDGDesignHistory* other)
{
  if (!other || other == this)
    return;
  const auto& steps = other->Internal->History.steps;
  this->Internal->History.steps.insert(
    this->Internal->History.steps.end(), steps.begin(), steps.end());
  this->Modified();
}

void vtkDDGDesignHistory::AddQuery(const std::string& image)
{
  this->Internal->History.steps.push_back(ddg::HistoryStep::query(image));
  this->Modified();
}

void vtkDDGDesignHistory::AddPick(int row)
{
  this->Internal->History.steps.push_back(ddg::HistoryStep::pick(row));
  this->Modified();
}

bool vtkDDGDesignHistory::AddLatent(const std::string& latentJson, const std::string& image)
{
  return this->Internal->attempt(
    [&]
    {
      const auto z = nlohmann::json::parse(latentJson).get<std::vector<float>>();
      this->Internal->History.steps.push_back(ddg::HistoryStep::latentDesign(z, image));
      this->Modified();
    });
}

bool vtkDDGDesignHistory::AddBlend(const std::string& latentsJson, double u, double v)
{
  return this->Internal->attempt(
    [&]
    {
      const auto z = nlohmann::json::parse(latentsJson).get<std::vector<std::vector<float>>>();
      this->Internal->History.steps.push_back(ddg::HistoryStep::blend(z, u, v));
      this->Modified();
    });
}

bool vtkDDGDesignHistory::AddEdit(const std::string& viewJson, int cluster, int pickX, int pickY,
  int clusters, double hue, double saturation, double lightness, double visibility, bool white)
{
  return this->Internal->attempt(
    [&]
    {
      // the history holds the view as JSON: refused here if it is not
      [[maybe_unused]] const auto view = nlohmann::json::parse(viewJson);
      this->Internal->History.steps.push_back(ddg::HistoryStep::edit(
        viewJson, cluster, pickX, pickY, clusters, hue, saturation, lightness, visibility, white));
      this->Modified();
    });
}

bool vtkDDGDesignHistory::AddMatch(const std::string& image, const std::string& viewJson,
  bool cameraEstimated, const std::string& tfJson, bool twoD, int bins, int iterations)
{
  return this->Internal->attempt(
    [&]
    {
      ddg::parseView(viewJson, "the match's view");
      (void)ddg::parseTransferFunctionFile(tfJson, "the match's TF");
      auto& steps = this->Internal->History.steps;
      const auto step =
        ddg::HistoryStep::match(image, viewJson, cameraEstimated, tfJson, twoD, bins, iterations);
      if (!steps.empty() && steps.back().action == "match")
        steps.back() = step;
      else
        steps.push_back(step);
      this->Modified();
    });
}

bool vtkDDGDesignHistory::SetAxes(const std::string& stepsJson)
{
  return this->Internal->attempt(
    [&]
    {
      this->Internal->History.setAxes(nlohmann::json::parse(stepsJson).get<std::vector<double>>());
      this->Modified();
    });
}

std::string vtkDDGDesignHistory::GetError() const
{
  return this->Internal->Error;
}

double vtkDDGDesignHistory::Ease(double t, const std::string& easing)
{
  try
  {
    return ddg::ease(t, easing);
  }
  catch (const std::exception&)
  {
    return -1;
  }
}
