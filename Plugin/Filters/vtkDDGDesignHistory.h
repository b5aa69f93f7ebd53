// vtkDDGDesignHistory.h: a design's history (Core's DesignHistory) for the front ends that do
// not link Core — the panel and pvpython build their history steps and JSON through it, so
// that every history file is written by one writer.
#ifndef vtkDDGDesignHistory_h
#define vtkDDGDesignHistory_h

#include "DDGFiltersModule.h" // export macro
#include "vtkObject.h"

#include <memory> // for std::unique_ptr
#include <string> // for std::string

/**
 * @class vtkDDGDesignHistory
 * @brief The steps that lead to a design (Core/Gallery/History.h) and their history JSON
 * ({"format": "ddg-history", "version": 1, "steps": [...]}, the file `ddg replay` reads and
 * vtkDDGDesign's History property takes).
 *
 * Latents are passed as JSON text (a list of numbers; a list of lists for a blend). Methods that
 * take text return false for text they cannot use and keep the history unchanged; GetError
 * says why.
 */
class DDGFILTERS_EXPORT vtkDDGDesignHistory : public vtkObject
{
public:
  static vtkDDGDesignHistory* New();
  vtkTypeMacro(vtkDDGDesignHistory, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The history JSON, or "" when there is no step.
  std::string GetJSON() const;
  /// Replaces the steps by those of a history JSON ("" empties the history).
  bool SetJSON(const std::string& json);

  int GetNumberOfSteps() const;
  /// The action of step i ("query", "pick", "latent", "blend", "edit", "axes"), or "".
  std::string GetAction(int i) const;
  void Clear();
  void RemoveLastStep();
  /// Appends the steps of another history.
  void Append(vtkDDGDesignHistory* other);

  ///@{
  /// Appends a step (HistoryStep's builders).
  void AddQuery(const std::string& image);
  void AddPick(int row);
  bool AddLatent(const std::string& latentJson, const std::string& image);
  bool AddBlend(const std::string& latentsJson, double u, double v);
  bool AddEdit(const std::string& viewJson, int cluster, int pickX, int pickY, int clusters,
    double hue, double saturation, double lightness, double visibility, bool white);
  /// The design matched to a picture (HistoryStep::match): replaces a match that ends the
  /// history (a new match of the same design), else appends; false for a view or TF Core
  /// cannot read.
  bool AddMatch(const std::string& image, const std::string& viewJson, bool cameraEstimated,
    const std::string& tfJson, bool twoD, int bins, int iterations);
  ///@}
  /// An "axes" step, replacing the last step when it is one (DesignHistory::setAxes).
  bool SetAxes(const std::string& stepsJson);

  /// The message of the last call that returned false.
  std::string GetError() const;

  /// Easing of an animation (Core's ease): "linear", "smoothstep" or "cosine" at t in [0, 1];
  /// -1 for an unknown easing.
  static double Ease(double t, const std::string& easing);

protected:
  vtkDDGDesignHistory();
  ~vtkDDGDesignHistory() override;

private:
  vtkDDGDesignHistory(const vtkDDGDesignHistory&) = delete;
  void operator=(const vtkDDGDesignHistory&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
