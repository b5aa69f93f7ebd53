// MatchLighting.cxx: matchPicture — the picture's lighting given, or estimated: matched unlit and
// lit, refitted with specular at the lit camera, the best fit kept.
#include "Reconstruct/Match.h"

#include "Common/Error.h"
#include "Reconstruct/MatchCamera.h"
#include "Reconstruct/MatchParts.h"

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace ddg
{

namespace
{

// The lightings a picture is matched with when nobody says: unlit, ParaView's Shade with its
// default coefficients, and with Specular 0.5 / SpecularPower 30 (shiny surfaces).
std::vector<std::pair<std::string, Lighting>> lightingCandidates()
{
  Lighting shade;
  shade.shade = true;
  Lighting specular = shade;
  specular.specular = 0.5;
  specular.specularPower = 30;
  return { { "unlit", Lighting{} }, { "Shade on", shade },
    { "Shade on, Specular 0.5 / power 30", specular } };
}

} // namespace

std::string noCameraExplains(
  double fitPSNR, double minimum, double overlap, const std::string& matched)
{
  std::ostringstream msg;
  msg.precision(3);
  msg << "no camera explains the picture: the best match differs from it by " << fitPSNR
      << " dB PSNR over the object (at least " << minimum << " dB needed; silhouette overlap "
      << std::lround(100 * overlap) << " %" << (matched.empty() ? "" : "; matched " + matched)
      << ") — is it a picture of this volume, uncropped?";
  return msg.str();
}

MatchResult matchPicture(const DifferentiableRenderer& renderer, const Image& picture,
  const MatchOptions& options, const MatchProgress& progress)
{
  if (options.lighting || options.view)
    return matchPictureLit(renderer, picture, options, progress);
  // Unknown: the whole match unlit and with Shade on (the camera search's short fits and polish
  // see the lighting: an unlit search can miss a lit picture's camera), then the TF refitted
  // with Specular at the lit match's camera; the best fit over the object is kept and the
  // refusal judged on it. Progress: each match 45 %, the refit 10 %.
  const auto candidates = lightingCandidates();
  std::ostringstream fits;
  fits.precision(3);
  std::optional<MatchResult> best;
  double second = -std::numeric_limits<double>::infinity();
  double stage[4] = { 0, 0, 0, 0 }; // seconds of every lighting's match, summed
  MatchResult::CameraStages cameraStages;
  auto consider = [&](MatchResult r, const std::string& name)
  {
    cameraStages += r.cameraStages;
    stage[0] += r.backgroundSeconds;
    stage[1] += r.cameraSeconds;
    stage[2] += r.fitSeconds;
    stage[3] += r.seconds;
    fits << (best ? ", " : "") << name << " " << r.fitPSNR << " dB";
    if (!best || r.fitPSNR > best->fitPSNR)
    {
      second = best ? best->fitPSNR : second;
      best = std::move(r);
    }
    else
    {
      second = std::max(second, r.fitPSNR);
    }
  };
  const auto part = [&](double start, double share)
  {
    return [&progress, start, share](const std::string& stage, double f, const Image* preview)
    { return !progress || progress(stage, start + share * f, preview); };
  };
  std::optional<MatchResult> litMatch; // its camera and search figures
  // the camera search's lighting-free stages: run by the unlit match, taken by the lit one
  matchparts::CameraSearchStages stages;
  for (size_t i = 0; i < 2; ++i) // unlit, Shade on: whole matches (a refusal there is final)
  {
    MatchOptions o = options;
    o.lighting = candidates[i].second;
    o.minimumFitPSNR = -std::numeric_limits<double>::infinity();
    MatchResult r = matchPictureLit(renderer, picture, o, part(0.45 * i, 0.45), &stages);
    if (i == 1)
      litMatch = r;
    consider(std::move(r), candidates[i].first);
  }
  for (size_t i = 2; i < candidates.size(); ++i) // the specular ones: refits at that camera
  {
    MatchOptions o = options;
    o.minimumFitPSNR = -std::numeric_limits<double>::infinity();
    o.view = litMatch->view;
    o.view->lighting = candidates[i].second;
    o.refineGivenView = false;
    MatchResult r = matchPictureLit(renderer, picture, o, part(0.9, 0.1));
    // the camera is the lit match's: keep its search figures
    r.cameraEstimated = litMatch->cameraEstimated;
    r.orbit = litMatch->orbit;
    r.zoom = litMatch->zoom;
    r.pan = litMatch->pan;
    r.overlap = litMatch->overlap;
    consider(std::move(r), candidates[i].first);
  }
  if (best->cameraEstimated && best->fitPSNR < options.minimumFitPSNR)
  {
    throw Error(noCameraExplains(best->fitPSNR, options.minimumFitPSNR, best->overlap, fits.str()));
  }
  best->lightingEstimated = true;
  best->otherLightingFitPSNR = second;
  // the time the estimate took: every lighting's stages, not the kept one's alone
  best->backgroundSeconds = stage[0];
  best->cameraSeconds = stage[1];
  best->fitSeconds = stage[2];
  best->seconds = stage[3];
  best->cameraStages = cameraStages;
  return *best;
}

} // namespace ddg
