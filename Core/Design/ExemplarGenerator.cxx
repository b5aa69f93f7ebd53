// ExemplarGenerator.cxx: parallel rendering of exemplars, shard files, the dataset index.
#include "Design/ExemplarGenerator.h"

#include "Design/CandidateRenderer.h"

#include "Design/DesignCheck.h"
#include "Design/DesignJson.h"
#include "Gallery/QueryImage.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Common/Parallel.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

namespace ddg
{
namespace
{
namespace fs = std::filesystem;
using nlohmann::json;
constexpr char kMagic[8] = { 'D', 'D', 'G', 'X', 'S', 'H', 'R', 'D' };

std::string shardName(int shard)
{
  char buf[32];
  std::snprintf(buf, sizeof(buf), "shard-%05d.bin", shard);
  return buf;
}

} // namespace

GenerateReport generateExemplars(const Volume& volume, const DesignSpaceSpec& spec,
  const std::string& dir, const GenerateOptions& opt, const std::function<bool(double)>& progress)
{
  const auto start = std::chrono::steady_clock::now();
  spec.validate();
  if (opt.count < 1 || opt.size < 8 || opt.size > 1024 || opt.shardSize < 1)
  {
    throw Error("generate: count must be >= 1, size 8..1024 and shard size >= 1");
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
  {
    throw Error("cannot create dataset directory '" + dir + "': " + ec.message());
  }
  // A previous dataset here is replaced: its index goes first, so a failed run never leaves an
  // index that describes shards of another run.
  fs::remove(fs::path(dir) / "dataset.json", ec);
  GenerateReport report;
  const bool twoD = spec.dimensions == 2;
  CandidateRenderer renderer(volume, spec, opt.size, opt.seed, opt.viewport);
  const RayCaster& caster = renderer.caster();
  if (!spec.regions.empty())
    report.regions = spec.regions;
  else if (opt.screen)
    report.regions =
      findDesignRegions(volume, caster, renderer.corners(), spec, &report.regionsLeftOut);
  else
    report.regions = twoD ? findFeatureRegions2D(volume, spec.maxRegions)
                          : findFeatureRegions(volume, spec.maxRegions);
  renderer.setRegions(report.regions);
  renderer.setUpWorkers(opt.workers);

  std::vector<Exemplar> items(static_cast<size_t>(opt.count));
  const size_t rec = CandidateRenderer::recordBytes(opt.size);
  const int shards = (opt.count + opt.shardSize - 1) / opt.shardSize;
  const std::int64_t maxCandidates = 4LL * opt.count;
  std::uint64_t next = opt.firstIndex; // the next index to examine
  std::vector<std::string> written;
  auto cleanup = [&]
  {
    for (const auto& f : written)
      fs::remove(f, ec);
  };
  // progress on the calling thread (parallelFor's worker 0), at most every 0.25 s
  using Clock = std::chrono::steady_clock;
  auto lastReport = Clock::now();
  std::atomic<int> done{ 0 };
  auto tick = [&](int threadId)
  {
    if (!progress || threadId != 0 || Clock::now() - lastReport < std::chrono::milliseconds(250))
      return;
    lastReport = Clock::now();
    if (!progress(std::min(1.0, static_cast<double>(done.load()) / opt.count)))
      throw Cancelled();
  };
  try
  {
    for (int shard = 0; shard < shards; ++shard)
    {
      const int first = shard * opt.shardSize;
      const int n = std::min(opt.shardSize, opt.count - first);
      std::vector<std::uint8_t> data(rec * n);
      int have = 0;
      while (have < n)
      {
        // a batch of candidate indices, sized by the pass rate so far
        const bool screening = opt.screen && report.candidates < maxCandidates;
        const double passRate = report.candidates > 0
          ? std::max(
              0.25, 1.0 - static_cast<double>(report.empty + report.flatBox) / report.candidates)
          : 1.0;
        const int batch = screening ? static_cast<int>(std::ceil((n - have) / passRate)) : n - have;
        std::vector<Exemplar> drawn(static_cast<size_t>(batch));
        std::vector<DesignVerdict> verdicts(static_cast<size_t>(batch));
        std::vector<std::uint8_t> records(rec * batch);
        // the batch's candidates: a contiguous share each for this process and every worker
        report.workerCandidates += renderer.exemplars(next, batch, screening, opt.workers,
          opt.threads, records.data(), drawn.data(), verdicts.data(),
          [&](std::int64_t q, int threadId)
          {
            if (!verdicts[q].junk())
              ++done;
            tick(threadId);
          });
        // in index order: the passing candidates until the shard is full
        for (int q = 0; q < batch && have < n; ++q)
        {
          ++next;
          if (screening)
          {
            ++report.candidates;
            if (verdicts[q].junk())
            {
              report.empty += verdicts[q].empty;
              report.flatBox += verdicts[q].flatBox;
              continue;
            }
          }
          std::copy_n(records.data() + rec * q, rec, data.data() + rec * have);
          items[static_cast<size_t>(first + have)] = std::move(drawn[q]);
          ++have;
        }
        done = first + have;
        if (opt.screen && !screening)
          report.screenExhausted = true;
      }
      std::string bytes(kMagic, kMagic + 8);
      const std::uint32_t header[4] = { 1, static_cast<std::uint32_t>(n),
        static_cast<std::uint32_t>(opt.size), 0 };
      bytes.append(reinterpret_cast<const char*>(header), sizeof(header));
      bytes.append(reinterpret_cast<const char*>(data.data()), data.size());
      const std::string path = (fs::path(dir) / shardName(shard)).string();
      writeFileAtomic(path, bytes, "exemplar shard");
      written.push_back(path);
      if (progress && !progress(static_cast<double>(first + n) / opt.count))
      {
        throw Cancelled();
      }
      lastReport = Clock::now();
    }
    json j;
    j["format"] = "ddg-exemplars";
    j["version"] = 1;
    j["volume"] = volumeFingerprint(volume);
    if (!opt.volumeFile.empty())
      j["volume_file"] = opt.volumeFile;
    j["size"] = opt.size;
    j["count"] = opt.count;
    j["seed"] = opt.seed;
    j["first_index"] = opt.firstIndex;
    j["shard_size"] = opt.shardSize;
    if (!opt.viewport)
      j["viewport"] = false;
    if (opt.screen)
      j["screen"] = { { "candidates", report.candidates }, { "empty", report.empty },
        { "flat_box", report.flatBox }, { "regions_left_out", report.regionsLeftOut },
        { "exhausted", report.screenExhausted } };
    j["spec"] = json::parse(designSpaceSpecToJson(spec));
    j["regions"] = json::array();
    for (const auto& r : report.regions)
      j["regions"].push_back(regionToJson(r));
    j["exemplars"] = json::array();
    for (const auto& e : items)
      j["exemplars"].push_back(exemplarToJson(e, twoD));
    writeFileAtomic((fs::path(dir) / "dataset.json").string(), j.dump() + "\n", "dataset index");
  }
  catch (...)
  {
    cleanup();
    throw;
  }
  report.count = opt.count;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

ExemplarDataset::ExemplarDataset(const std::string& dir)
  : Dir(dir)
{
  const std::string indexPath = (fs::path(dir) / "dataset.json").string();
  json j;
  try
  {
    j = json::parse(readTextFile(indexPath, "dataset index"));
  }
  catch (const json::parse_error& e)
  {
    throw Error("dataset index '" + indexPath + "' is corrupt: " + e.what());
  }
  try
  {
    if (j.value("format", std::string()) != "ddg-exemplars" || j.value("version", 0) != 1)
      throw Error("'" + indexPath + "' is not a version-1 ddg exemplar dataset");
    Fingerprint = j.at("volume").get<std::string>();
    Size = j.at("size").get<int>();
    Count = j.at("count").get<int>();
    VolumeFile = j.value("volume_file", std::string());
    ShardSize = j.at("shard_size").get<int>();
    Viewport = j.value("viewport", true);
    Spec = parseDesignSpaceSpec(j.at("spec").dump(), indexPath);
    for (const auto& r : j.at("regions"))
      Regions.push_back(regionFromJson(r));
    for (const auto& e : j.at("exemplars"))
      Items.push_back(exemplarFromJson(e, indexPath));
  }
  catch (const json::exception& e)
  {
    throw Error("dataset index '" + indexPath + "' is corrupt: " + e.what());
  }
  if (static_cast<int>(Items.size()) != Count || Size < 8 || ShardSize < 1)
  {
    throw Error("dataset index '" + indexPath + "' is inconsistent (count, size or shard size)");
  }
  const int shards = (Count + ShardSize - 1) / ShardSize;
  for (int s = 0; s < shards; ++s)
  {
    const std::string path = (fs::path(dir) / shardName(s)).string();
    const int n = std::min(ShardSize, Count - s * ShardSize);
    std::error_code ec;
    const auto bytes = fs::file_size(path, ec);
    if (ec || bytes != 24 + CandidateRenderer::recordBytes(Size) * n)
    {
      throw Error("dataset shard '" + path + "' is missing or truncated");
    }
    std::ifstream in(path, std::ios::binary);
    char magic[8];
    std::uint32_t header[4];
    in.read(magic, 8);
    in.read(reinterpret_cast<char*>(header), sizeof(header));
    if (!in || std::memcmp(magic, kMagic, 8) != 0 || header[0] != 1 ||
      header[1] != static_cast<std::uint32_t>(n) || header[2] != static_cast<std::uint32_t>(Size))
    {
      throw Error("dataset shard '" + path + "' has a wrong header");
    }
  }
}

void ExemplarDataset::load(int i, std::vector<std::uint8_t>& rgbExp,
  std::vector<std::uint8_t>& viewport, std::vector<std::uint8_t>& truth) const
{
  if (i < 0 || i >= Count)
  {
    throw Error("exemplar index out of range");
  }
  const int shard = i / ShardSize, q = i % ShardSize;
  const size_t px = static_cast<size_t>(Size) * Size;
  std::ifstream in((fs::path(Dir) / shardName(shard)).string(), std::ios::binary);
  in.seekg(static_cast<std::streamoff>(24 + CandidateRenderer::recordBytes(Size) * q));
  rgbExp.resize(3 * px);
  viewport.resize(4 * px);
  truth.resize(4 * px);
  in.read(reinterpret_cast<char*>(rgbExp.data()), static_cast<std::streamsize>(rgbExp.size()));
  in.read(reinterpret_cast<char*>(viewport.data()), static_cast<std::streamsize>(viewport.size()));
  in.read(reinterpret_cast<char*>(truth.data()), static_cast<std::streamsize>(truth.size()));
  if (!in)
  {
    throw Error("cannot read exemplar " + std::to_string(i) + " from '" + Dir + "'");
  }
}

ExemplarDataset::Images ExemplarDataset::images(int i) const
{
  std::vector<std::uint8_t> a, b, c;
  load(i, a, b, c);
  auto toImage = [this](const std::vector<std::uint8_t>& bytes, int channels)
  {
    Image img(Size, Size, channels);
    for (size_t k = 0; k < bytes.size(); ++k)
      img.pixels[k] = bytes[k] / 255.0f;
    return img;
  };
  return { toImage(a, 3), toImage(b, 4), toImage(c, 4) };
}

} // namespace ddg
