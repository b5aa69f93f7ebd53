// ViewEstimation.h: finds the camera of a target image whose view is not known exactly.
#pragma once

#include "Reconstruct/Reconstruction.h"

#include <string>
#include <vector>

namespace ddg
{

/// Options (defaults in brackets).
struct ViewEstimationOptions
{
  double azimuthStep = 30;   ///< coarse grid: azimuth 0..360 in these steps [30 degrees]
  double elevationStep = 30; ///< elevation -60..60 in these steps [30 degrees]
  std::vector<double> zooms{ 0.8, 1.0, 1.25 }; ///< distance factors tried [0.8, 1, 1.25]
  int candidates = 4;   ///< best coarse views scored by a short reconstruction [4]
  int refineRounds = 3; ///< local refinement rounds, halving the steps [3]
  int scoreSize = 64;   ///< image side of the scoring renders [64]
  int scoreSteps = 60;  ///< Adam steps of the short reconstructions [60]
  RenderOptions render;
};

struct ViewEstimationReport
{
  double azimuth = 0, elevation = 0, zoom = 1; ///< of the estimate, relative to the initial view
  double loss = 0;                             ///< short-reconstruction loss at the estimate
  int evaluations = 0;                         ///< short reconstructions run
  double seconds = 0;
};

/// Estimates target.view's camera by orbiting the volume's centre: azimuth about the initial
/// view_up, elevation, and distance (zoom); the view angle, projection, roll and the image
/// size come from target.view and are kept. Stage 1 scores every grid view by how well an
/// occupancy render (opaque above one of three value thresholds) overlaps the target's
/// foreground (IoU of masks); stage 2 runs a short TF reconstruction at the best `candidates`
/// views (small images) and keeps the lowest loss; stage 3 refines azimuth, elevation and zoom
/// locally with the same score. Fails on near-symmetric objects (mirror views score alike),
/// panned or cropped screenshots (the orbit is centred), and rolled cameras.
View estimateView(const DifferentiableRenderer& renderer, const ReconstructionTarget& target,
  const ViewEstimationOptions& options = {}, ViewEstimationReport* report = nullptr);

/// The view orbited from `base` about its focal point: azimuth about base's view_up, then
/// elevation about the right vector, distance divided by zoom (parallel scale too).
View orbitView(const View& base, double azimuthDeg, double elevationDeg, double zoom);

} // namespace ddg
