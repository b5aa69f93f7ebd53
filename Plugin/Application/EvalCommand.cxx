// EvalCommand.cxx: `ddg eval` — evaluate a model bundle on held-out exemplars: PSNR, SSIM, EMD,
// invariance, latency.
#ifdef DDG_WITH_TORCH
#include "CommandSupport.h"

#include "DDGVolumeAdaptor.h"

#include "Common/Error.h"
#include "Common/FileUtil.h"
#include "Design/ExemplarGenerator.h"
#include "Gallery/BuildDesignSpace.h"
#include "Neural/NeuralDesignModel.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace
{
using namespace ddg::cli;

struct EvalArgs
{
  std::string model, data, perExemplar, volume;
  int count = 1000;
  bool json = false;
};

int runEval(const std::string& modelDir, const std::string& dataDir, int count, bool json,
  const std::string& volume, const std::string& perExemplar)
{
  const ddg::ExemplarDataset data(dataDir);
  auto model = ddg::NeuralDesignModel::loadBundle(modelDir, data.fingerprint());
  if (!volume.empty())
    model.attachVolume(ddg::readVolumeFile(volume));
  const auto e = model.evaluate(data, count);
  if (!perExemplar.empty())
  {
    std::string csv = "index,active_regions,background,psnr,ssim,emd,lit,picture\n";
    char line[160];
    for (size_t i = 0; i < e.items.size(); ++i)
    {
      const auto& x = data.exemplars()[i];
      std::snprintf(line, sizeof(line), "%zu,%zu,%d,%.4f,%.5f,%.5f,%d,%d\n", i, x.active.size(),
        x.background, e.items[i].psnr, e.items[i].ssim, e.items[i].emd,
        static_cast<int>(x.viewExp.lighting.shade), static_cast<int>(x.picture.has_value()));
      csv += line;
    }
    ddg::writeFileAtomic(perExemplar, csv, "per-exemplar figures");
  }
  if (json)
    std::printf("%s\n", ddg::metricsToJson(e, nullptr, model.parameterCount()).c_str());
  else
    printEvaluation(e);
  return 0;
}

} // namespace

ddg::cli::Command ddg::cli::addEvalCommand(CLI::App& app)
{
  auto e = std::make_shared<EvalArgs>();
  auto* evalCmd = app.add_subcommand(
    "eval", "Evaluate a model bundle on held-out exemplars: PSNR, SSIM, EMD, invariance, latency.");
  evalCmd->add_option("--model", e->model, "Model bundle directory")->required();
  evalCmd->add_option("--data", e->data, "Held-out exemplar directory (same volume)")->required();
  evalCmd->add_option("--count", e->count, "Exemplars used (default 1000)");
  evalCmd->add_flag("--json", e->json, "Print the figures as JSON");
  evalCmd->add_option("--per-exemplar", e->perExemplar,
    "Also write every exemplar's PSNR, SSIM and EMD to this CSV file");
  evalCmd->add_option(
    "--volume", e->volume, "The volume (needed for decoder bundles, which ray cast their TFs)");
  return { evalCmd,
    [e] { return runEval(e->model, e->data, e->count, e->json, e->volume, e->perExemplar); } };
}
#endif
