// KindCommand.cxx: `ddg train-kind` (the kind network, Core's KindNetwork, trained on generated
// datasets of several volumes) and `ddg kind` (whether pictures show a volume of the kind a
// volume is; calibrating the network's threshold on pictures of known kind).
#ifdef DDG_WITH_TORCH
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Image/Image.h"
#include "Neural/KindNetwork.h"
#include "Render/RayCaster.h" // ddg::Cancelled

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <map>

namespace
{
using namespace ddg::cli;

struct TrainKindArgs
{
  std::vector<std::string> datasets;
  std::string out;
  ddg::KindTrainOptions opt;
  bool quiet = false;
};

int runTrainKind(const TrainKindArgs& a)
{
  std::vector<std::string> names, dirs;
  for (const auto& d : a.datasets)
  {
    const size_t eq = d.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == d.size())
      throw ddg::Error("--dataset takes NAME=DIR, not '" + d + "'");
    names.push_back(d.substr(0, eq));
    dirs.push_back(d.substr(eq + 1));
  }
  ddg::KindTrainReport report;
  const auto net = ddg::KindNetwork::train(names, dirs, a.opt, &report,
    [&](int epoch, double loss, double accuracy)
    {
      if (!a.quiet)
      {
        std::printf("epoch %3d  loss %.4f  held-out accuracy %.3f\n", epoch, loss, accuracy);
        std::fflush(stdout);
      }
      return true;
    });
  net.save(a.out);
  std::printf("wrote the kind network (%zu kinds) to %s: %d training and %d held-out exemplars, "
              "held-out accuracy %.3f, %.0f s\n",
    names.size(), a.out.c_str(), report.trainingExemplars, report.validationExemplars,
    report.validationAccuracy, report.seconds);
  return 0;
}

struct KindArgs
{
  std::string model, volume, calibrate, out;
  std::vector<std::string> images;
  int threads = 0;
};

// The volume's reference, once per volume file.
const std::vector<double>& referenceOf(const ddg::KindNetwork& net, const std::string& volume,
  int threads, std::map<std::string, std::vector<double>>& cache)
{
  auto it = cache.find(volume);
  if (it == cache.end())
    it = cache.emplace(volume, ddg::kindReference(net, ddg::readVolumeFile(volume), threads)).first;
  return it->second;
}

int runKind(const KindArgs& a)
{
  ddg::KindNetwork net = ddg::KindNetwork::load(a.model);
  std::map<std::string, std::vector<double>> refs;
  if (!a.calibrate.empty())
  {
    if (!a.images.empty() || !a.volume.empty())
      throw ddg::Error("--calibrate takes no --image or --volume (the list names them)");
    // [[picture, volume], ...]: pictures that show a volume of the volume's kind
    const auto list =
      nlohmann::json::parse(ddg::readTextFile(a.calibrate, "calibration list"), nullptr, false);
    if (!list.is_array() || list.size() < 2)
      throw ddg::Error("--calibrate: '" + a.calibrate +
        "' must be a JSON list of two or more [picture, volume] pairs");
    std::vector<double> agreements;
    for (const auto& pair : list)
    {
      if (!pair.is_array() || pair.size() != 2 || !pair[0].is_string() || !pair[1].is_string())
        throw ddg::Error("--calibrate: each entry is [picture, volume]");
      const auto c = ddg::checkKind(net, ddg::readImage(pair[0].get<std::string>()),
        referenceOf(net, pair[1].get<std::string>(), a.threads, refs));
      agreements.push_back(c.agreement);
      std::printf("%.3f  %s on %s\n", c.agreement, pair[0].get<std::string>().c_str(),
        pair[1].get<std::string>().c_str());
    }
    std::sort(agreements.begin(), agreements.end());
    // warns at most one of the calibration pictures: just under the second lowest
    net.setThreshold(std::max(0.0, agreements[1] - 1e-6));
    net.save(a.out.empty() ? a.model : a.out);
    std::printf("threshold %.6f (just under the second lowest of %zu same-kind agreements), "
                "written to %s\n",
      net.threshold(), agreements.size(), (a.out.empty() ? a.model : a.out).c_str());
    return 0;
  }
  if (a.images.empty() || a.volume.empty())
    throw ddg::Error("ddg kind needs --volume and one or more --image (or --calibrate LIST)");
  if (!a.out.empty())
    throw ddg::Error("--out is for --calibrate");
  const auto& ref = referenceOf(net, a.volume, a.threads, refs);
  for (const auto& path : a.images)
  {
    const auto c = ddg::checkKind(net, ddg::readImage(path), ref);
    std::printf("%s: %s\n", path.c_str(), ddg::describeKindCheck(c).c_str());
  }
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addTrainKindCommand(CLI::App& app)
{
  auto a = std::make_shared<TrainKindArgs>();
  auto* c = app.add_subcommand("train-kind",
    "Train the kind network (tells whether a picture shows a volume of another kind) on datasets "
    "of several volumes made by `ddg generate` with one spec and size (scripts/train_kind.sh "
    "makes the shipped Data/Models/kind).");
  c->add_option("--dataset", a->datasets, "NAME=DIR, one per volume (two or more)")
    ->required()
    ->expected(2, 1000);
  c->add_option("--out", a->out, "Output directory (kind.pt, kind.json)")->required();
  c->add_option("--epochs", a->opt.epochs, "Passes over the exemplars (default 40)")
    ->check(CLI::Range(1, 10000));
  c->add_option("--batch", a->opt.batch, "Exemplars per step (default 128)")
    ->check(CLI::Range(2, 100000));
  c->add_option("--lr", a->opt.maxLearningRate, "Peak learning rate, one cycle (default 3e-3)")
    ->check(CLI::PositiveNumber);
  c->add_option("--seed", a->opt.seed, "Seed (default 5)");
  c->add_option("--threads", a->opt.threads, "Threads (default: all cores)")
    ->check(CLI::Range(0, 1024));
  c->add_flag("--quiet", a->quiet, "No per-epoch lines");
  return { c, [a] { return runTrainKind(*a); } };
}

ddg::cli::Command ddg::cli::addKindCommand(CLI::App& app)
{
  auto a = std::make_shared<KindArgs>();
  auto* c = app.add_subcommand("kind",
    "Whether pictures show a volume of the volume's kind: the kind network's agreement between "
    "each picture and the volume's own exemplars (1 = alike), below the network's threshold "
    "'may show a volume of another kind'. --calibrate sets that threshold.");
  c->add_option("--model", a->model, "Kind network directory (Data/Models/kind)")->required();
  c->add_option("--volume", a->volume, "The volume");
  c->add_option("--image", a->images, "Pictures (any size; framed as a query frames them)");
  c->add_option("--calibrate", a->calibrate,
    "JSON list of [picture, volume] pairs of the same kind: the threshold is set just under "
    "the second lowest agreement (at most one of them warned) and the network rewritten");
  c->add_option("--out", a->out, "With --calibrate: write the network here instead");
  c->add_option("--threads", a->threads, "Threads (default: all cores)")
    ->check(CLI::Range(0, 1024));
  return { c, [a] { return runKind(*a); } };
}
#endif
