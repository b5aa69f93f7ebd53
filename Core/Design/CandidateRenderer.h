// CandidateRenderer.h: what rendering a design space's candidates needs (the volume's ray caster,
// the box's corners, the feature regions, the auxiliary TF), made once per generation — by
// generateExemplars, by buildOutlineLatents and, from a setup message, by a worker process that
// holds the same volume — and the workers that render shares of a batch.
#pragma once

#include "Design/DesignCheck.h"
#include "Design/DesignSpace.h"
#include "Image/Image.h"
#include "Render/RayCaster.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace ddg
{

/// Processes besides this one that render candidates for generateExemplars and
/// buildOutlineLatents, each holding the same volume, bit for bit (the ranks of `mpiexec -np N
/// pvserver`: the plugin's DDGBuildRanks.h). Each gets a contiguous share of every batch, this
/// process the first; the messages are Core's (serveExemplars answers them), the transport the
/// implementer's.
class ExemplarWorkers
{
public:
  virtual ~ExemplarWorkers() = default;
  /// The workers (0: this process renders alone).
  virtual int size() const = 0;
  /// Sends `message` to worker w (without waiting for its answer).
  virtual void send(int worker, const std::string& message) = 0;
  /// Worker w's answer to its last render message (waits; throws ddg::Error when it stopped).
  virtual std::string receive(int worker) = 0;
};

/// A worker's side: answers the messages of generateExemplars and buildOutlineLatents from
/// another process with `volume` (a "setup" per generation, then batches of candidates, rendered
/// by `threads` threads, 0 = all cores) until the message "end". The results are the ones this
/// process would render itself. Throws ddg::Error for a message it does not know, and what
/// `receive` or `send` throw.
void serveExemplars(const Volume& volume, const std::function<std::string()>& receive,
  const std::function<void(const std::string&)>& send, int threads = 0);

/// Candidates of a design space (sampleExemplar's draws) rendered as exemplar records or outline
/// images, here or by workers. The volume must outlive it.
class CandidateRenderer
{
public:
  CandidateRenderer(
    const Volume& volume, const DesignSpaceSpec& spec, int size, std::uint64_t seed, bool viewport);
  /// A worker's, from setup()'s text.
  static std::unique_ptr<CandidateRenderer> fromSetup(
    const Volume& volume, const std::string& text);

  /// Bytes of one exemplar record at `size` pixels (RGB at V_exp, viewport and truth RGBA).
  static size_t recordBytes(int size);

  const RayCaster& caster() const { return Caster; }
  const BoxCorners& corners() const { return Corners; }
  /// The feature regions the candidates are drawn over (before any render).
  void setRegions(std::vector<FeatureRegion> regions);
  /// What a worker needs to render candidates as this process does.
  std::string setup() const;
  /// Sends `workers` (may be null) the setup: before the first batch of each generation.
  void setUpWorkers(ExemplarWorkers* workers) const;

  /// Exemplar candidate `index`: its record (left as it is when junk), the exemplar and, when
  /// screening, the verdict.
  void renderExemplar(std::uint64_t index, bool screening, std::uint8_t* record, Exemplar& drawn,
    DesignVerdict& verdict) const;
  /// Outline candidate `index`: its RGB image at V_exp over its background; false (and no image)
  /// when screening finds it junk.
  bool renderOutline(std::uint64_t index, bool screening, Image& rgb) const;

  /// Candidates [first, first + count) rendered in shares by this process (the first share, on
  /// `threads` threads, `each(q, threadId)` after each of its candidates; it may throw, e.g.
  /// Cancelled) and by `workers` (may be null), into the arrays at q = index - first:
  /// exemplars (records, drawn, verdicts), or outline images (images; junk: an empty image).
  /// exemplars() returns the candidates the workers rendered.
  int exemplars(std::uint64_t first, int count, bool screening, ExemplarWorkers* workers,
    int threads, std::uint8_t* records, Exemplar* drawn, DesignVerdict* verdicts,
    const std::function<void(std::int64_t q, int threadId)>& each) const;
  void outline(std::uint64_t first, int count, bool screening, ExemplarWorkers* workers,
    int threads, Image* images) const;

  /// A worker's answer to a message ("exemplars FIRST COUNT SCREENING" or "outline ...").
  std::string answer(const std::string& request, int threads) const;

private:
  const Volume& TheVolume;
  DesignSpaceSpec Spec;
  int Size;
  std::uint64_t Seed;
  bool Viewport;
  RayCaster Caster;
  BoxCorners Corners;
  std::array<double, 2> GradientRange;
  std::vector<FeatureRegion> Regions;
  std::vector<GaussianPrimitive> Aux;
  RenderOptions Options;
};

} // namespace ddg
