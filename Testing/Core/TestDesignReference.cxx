// TestDesignReference.cxx: the design-reference grammar and the history steps as the front ends
// build them (Core/Gallery/DesignReference.h, History.h). Compared: parsed fields against the
// text given; each builder's step against the JSON the documented history format holds (read
// back by DesignHistory::fromJson, exact); setAxes against the panel's rule (the sliders move
// one "axes" step). Failure cases: unknown kinds, empty arguments, non-integer rows, bad files.
#include "Gallery/DesignReference.h"

#include "Common/Error.h"
#include "Image/Image.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace
{
std::string tempPath(const std::string& name)
{
  return (std::filesystem::temp_directory_path() / ("ddg_ref_" + name)).string();
}
} // namespace

TEST(DesignReference, ParsesTheFourKinds)
{
  const auto row = ddg::DesignReference::parse("row:17");
  EXPECT_EQ(row.kind, ddg::DesignReference::Kind::Row);
  EXPECT_EQ(row.row, 17);
  const auto image = ddg::DesignReference::parse("image:a/b:c.png"); // the first colon splits
  EXPECT_EQ(image.kind, ddg::DesignReference::Kind::Image);
  EXPECT_EQ(image.path, "a/b:c.png");
  EXPECT_EQ(ddg::DesignReference::parse("latent:z.json").kind, ddg::DesignReference::Kind::Latent);
  EXPECT_EQ(
    ddg::DesignReference::parse("history:h.json").kind, ddg::DesignReference::Kind::History);
}

TEST(DesignReference, RefusesWhatIsNotAReference)
{
  for (const char* bad : { "17", "row:", "", "image:" })
  {
    try
    {
      ddg::DesignReference::parse(bad);
      FAIL() << bad;
    }
    catch (const ddg::Error& e)
    {
      EXPECT_NE(std::string(e.what()).find("use row:N, image:PATH, latent:PATH or history:PATH"),
        std::string::npos)
        << bad;
    }
  }
  EXPECT_THROW(ddg::DesignReference::parse("row:1x"), ddg::Error);
  EXPECT_THROW(ddg::DesignReference::parse("rows:1"), ddg::Error);
  EXPECT_THROW(ddg::DesignReference::parse("latent:/no/such/file.json").history(), ddg::Error);
}

TEST(DesignReference, HistoryOfEachKind)
{
  EXPECT_EQ(ddg::DesignReference::parse("row:3").history().steps.at(0).action, "pick");
  EXPECT_EQ(ddg::DesignReference::parse("row:3").history().steps.at(0).row, 3);
  const auto q = ddg::DesignReference::parse("image:shot.png").history();
  ASSERT_EQ(q.steps.size(), 1u);
  EXPECT_EQ(q.steps[0].action, "query");
  EXPECT_EQ(q.steps[0].image, "shot.png");

  const std::string latentFile = tempPath("latent.json");
  ddg::writeLatentFile({ 0.5f, -1.25f, 2.0f }, latentFile);
  EXPECT_EQ(ddg::readLatentFile(latentFile), (std::vector<float>{ 0.5f, -1.25f, 2.0f }));
  const auto l = ddg::DesignReference::parse("latent:" + latentFile).history();
  EXPECT_EQ(l.steps.at(0).action, "latent");
  EXPECT_EQ(l.steps.at(0).latent, (std::vector<float>{ 0.5f, -1.25f, 2.0f }));

  const std::string historyFile = tempPath("history.json");
  ddg::DesignHistory h;
  h.steps = { ddg::HistoryStep::pick(2), ddg::HistoryStep::axes({ 0.5, -1 }) };
  h.write(historyFile);
  const auto back = ddg::DesignReference::parse("history:" + historyFile).history();
  ASSERT_EQ(back.steps.size(), 2u);
  EXPECT_EQ(back.steps[1].steps, (std::vector<double>{ 0.5, -1 }));

  std::ofstream(latentFile) << "{\"not\": 1}";
  EXPECT_THROW(ddg::readLatentFile(latentFile), ddg::Error);
  std::remove(latentFile.c_str());
  std::remove(historyFile.c_str());
}

