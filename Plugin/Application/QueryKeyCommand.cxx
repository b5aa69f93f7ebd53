// QueryKeyCommand.cxx: `ddg query-key` — fits a bundle's query key (Gallery/QueryKey.h) on
// exemplars of its design space and writes it into the bundle (what `ddg build` does itself).
#ifdef DDG_WITH_TORCH
#include "CommandSupport.h"

#include "Common/Error.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/Gallery.h"
#include "Gallery/QueryKey.h"

#include <cstdio>

namespace
{
using namespace ddg::cli;

struct QueryKeyArgs
{
  std::string model, data;
  int pairs = ddg::kQueryKeyPairs;
  int threads = 0;
};

int runQueryKey(const QueryKeyArgs& a)
{
  const ddg::ExemplarDataset data(a.data);
  const auto model = ddg::NeuralDesignModel::loadBundle(a.model, data.fingerprint());
  const auto t0 = Clock::now();
  const ddg::QueryKey key = ddg::queryKeyFromExemplars(model, data, a.pairs, a.threads);
  if (key.empty())
    throw ddg::Error("too few exemplars in '" + a.data + "' show the design from both views: " +
      "a query key needs at least " + std::to_string(2 * model.config().latent));
  ddg::writeQueryKey(key, ddg::queryKeyFile(a.model));
  std::printf("query key (%s): %d values from %d latent values, %d view pairs, %.1f s, written to "
              "%s\n",
    key.method.c_str(), key.components, key.dim, key.pairs, msSince(t0) / 1000,
    ddg::queryKeyFile(a.model).c_str());
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addQueryKeyCommand(CLI::App& app)
{
  auto qa = std::make_shared<QueryKeyArgs>();
  auto* cmd = app.add_subcommand("query-key",
    "Fit a bundle's query key and write it into the bundle (query_key.json): a map of the "
    "latent that keeps what tells designs apart and leaves out what changes with the camera, "
    "learnt from pairs of one design's images from two views, by which a query finds its nearest "
    "designs. From 1000 usable pairs a small network trained contrastively (more pairs: better; "
    "the shipped bundles' keys use 16000), below that linear discriminant analysis. `ddg build` "
    "fits one itself (up to 2000 pairs); this adds one to an older bundle or refits it. "
    "Exemplars: `ddg generate` with the bundle's spec, not its training or held-out range.");
  cmd->add_option("--model", qa->model, "Model bundle directory")->required();
  cmd->add_option("--data", qa->data, "Exemplars of the bundle's volume (ddg generate)")
    ->required();
  cmd->add_option("--pairs", qa->pairs, "Exemplars used (default 2000)")
    ->check(CLI::Range(1, 1000000));
  cmd->add_option("--threads", qa->threads, "Worker threads (default 0: all cores)")
    ->check(CLI::Range(0, 256));
  return { cmd, [qa] { return runQueryKey(*qa); } };
}
#endif
