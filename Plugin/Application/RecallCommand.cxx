// RecallCommand.cxx: `ddg recall` — how often a query finds the design it shows: held-out designs
// join the bundle's outline, .
#ifdef DDG_WITH_TORCH
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/BuildDesignSpace.h"
#include "Gallery/BundleSession.h"
#include "Gallery/DesignReference.h"
#include "Gallery/Export.h"
#include "Gallery/Gallery.h"
#include "Gallery/History.h"
#include "Gallery/QueryKey.h"
#include "Image/Image.h"
#include "Render/View.h"
#include "TransferFunction/ColorSpace.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct RecallArgs
{
  std::string model, data;
  int count = 200, k = 5;
  bool noKey = false;
};

int runRecall(const RecallArgs& a)
{
  const ddg::ExemplarDataset data(a.data);
  const auto model = ddg::NeuralDesignModel::loadBundle(a.model, data.fingerprint());
  const auto latents = ddg::readLatentSet(ddg::outlineFile(a.model));
  const std::string keyFile = ddg::queryKeyFile(a.model);
  const ddg::QueryKey key =
    !a.noKey && std::filesystem::exists(keyFile) ? ddg::readQueryKey(keyFile) : ddg::QueryKey{};
  const auto t0 = Clock::now();
  const auto r = ddg::queryRecall(model, latents, data, a.count, a.k, key);
  std::printf("query recall@%d over %d held-out designs joined to the %d-design outline (%s): "
              "own image %.1f %%, other view %.1f %% (%.1f s)\n",
    r.k, r.count, latents.count(),
    key.empty()
      ? "by the latents"
      : ("by the query key, " + std::to_string(key.components) + " of " + std::to_string(key.dim))
          .c_str(),
    100 * r.ownImage, 100 * r.otherView, msSince(t0) / 1000);
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addRecallCommand(CLI::App& app)
{
  auto ra = std::make_shared<RecallArgs>();
  auto* recall = app.add_subcommand("recall",
    "How often a query finds the design it shows: held-out designs join the bundle's outline, "
    "then each is queried with its own image and with its image from another view; prints the "
    "fraction found among the k nearest (by the bundle's query key when it has one, as the "
    "gallery's query finds them).");
  recall->add_option("--model", ra->model, "Model bundle directory (with outline.bin)")->required();
  recall->add_option("--data", ra->data, "Held-out exemplars (ddg generate, same volume)")
    ->required();
  recall->add_option("--count", ra->count, "Held-out designs (default 200)")
    ->check(CLI::Range(1, 100000));
  recall->add_option("--k", ra->k, "Nearest designs that count as found (default 5)")
    ->check(CLI::Range(1, 1000));
  recall->add_flag("--no-key", ra->noKey,
    "Compare latents as they are, not by the bundle's query key (query_key.json) as the "
    "gallery's query does");
  return { recall, [ra] { return runRecall(*ra); } };
}
#endif
