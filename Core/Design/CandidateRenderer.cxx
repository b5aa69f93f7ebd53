// CandidateRenderer.cxx: one candidate's renders, a batch in shares, the workers' messages.
#include "Design/CandidateRenderer.h"

#include "Design/DesignJson.h"
#include "Design/DesignSpace.h"
#include "Gallery/QueryImage.h"

#include "Common/Error.h"
#include "Common/Parallel.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace ddg
{
namespace
{
using nlohmann::json;

void toBytes(const Image& img, std::uint8_t* out)
{
  for (size_t i = 0; i < img.pixels.size(); ++i)
  {
    out[i] = static_cast<std::uint8_t>(std::lround(std::clamp(img.pixels[i], 0.0f, 1.0f) * 255.0f));
  }
}

// A picture's colour legend: the design's colours in the order of their values.
std::vector<std::array<double, 3>> legend(std::vector<GaussianPrimitive> tf)
{
  std::sort(tf.begin(), tf.end(),
    [](const GaussianPrimitive& a, const GaussianPrimitive& b) { return a.mean[0] < b.mean[0]; });
  std::vector<std::array<double, 3>> colours;
  for (const auto& g : tf)
    colours.push_back({ g.rgb[0], g.rgb[1], g.rgb[2] });
  return colours;
}

// The head of a worker's answer to a message: the message itself, then a newline ("error
// MESSAGE" instead when the worker failed).
std::string answerHead(const std::string& request)
{
  return "answer " + request + "\n";
}

// Checks that `in` answers `request` (throws the worker's error, or one for an answer to
// another message); returns where its body starts.
size_t answerBody(const std::string& in, const std::string& request)
{
  if (in.rfind("error ", 0) == 0)
    throw Error(in.substr(6));
  const std::string head = answerHead(request);
  if (in.compare(0, head.size(), head) != 0)
    throw Error("an exemplar worker answered another message than '" + request + "'");
  return head.size();
}

// A render message: "KIND FIRST COUNT SCREENING".
std::string shareMessage(const char* kind, std::uint64_t first, int count, bool screening)
{
  return std::string(kind) + " " + std::to_string(first) + " " + std::to_string(count) + " " +
    (screening ? "1" : "0");
}
// The share of candidates [0, count) of process p of `processes` (this one is 0).
int shareStart(int count, int p, int processes)
{
  return static_cast<int>(static_cast<std::int64_t>(count) * p / processes);
}

// Sends every worker its share's message; returns the number of processes.
int sendShares(
  ExemplarWorkers* workers, const char* kind, std::uint64_t first, int count, bool screening)
{
  const int processes = 1 + (workers ? workers->size() : 0);
  for (int w = 1; w < processes; ++w)
  {
    const int q0 = shareStart(count, w, processes), q1 = shareStart(count, w + 1, processes);
    workers->send(w - 1, shareMessage(kind, first + q0, q1 - q0, screening));
  }
  return processes;
}

// Reads a worker's answer in order.
struct Reader
{
  const std::string& in;
  size_t at;
  void done() const
  {
    if (at != in.size())
      throw Error("an exemplar worker's answer is longer than its candidates");
  }
  const char* take(size_t n)
  {
    if (at + n > in.size())
      throw Error("an exemplar worker's answer is truncated");
    const char* p = in.data() + at;
    at += n;
    return p;
  }
};

// Reads every worker's answer to its share (sent by sendShares): `each(reader, q)` takes
// candidate q's bytes, in order; returns the candidates the workers rendered.
int readShares(ExemplarWorkers* workers, const char* kind, std::uint64_t first, int count,
  bool screening, int processes, const std::function<void(Reader&, int)>& each)
{
  for (int w = 1; w < processes; ++w)
  {
    const int q0 = shareStart(count, w, processes), q1 = shareStart(count, w + 1, processes);
    const std::string in = workers->receive(w - 1);
    Reader r{ in, answerBody(in, shareMessage(kind, first + q0, q1 - q0, screening)) };
    for (int q = q0; q < q1; ++q)
      each(r, q);
    r.done();
  }
  return count - shareStart(count, 1, processes);
}
} // namespace

CandidateRenderer::CandidateRenderer(
  const Volume& volume, const DesignSpaceSpec& spec, int size, std::uint64_t seed, bool viewport)
  : TheVolume(volume)
  , Spec(spec)
  , Size(size)
  , Seed(seed)
  , Viewport(viewport)
  , Caster(volume)
  , Corners(volume, spec.dimensions, Caster.defaultOpacityUnitDistance())
  , GradientRange(
      spec.dimensions == 2 ? volume.gradientMagnitudeRange() : std::array<double, 2>{ 0.0, 1.0 })
{
  Options.threads = 1;
}

size_t CandidateRenderer::recordBytes(int size)
{
  return static_cast<size_t>(size) * size * (3 + 4 + 4);
}

void CandidateRenderer::setRegions(std::vector<FeatureRegion> regions)
{
  Regions = std::move(regions);
  Aux = auxiliaryPrimitives(Spec, Regions);
}

std::string CandidateRenderer::setup() const
{
  json j = { { "spec", json::parse(designSpaceSpecToJson(Spec)) }, { "size", Size },
    { "seed", Seed }, { "viewport", Viewport }, { "regions", json::array() },
    { "volume", volumeFingerprint(TheVolume) } };
  for (const auto& r : Regions)
    j["regions"].push_back(regionToJson(r));
  return j.dump();
}

void CandidateRenderer::setUpWorkers(ExemplarWorkers* workers) const
{
  if (!workers)
    return;
  const std::string message = "setup " + setup();
  for (int w = 0; w < workers->size(); ++w)
    workers->send(w, message);
}

std::unique_ptr<CandidateRenderer> CandidateRenderer::fromSetup(
  const Volume& volume, const std::string& text)
{
  try
  {
    const json j = json::parse(text);
    if (j.at("volume").get<std::string>() != volumeFingerprint(volume))
      throw Error("this process's design-space volume (" + volumeFingerprint(volume) +
        ") is not the first process's (" + j.at("volume").get<std::string>() + ")");
    auto r = std::make_unique<CandidateRenderer>(volume,
      parseDesignSpaceSpec(j.at("spec").dump(), "exemplar setup"), j.at("size").get<int>(),
      j.at("seed").get<std::uint64_t>(), j.at("viewport").get<bool>());
    std::vector<FeatureRegion> regions;
    for (const auto& q : j.at("regions"))
      regions.push_back(regionFromJson(q));
    r->setRegions(std::move(regions));
    return r;
  }
  catch (const json::exception& e)
  {
    throw Error(std::string("an exemplar worker's setup is not readable: ") + e.what());
  }
}

void CandidateRenderer::renderExemplar(std::uint64_t index, bool screening, std::uint8_t* out,
  Exemplar& drawn, DesignVerdict& verdict) const
{
  const size_t px = static_cast<size_t>(Size) * Size;
  auto draw = [&](const std::vector<GaussianPrimitive>& tf, const View& view)
  { return renderDesign(Caster, tf, Spec.dimensions, GradientRange, view, Options); };
  Exemplar e = sampleExemplar(TheVolume, Spec, Regions, Seed, index, Size);
  const Image exp = draw(e.primitives, e.viewExp);
  if (screening)
  {
    verdict = screenDesign(Caster, Corners, e.primitives, exp, e.viewExp);
    if (verdict.junk())
      return;
  }
  if (e.picture) // a user's picture of the design, framed as a query is
  {
    const View pv = pictureView(e.viewExp, *e.picture);
    const Image picture = drawPicture(draw(e.primitives, pv), pv, *e.picture, legend(e.primitives));
    if (hasQueryContent(picture))
      toBytes(prepareQueryImage(picture, Size), out);
    else // nothing shows (a query would be refused): the clean image, no look
      e.picture.reset();
  }
  if (!e.picture)
    toBytes(compositeOverBackground(exp, e.viewExp.background), out);
  if (Viewport)
    toBytes(draw(Aux, e.viewView), out + 3 * px);
  else
    std::fill_n(out + 3 * px, 4 * px, std::uint8_t(0));
  toBytes(draw(e.primitives, e.viewView), out + 7 * px);
  drawn = std::move(e);
}

bool CandidateRenderer::renderOutline(std::uint64_t index, bool screening, Image& rgb) const
{
  const Exemplar e = sampleExemplar(TheVolume, Spec, Regions, Seed, index, Size);
  const Image rgba =
    renderDesign(Caster, e.primitives, Spec.dimensions, GradientRange, e.viewExp, Options);
  if (screening && screenDesign(Caster, Corners, e.primitives, rgba, e.viewExp).junk())
    return false;
  rgb = compositeOverBackground(rgba, e.viewExp.background);
  return true;
}

int CandidateRenderer::exemplars(std::uint64_t first, int count, bool screening,
  ExemplarWorkers* workers, int threads, std::uint8_t* records, Exemplar* drawn,
  DesignVerdict* verdicts, const std::function<void(std::int64_t, int)>& each) const
{
  const size_t rec = recordBytes(Size);
  const int processes = sendShares(workers, "exemplars", first, count, screening);
  parallelFor(shareStart(count, 1, processes), threads,
    [&](std::int64_t q, int threadId)
    {
      renderExemplar(first + q, screening, records + rec * q, drawn[q], verdicts[q]);
      if (each)
        each(q, threadId);
    });
  // a worker's candidate: its verdict, record and whether it kept its user's picture (dropped
  // when nothing shows in it); the exemplar itself is drawn again here (the same volume, spec,
  // regions and seed)
  return readShares(workers, "exemplars", first, count, screening, processes,
    [&](Reader& r, int q)
    {
      const char* v = r.take(3);
      verdicts[q].empty = v[0] != 0;
      verdicts[q].flatBox = v[1] != 0;
      std::memcpy(records + rec * q, r.take(rec), rec);
      if (verdicts[q].junk())
        return;
      drawn[q] = sampleExemplar(TheVolume, Spec, Regions, Seed, first + q, Size);
      if (v[2] == 0)
        drawn[q].picture.reset();
    });
}

void CandidateRenderer::outline(std::uint64_t first, int count, bool screening,
  ExemplarWorkers* workers, int threads, Image* images) const
{
  const int processes = sendShares(workers, "outline", first, count, screening);
  parallelFor(shareStart(count, 1, processes), threads,
    [&](std::int64_t q, int)
    {
      if (!renderOutline(first + q, screening, images[q]))
        images[q] = Image();
    });
  const size_t bytes = static_cast<size_t>(Size) * Size * 3 * sizeof(float);
  readShares(workers, "outline", first, count, screening, processes,
    [&](Reader& r, int q)
    {
      images[q] = Image();
      if (*r.take(1) == 0)
        return; // junk
      images[q] = Image(Size, Size, 3);
      std::memcpy(images[q].pixels.data(), r.take(bytes), bytes);
    });
}

std::string CandidateRenderer::answer(const std::string& request, int threads) const
{
  char kind[16] = { 0 };
  unsigned long long first = 0;
  int count = 0, screening = 0;
  if (std::sscanf(request.c_str(), "%15s %llu %d %d", kind, &first, &count, &screening) != 4 ||
    count < 0 || (std::strcmp(kind, "exemplars") != 0 && std::strcmp(kind, "outline") != 0))
    throw Error(
      "an exemplar worker got a message it does not know: '" + request.substr(0, 40) + "'");
  std::string out = answerHead(request);
  if (std::strcmp(kind, "outline") == 0)
  {
    std::vector<Image> images(static_cast<size_t>(count));
    outline(first, count, screening != 0, nullptr, threads, images.data());
    for (const Image& im : images)
    {
      out.push_back(im.pixels.empty() ? 0 : 1);
      out.append(reinterpret_cast<const char*>(im.pixels.data()), im.pixels.size() * sizeof(float));
    }
    return out;
  }
  const size_t rec = recordBytes(Size);
  std::vector<std::uint8_t> records(rec * count);
  std::vector<Exemplar> drawn(static_cast<size_t>(count));
  std::vector<DesignVerdict> verdicts(static_cast<size_t>(count));
  exemplars(first, count, screening != 0, nullptr, threads, records.data(), drawn.data(),
    verdicts.data(), {});
  for (int q = 0; q < count; ++q)
  {
    out.push_back(static_cast<char>(verdicts[q].empty));
    out.push_back(static_cast<char>(verdicts[q].flatBox));
    out.push_back(static_cast<char>(drawn[q].picture.has_value()));
    out.append(reinterpret_cast<const char*>(records.data() + rec * q), rec);
  }
  return out;
}

void serveExemplars(const Volume& volume, const std::function<std::string()>& receive,
  const std::function<void(const std::string&)>& send, int threads)
{
  std::unique_ptr<CandidateRenderer> renderer;
  std::string failed; // why the last setup failed: the answer to its batches
  for (;;)
  {
    const std::string message = receive();
    if (message == "end")
      return;
    if (message.rfind("setup ", 0) == 0)
    {
      renderer.reset();
      failed.clear();
      try
      {
        renderer = CandidateRenderer::fromSetup(volume, message.substr(6));
      }
      catch (const std::exception& e)
      {
        failed = e.what();
      }
      continue; // no answer
    }
    // a failure is the answer (the coordinator reports it): the worker goes on serving
    std::string answer;
    try
    {
      if (!renderer)
        throw Error(failed.empty()
            ? "an exemplar worker got '" + message.substr(0, 40) + "' before its setup"
            : failed);
      answer = renderer->answer(message, threads);
    }
    catch (const std::exception& e)
    {
      answer = std::string("error ") + e.what();
    }
    send(answer);
  }
}

} // namespace ddg
