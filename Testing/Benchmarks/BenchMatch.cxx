// BenchMatch.cxx: where the picture match's time goes (issue 17's speed goal: an 800 x 600
// screenshot -> matched TF in <= 5 s on 2 cores, bar 15 s). Prints, side by side in one run, the
// seconds per stage (background and masks, camera search, fit) of Core's matchPicture on
// screenshots made like ParaView's GUI leaves them (the palette's background, a rolled, panned,
// zoomed camera, an orientation-axes-sized mark), with the camera estimated and with it given,
// on 1 and on all threads, and the ratios; and the camera search by part (silhouettes, the
// colours' screening, the candidates' short fits and refinement, the winner's polish). A program
// that prints figures: no timed assertions.
//
//   BenchMatch [--repeat N]    (default 1)
#include "DDGVolumeAdaptor.h"

#include "Reconstruct/Match.h"
#include "Render/RayCaster.h"
#include "TransferFunction/TransferFunctionIO.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

using namespace ddg;

namespace
{
struct Row
{
  double background = 0, camera = 0, fit = 0, total = 0, fitPSNR = 0;
  MatchResult::CameraStages stages; // the camera search's parts
};

Row median(std::vector<Row> rows)
{
  auto med = [&](double Row::*field)
  {
    std::vector<double> v;
    for (const auto& r : rows)
      v.push_back(r.*field);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  auto stage = [&](double MatchResult::CameraStages::*field)
  {
    std::vector<double> v;
    for (const auto& r : rows)
      v.push_back(r.stages.*field);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  return { med(&Row::background), med(&Row::camera), med(&Row::fit), med(&Row::total),
    med(&Row::fitPSNR),
    { stage(&MatchResult::CameraStages::silhouettes), stage(&MatchResult::CameraStages::colours),
      stage(&MatchResult::CameraStages::candidates), stage(&MatchResult::CameraStages::polish) } };
}
} // namespace

int main(int argc, char** argv)
{
  int repeat = 1;
  for (int i = 1; i + 1 < argc; ++i)
    if (!std::strcmp(argv[i], "--repeat"))
      repeat = std::max(1, std::atoi(argv[i + 1]));
  const std::string data = DDG_DATA_DIR;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  std::printf(
    "BenchMatch: 800 x 600 screenshots, %d run(s) each (median), %u cores\n", repeat, cores);
  std::printf("%-8s %-9s %7s | %8s %8s %8s %8s | %8s | camera by part (s): %6s %6s %6s %6s\n",
    "volume", "camera", "threads", "bg (s)", "cam (s)", "fit (s)", "all (s)", "fit dB", "silh",
    "colour", "cands", "polish");
  struct Case
  {
    const char* volume;
    const char* preset;
  };
  for (const Case c : { Case{ "tooth", "tooth_dentin_enamel" }, Case{ "engine", "engine_block" } })
  {
    const Volume vol = readVolumeFile(data + "/Volumes/" + c.volume + ".vti");
    const DifferentiableRenderer renderer(vol);
    const auto table = renderer.caster().paraviewTable(
      readPreset(data + "/TransferFunctions/" + c.preset + ".json"));
    View truth = cameraMove(defaultView(vol, 800, 600), 35, 20, 12, 1.2, { 0.03, -0.04 });
    truth.background = { 82 / 255.0, 87 / 255.0, 110 / 255.0 };
    Image picture =
      compositeOverBackground(renderer.caster().render(table, truth), truth.background);
    for (int y = 520; y < 580; ++y) // an orientation-axes-sized mark, lower left
      for (int x = 20; x < 26; ++x)
        for (int k = 0; k < 3; ++k)
          picture.pixels[3 * (static_cast<size_t>(y) * 800 + x) + k] = k == 1 ? 0.9f : 0.2f;
    double totals[2][2] = {};
    for (int given = 0; given < 2; ++given)
      for (int t = 0; t < 2; ++t)
      {
        const int threads = t == 0 ? 1 : 0;
        std::vector<Row> rows;
        for (int r = 0; r < repeat; ++r)
        {
          MatchOptions opt;
          opt.reconstruction.render.threads = threads;
          if (given)
            opt.view = truth;
          const auto m = matchPicture(renderer, picture, opt);
          rows.push_back({ m.backgroundSeconds, m.cameraSeconds, m.fitSeconds, m.seconds, m.fitPSNR,
            m.cameraStages });
        }
        const Row row = median(rows);
        totals[given][t] = row.total;
        std::printf("%-8s %-9s %7s | %8.2f %8.2f %8.2f %8.2f | %8.2f | %6.2f %6.2f %6.2f %6.2f\n",
          c.volume, given ? "given" : "estimated", t == 0 ? "1" : "all", row.background, row.camera,
          row.fit, row.total, row.fitPSNR, row.stages.silhouettes, row.stages.colours,
          row.stages.candidates, row.stages.polish);
      }
    std::printf("%-8s ratios: all threads / 1 thread %.2f (estimated), %.2f (given); estimated / "
                "given %.2f (all threads)\n",
      c.volume, totals[0][1] / totals[0][0], totals[1][1] / totals[1][0],
      totals[0][1] / totals[1][1]);
  }
  return 0;
}
