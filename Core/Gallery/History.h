// History.h: the path a user took through the design space (query -> picks -> edits -> TF),
// as a JSON file that replays it.
#pragma once

#include "Gallery/Gallery.h"
#include "TransferFunction/TransferFunctionIO.h"

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
  /// pick, hue, saturation, lightness, visibility, clusters, white), "axes" (steps), "match"
  /// (image, view, camera, two_d, bins, iterations, tf: the design matched to a picture at its
  /// camera — the last step; it leaves the design as it is and gives the TF, see replayMatch).
  std::string action;
  std::string image;                       ///< query: the image file
  int row = -1;                            ///< pick: the outline row
  std::vector<int> rows;                   ///< blend: 2-4 outline rows
  std::vector<float> latent;               ///< latent: the design
  std::vector<std::vector<float>> latents; ///< blend: 2-4 latents (instead of rows)
  double u = 0, v = 0;                     ///< blend
  std::string viewJson;                    ///< edit: the view the edit was made at (view JSON)
  int cluster = -1;                        ///< edit: the colour cluster (or -1 with pickX/pickY)
  int pickX = -1, pickY = -1;              ///< edit: the pixel whose cluster was edited
  int clusters = 4;                        ///< edit: clusters found
  double hue = 0, saturation = 1, lightness = 0, visibility = 1; ///< edit
  bool white = false;           ///< edit: re-analyzed over white instead of black
  std::vector<double> steps;    ///< axes
  bool cameraEstimated = false; ///< match: the camera was estimated ("camera": "estimated")
  bool twoD = false;            ///< match: a 2D TF
  int bins = 128;               ///< match: TF bins along the value
  int iterations = 500;         ///< match: the fit's steps
  std::string tfJson; ///< match: the TF it gave (preset or 2D JSON), for an unreadable picture

  /// The steps as the front ends record them (the one place that builds each kind).
  static HistoryStep query(const std::string& image);
  static HistoryStep pick(int row);
  /// A design given by its latent; `image` may name the picture it was queried with.
  static HistoryStep latentDesign(const std::vector<float>& latent, const std::string& image = "");
  /// A cell (u, v) of the navigation grid between 2-4 latents.
  static HistoryStep blend(const std::vector<std::vector<float>>& latents, double u, double v);
  /// An edit of a colour cluster (cluster >= 0) or of the cluster under pixel (pickX, pickY), at
  /// the view given as view JSON.
  static HistoryStep edit(const std::string& viewJson, int cluster, int pickX, int pickY,
    int clusters, double hue, double saturation, double lightness, double visibility, bool white);
  static HistoryStep axes(const std::vector<double>& steps);
  /// The design matched to the picture `image` at the camera `viewJson` (found or given), with
  /// the TF it gave (a preset or 2D TF file's JSON).
  static HistoryStep match(const std::string& image, const std::string& viewJson,
    bool cameraEstimated, const std::string& tfJson, bool twoD, int bins, int iterations);
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
  /// Throws ddg::Error (naming `origin`) when a "match" step is not the last step.
  void checkMatchLast(const std::string& origin) const;

  /// Appends an "axes" step, or replaces the last step when it is one (the principal-axis
  /// sliders move one design, not a chain of them).
  void setAxes(const std::vector<double>& steps);
};

/// An edit of a design's image (what an "edit" step does, plus a brushed mask, which histories
/// do not record): colour clusters of its render at `view`, one of them (or the mask) recoloured
/// and made more or less visible, the result re-analyzed over black or white.
struct DesignEdit
{
  View view;
  int clusters = 4;           ///< colour clusters found in the render
  int cluster = -1;           ///< the cluster edited, or -1 with pickX/pickY or a mask
  int pickX = -1, pickY = -1; ///< the pixel whose cluster is edited
  Image mask;                 ///< a brushed mask (one channel at the view's size), or empty
  double hue = 0, saturation = 1, lightness = 0, visibility = 1;
  bool white = false; ///< re-analyzed over white instead of black

  /// The edit of a history step.
  static DesignEdit fromStep(const HistoryStep& step);
  /// The history step of this edit (throws ddg::Error for a masked edit: not recordable).
  HistoryStep toStep() const;
};

/// What an edit gives.
struct DesignEditResult
{
  std::vector<float> latent; ///< the re-analyzed design
  Image before, edited;      ///< the render and the edited image (premultiplied RGBA)
  ColorClusters clusters;    ///< the render's colour clusters
  int cluster = -1;          ///< the cluster edited (-1 for a mask)
};

/// Applies `edit` to the design `latent` (under `lock`, if any). Throws ddg::Error when the edit
/// names nothing (no cluster, pick or mask) or picks a background pixel.
DesignEditResult editDesign(const DesignGallery& gallery, const std::vector<float>& latent,
  const DesignEdit& edit, const FeatureLock* lock = nullptr);

/// Applies one step to the current latent (empty before the first step) and returns the new
/// one. Image paths in query steps are read as given (relative to the working directory).
std::vector<float> applyHistoryStep(
  const DesignGallery& gallery, const HistoryStep& step, const std::vector<float>& current);

/// Replays every step: the design the path ends on (a "match" step leaves it as it is).
std::vector<float> replayHistory(const DesignGallery& gallery, const DesignHistory& history);

/// What a "match" step gives: the design `latent`'s TF matched again to the step's picture at
/// the step's camera (Core's matchPicture, the camera given), or, when the picture cannot be
/// read (a pasted picture), the TF the step recorded. `rematched` tells which; `fitPSNR` the
/// new fit's PSNR over the object (0 when not rematched).
TransferFunctionFile replayMatch(const DesignGallery& gallery, const std::vector<float>& latent,
  const HistoryStep& step, bool* rematched = nullptr, double* fitPSNR = nullptr);

} // namespace ddg