TEST(HistoryStep, BuildersWriteTheDocumentedJson)
{
  const std::string view = "{\"camera\": {\"position\": [0, 0, 5], \"focal_point\": [0, 0, 0], "
                           "\"view_up\": [0, 1, 0], \"view_angle\": 30}, \"size\": [64, 48]}";
  ddg::DesignHistory h;
  h.steps = { ddg::HistoryStep::blend({ { 1, 2 }, { 3, 4 } }, 0.25, 0.5),
    ddg::HistoryStep::edit(view, 2, -1, -1, 4, 30, 1, 0, 1.5, false),
    ddg::HistoryStep::edit(view, -1, 10, 20, 5, 0, 1, 0, 0.5, true),
    ddg::HistoryStep::latentDesign({ 7, 8 }, "pasted.png") };
  const auto j = nlohmann::json::parse(h.toJson());
  EXPECT_EQ(j.at("format"), "ddg-history");
  EXPECT_EQ(j.at("version"), 1);
  const auto& s = j.at("steps");
  EXPECT_EQ(s[0].at("latents"), nlohmann::json::parse("[[1.0, 2.0], [3.0, 4.0]]"));
  EXPECT_EQ(s[0].at("u"), 0.25);
  EXPECT_EQ(s[1].at("cluster"), 2);
  EXPECT_FALSE(s[1].contains("pick"));
  EXPECT_EQ(s[1].at("visibility"), 1.5);
  EXPECT_EQ(s[2].at("pick"), nlohmann::json::parse("[10, 20]"));
  EXPECT_FALSE(s[2].contains("cluster"));
  EXPECT_EQ(s[2].at("white"), true);
  EXPECT_EQ(s[3].at("image"), "pasted.png");
  const auto back = ddg::DesignHistory::fromJson(h.toJson());
  EXPECT_EQ(back.toJson(), h.toJson());
}

TEST(HistoryStep, MatchEndsAHistoryAndKeepsItsTF)
{
  const std::string view = "{\"camera\": {\"position\": [0, 0, 5], \"focal_point\": [0, 0, 0], "
                           "\"view_up\": [0, 1, 0], \"view_angle\": 30}, \"size\": [64, 48]}";
  const std::string preset = "[{\"Name\": \"m\", \"ColorSpace\": \"RGB\", \"RGBPoints\": "
                             "[0, 1, 0, 0, 1, 0, 0, 1], \"Points\": [0, 0, 0.5, 0, 1, 1, 0.5, 0]}]";
  ddg::DesignHistory h;
  h.steps = { ddg::HistoryStep::pick(3),
    ddg::HistoryStep::match("shot.png", view, true, preset, false, 64, 200) };
  const auto j = nlohmann::json::parse(h.toJson());
  const auto& m = j.at("steps")[1];
  EXPECT_EQ(m.at("action"), "match");
  EXPECT_EQ(m.at("image"), "shot.png");
  EXPECT_EQ(m.at("camera"), "estimated");
  EXPECT_EQ(m.at("bins"), 64);
  EXPECT_EQ(m.at("iterations"), 200);
  EXPECT_EQ(m.at("two_d"), false);
  EXPECT_TRUE(m.at("tf").is_array());
  const auto back = ddg::DesignHistory::fromJson(h.toJson());
  EXPECT_EQ(back.toJson(), h.toJson());
  EXPECT_TRUE(back.steps[1].cameraEstimated);
  // a match is the last step; it needs its view and TF
  ddg::DesignHistory after = h;
  after.steps.push_back(ddg::HistoryStep::pick(1));
  EXPECT_THROW(ddg::DesignHistory::fromJson(after.toJson()), ddg::Error);
  ddg::DesignHistory noTF = h;
  noTF.steps[1].tfJson.clear();
  EXPECT_THROW(noTF.write("never_written.json"), ddg::Error);
  EXPECT_FALSE(std::ifstream("never_written.json").good());
}

TEST(HistoryStep, AxesMoveOneStep)
{
  ddg::DesignHistory h;
  h.steps = { ddg::HistoryStep::pick(0) };
  h.setAxes({ 1 });
  h.setAxes({ 1, 2 });
  ASSERT_EQ(h.steps.size(), 2u);
  EXPECT_EQ(h.steps[1].steps, (std::vector<double>{ 1, 2 }));
  h.steps.push_back(ddg::HistoryStep::pick(4));
  h.setAxes({ 3 });
  EXPECT_EQ(h.steps.size(), 4u);
}

TEST(DesignEdit, StepRoundTripAndMaskRefused)
{
  ddg::DesignEdit e;
  e.view.width = 32;
  e.view.height = 16;
  e.pickX = 3;
  e.pickY = 4;
  e.cluster = 1; // a pick wins: the step names the pixel
  e.hue = 45;
  const auto step = e.toStep();
  EXPECT_EQ(step.cluster, -1);
  const auto back = ddg::DesignEdit::fromStep(step);
  EXPECT_EQ(back.pickX, 3);
  EXPECT_EQ(back.view.width, 32);
  EXPECT_EQ(back.hue, 45);
  e.mask = ddg::Image(32, 16, 1, 1.0f);
  EXPECT_THROW(e.toStep(), ddg::Error);
}
