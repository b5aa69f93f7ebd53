// History.h: the path a user took through the design space (query -> picks -> edits -> TF),
// as a JSON file that replays it.
#pragma once

#include "Gallery/Gallery.h"

#include <string>
#include <vector>

namespace ddg
{

/// One step. JSON: {"action": ..., and the fields the action uses}.
struct HistoryStep
{
  /// "query" (image), "pick" (row), "latent" (latent: a design given by its latent, e.g. a
  /// query's result whose image the replaying process cannot read; "image" may name it),
  /// "blend" (rows or latents, u, v: a cell of a navigation grid), "edit" (view, cluster or
  /// pick, hue, saturation, lightness, visibility, clusters, white), "axes" (steps).
  std::string action;
  std::string image;           ///< query: the image file
  int row = -1;                ///< pick: the outline row
  std::vector<int> rows;       ///< blend: 2-4 outline rows
  std::vector<float> latent;   ///< latent: the design
  std::vector<std::vector<float>> latents; ///< blend: 2-4 latents (instead of rows)
  double u = 0, v = 0;         ///< blend
  std::string viewJson;        ///< edit: the view the edit was made at (view JSON)
  int cluster = -1;            ///< edit: the colour cluster (or -1 with pickX/pickY)
  int pickX = -1, pickY = -1;  ///< edit: the pixel whose cluster was edited
  int clusters = 4;            ///< edit: clusters found
  double hue = 0, saturation = 1, lightness = 0, visibility = 1; ///< edit
  bool white = false;          ///< edit: re-analyzed over white instead of black
  std::vector<double> steps;   ///< axes
};

/// A replayable path. JSON file: {"format": "ddg-history", "version": 1, "steps": [...]}.
struct DesignHistory
{
  std::vector<HistoryStep> steps;

  std::string toJson() const;
  /// Throws ddg::Error naming the step for unknown actions or missing/invalid fields, and for a
  /// history that does not start with "query", "pick", "latent" or "blend" (what gives the first
  /// design).
  static DesignHistory fromJson(const std::string& text, const std::string& origin = "history");
  static DesignHistory read(const std::string& path);
  void write(const std::string& path) const;
};

/// Applies one step to the current latent (empty before the first step) and returns the new
/// one. Image paths in query steps are read as given (relative to the working directory).
std::vector<float> applyHistoryStep(
  const DesignGallery& gallery, const HistoryStep& step, const std::vector<float>& current);

/// Replays every step: the design the path ends on.
std::vector<float> replayHistory(const DesignGallery& gallery, const DesignHistory& history);

} // namespace ddg
