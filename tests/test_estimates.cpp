// Figures with their errors: means and standard errors, the verdict of a difference, histories
// folded into a design's estimate, the life's error propagated through the life line; and
// `millwear run --replicates` end to end on the lab mill: the reported error against the
// spread of independent runs, one history's errors against the spread of seeds, and the
// comparison's verdicts.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "io/csv.hpp"
#include "metrics/estimates.hpp"
#include "scene/scene.hpp"
#include "study/design_estimates.hpp"
#include "temp_dir.hpp"
#include "wear/life.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;
using millwear::Estimate;

namespace {

TEST(Estimates, MeanAndStandardErrorOfKnownValues) {
  // 1, 2, 3, 4: mean 2.5, sample variance 5/3, se = sqrt(5/3 / 4).
  const Estimate e = millwear::mean_and_se({1.0, 2.0, 3.0, 4.0});
  EXPECT_DOUBLE_EQ(e.mean, 2.5);
  EXPECT_NEAR(e.se, std::sqrt(5.0 / 3.0 / 4.0), 1e-15);
  EXPECT_TRUE(std::isnan(millwear::mean_and_se({7.0}).se));
  EXPECT_DOUBLE_EQ(millwear::mean_and_se({7.0}).mean, 7.0);
  EXPECT_TRUE(std::isnan(millwear::mean_and_se({}).mean));
}

// Six replicates of one new lifter: their area exactly, with no error at all (the sum's
// rounding gave 3e-12, printed as a measured spread).
TEST(Estimates, EqualValuesHaveExactlyNoError) {
  const std::vector<double> same(6, 42386.090624017219);  // six: the sum rounds
  const Estimate e = millwear::mean_and_se(same);
  EXPECT_EQ(e.mean, 42386.090624017219);
  EXPECT_EQ(e.se, 0.0);
}

TEST(Estimates, ADifferenceIsResolvedPastTwoCombinedErrors) {
  using millwear::ErrorSource;
  // One history's batch means: combined error sqrt(0.3^2 + 0.4^2) = 0.5; a difference of
  // 1.01 is resolved, 0.99 is not.
  const auto yes = millwear::compare({10.0, 0.3}, {8.99, 0.4}, 1, ErrorSource::BatchMeans);
  EXPECT_NEAR(yes.se, 0.5, 1e-12);
  EXPECT_EQ(yes.threshold, 2.0);
  EXPECT_TRUE(yes.resolved);
  EXPECT_EQ(yes.replicates_needed, 0);
  const auto no = millwear::compare({10.0, 0.3}, {9.01, 0.4}, 1, ErrorSource::BatchMeans);
  EXPECT_FALSE(no.resolved);
  // The count that would resolve it is run as replicates, so judged by their threshold: the
  // smallest n with t(Welch dof at n) * 0.5 / sqrt(n) < 0.99.
  const int n = no.replicates_needed;
  ASSERT_GE(n, 2);
  const auto t_at = [](int k) { return millwear::resolved_threshold(millwear::welch_dof(0.3, 0.4, k)); };
  EXPECT_LT(t_at(n) * 0.5 / std::sqrt(n), 0.99);
  if (n > 2) {
    EXPECT_GT(t_at(n - 1) * 0.5 / std::sqrt(n - 1.0), 0.99);
  }
  // Never the count already run: four histories that did not resolve it need more than four.
  const auto four = millwear::compare({3.0, 1.0}, {0.0, 0.0}, 4, ErrorSource::Replicates);
  ASSERT_FALSE(four.resolved);
  EXPECT_GT(four.replicates_needed, 4);
  // No error known: no verdict either way.
  const auto unknown = millwear::compare({1.0, std::nan("")}, {0.0, 0.1}, 1, ErrorSource::BatchMeans);
  EXPECT_FALSE(unknown.resolved);
  EXPECT_EQ(unknown.replicates_needed, -1);
}

// The threshold is Student's t at the level of two standard errors of a normal variable
// (Phi(2) = 0.97725), in closed form for one and two degrees of freedom:
// t1 = tan(pi (0.97725 - 1/2)), t2 = sqrt(2 q^2 / (1 - q^2)) with q = 2 * 0.97725 - 1.
TEST(Estimates, FewReplicatesNeedStudentsThreshold) {
  using millwear::ErrorSource;
  const double p = 0.5 * std::erfc(-2.0 / std::sqrt(2.0)), q = 2.0 * p - 1.0;
  EXPECT_NEAR(millwear::resolved_threshold(1.0), std::tan(M_PI * (p - 0.5)), 1e-9);
  EXPECT_NEAR(millwear::resolved_threshold(2.0), std::sqrt(2.0 * q * q / (1.0 - q * q)), 1e-9);
  EXPECT_NEAR(millwear::resolved_threshold(1e9), 2.0, 1e-12);
  // Two replicates per design with equal errors: 2 degrees of freedom, a threshold of 4.53;
  // four combined errors are not a resolved difference, five are.
  const double t2 = std::sqrt(2.0 * q * q / (1.0 - q * q));
  EXPECT_NEAR(millwear::welch_dof(1.0, 1.0, 2), 2.0, 1e-12);
  const double se = std::sqrt(2.0);
  const auto four = millwear::compare({4.0 * se, 1.0}, {0.0, 1.0}, 2, ErrorSource::Replicates);
  EXPECT_NEAR(four.threshold, t2, 1e-9);
  EXPECT_FALSE(four.resolved);
  EXPECT_TRUE(millwear::compare({5.0 * se, 1.0}, {0.0, 1.0}, 2, ErrorSource::Replicates).resolved);
  // One error far larger than the other: the degrees of freedom of that design alone.
  EXPECT_NEAR(millwear::welch_dof(1.0, 1e-6, 4), 3.0, 1e-9);
  // Sixteen per design: close to two errors.
  EXPECT_LT(millwear::compare({1.0, 0.2}, {0.0, 0.2}, 16, ErrorSource::Replicates).threshold, 2.1);
}

// A lifter whose stages lose `lost_m` of height each (with recorded errors se_m on each
// stage's loss), the area following the height.
std::vector<millwear::study::LifterAtStage> straight_history(int stages, double lost_m, double se_m) {
  std::vector<millwear::study::LifterAtStage> at;
  for (int k = 0; k < stages; ++k) {
    millwear::study::LifterAtStage r;
    r.hours = 100.0 * k;
    r.height_m = 0.02 - lost_m * k;
    r.area_m2 = 4e-4 - 0.02 * lost_m * k;
    r.worn_height_se_m = se_m;
    r.worn_area_se_m2 = 0.02 * se_m;
    at.push_back(r);
  }
  at.back().worn_height_se_m = at.back().worn_area_se_m2 = std::nan("");  // the last stage is not worn through
  return at;
}

TEST(LifeError, ExtrapolatedFromTwoStagesIsTheHeightErrorOverTheHeightLost) {
  // Two stages, 1 mm lost with an error of 0.1 mm; replacement at 5 mm: the life is
  // 100 h x 15 mm / 1 mm, and it scales as one over the height lost.
  const auto at = straight_history(2, 1e-3, 1e-4);
  const double life = 1500.0;
  EXPECT_NEAR(millwear::study::life_error_h(at, 4e-4, 0.02, 0.005), life * 1e-4 / 1e-3, 1e-9 * life);
  // Never under the replacement height, and no height lost: no error.
  EXPECT_TRUE(std::isnan(millwear::study::life_error_h(straight_history(2, 0.0, 1e-4), 4e-4, 0.02, 0.005)));
}

TEST(LifeError, AgreesWithTheSpreadOfTheLifeLineOverDrawnHistories) {
  // Histories whose stage losses scatter with the recorded errors: the life line's spread over
  // many draws is the propagated error, for a life between stages (the two stages around the
  // crossing, correlated through the loss before them) and past them (the trend of the last
  // three).
  for (const double replacement_m : {0.0155, 0.010}) {
    const auto at = straight_history(6, 1e-3, 3e-5);
    const double expected = millwear::study::life_error_h(at, 4e-4, 0.02, replacement_m);
    std::mt19937_64 rng(7);
    std::normal_distribution<double> noise(0.0, 3e-5);
    double sum = 0.0, sum2 = 0.0;
    const int draws = 20000;
    for (int n = 0; n < draws; ++n) {
      std::vector<double> hours, height;
      double h = 0.02;
      for (std::size_t k = 0; k < at.size(); ++k) {
        hours.push_back(at[k].hours);
        height.push_back(h);
        h -= 1e-3 + noise(rng);
      }
      const double life = millwear::life_line(hours, height, replacement_m).hours;
      sum += life;
      sum2 += life * life;
    }
    const double mean = sum / draws, sd = std::sqrt((sum2 / draws - mean * mean) * draws / (draws - 1.0));
    const auto line = millwear::life_line({0, 100, 200, 300, 400, 500}, {0.02, 0.019, 0.018, 0.017, 0.016, 0.015},
                                          replacement_m);
    EXPECT_EQ(line.extrapolated, replacement_m < 0.015) << replacement_m;
    // The sample sd of 20000 draws is within 1.5% of the truth (3 of its own errors of 0.5%).
    EXPECT_NEAR(sd, expected, 0.015 * expected) << replacement_m;
  }
}

TEST(LifeError, APatternsLifeIsItsShortestLivedKindsWithThatKindsError) {
  // Two kinds of lifter: kind 0 loses no height and never reaches the replacement height (no
  // life); kind 1 loses 1 mm per 100 h with an error of 0.1 mm per stage and reaches 5 mm at
  // 1500 h. The pattern lasts kind 1's life, with kind 1's propagated error.
  const millwear::Scene scene = millwear::load_scene(std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml");
  const auto kind1 = straight_history(2, 1e-3, 1e-4);
  std::map<int, millwear::StageRecord> stages;
  for (int k = 0; k < 2; ++k) {
    millwear::StageRecord r;
    r.stage = k;
    r.hours = kind1[k].hours;
    r.lifter = {4e-4, 0.02};
    r.kinds = {{4e-4, 0.02}, {kind1[k].area_m2, kind1[k].height_m}};
    r.kind_area_loss_rate_m2_per_s = {0.0, kind1[k].rate_m2_per_s};
    r.kind_area_loss_rate_rel_sem = {0.0, kind1[k].rate_rel_sem};
    r.worn_se = {0.0, 0.0};
    r.kind_worn_se = {{0.0, 0.0}, {kind1[k].worn_area_se_m2, kind1[k].worn_height_se_m}};
    stages[k] = r;
  }
  const double life = 1500.0, nan = std::nan("");
  const millwear::DesignEstimate d =
      millwear::study::estimate_history("pattern", scene, stages, life, true, {nan, life}, {true, true});
  ASSERT_EQ(d.kind_life_h.size(), 2u);
  EXPECT_TRUE(std::isnan(d.kind_life_h[0].mean));
  EXPECT_DOUBLE_EQ(d.life_h.mean, life);
  EXPECT_NEAR(d.life_h.se, life * 1e-4 / 1e-3, 1e-9 * life);
  EXPECT_DOUBLE_EQ(d.life_h.se, d.kind_life_h[1].se);
}

TEST(LifeError, NoneWhenTheFirstStageIsUnderTheReplacementHeight) {
  // A lifter already at the replacement height: its life is the first stage's, exactly.
  EXPECT_EQ(millwear::study::life_error_h(straight_history(3, 1e-3, 1e-4), 4e-4, 0.02, 0.025), 0.0);
}

TEST(Estimates, HistoriesFoldIntoTheMeanAndItsError) {
  std::vector<millwear::DesignEstimate> hs(3);
  const double power[] = {100.0, 110.0, 120.0};
  const double life[] = {900.0, 1000.0, 1100.0};
  for (int i = 0; i < 3; ++i) {
    millwear::StageEstimate s;
    s.power_W = {power[i], 1.0};  // a history's own error is not the spread between histories
    hs[i].stages = {s, s};
    hs[i].life_h = {life[i], 5.0};
    hs[i].life_extrapolated = i == 1;
  }
  hs[2].stages.pop_back();  // a history that finished one stage fewer
  const millwear::DesignEstimate d = millwear::combine_histories("d", hs);
  EXPECT_EQ(d.replicates, 3);
  EXPECT_EQ(d.source, millwear::ErrorSource::Replicates);
  ASSERT_EQ(d.stages.size(), 1u);
  EXPECT_DOUBLE_EQ(d.stages[0].power_W.mean, 110.0);
  EXPECT_NEAR(d.stages[0].power_W.se, 10.0 / std::sqrt(3.0), 1e-12);
  EXPECT_DOUBLE_EQ(d.life_h.mean, 1000.0);
  EXPECT_NEAR(d.life_h.se, 100.0 / std::sqrt(3.0), 1e-12);
  EXPECT_TRUE(d.life_extrapolated);
}

// --- `millwear run --replicates` on the lab mill --------------------------------------------

using millwear::testing::quoted;
using millwear::testing::read_text;
using millwear::testing::run_millwear;

std::string src(const std::string& rel) { return quoted(fs::path(MILLWEAR_SOURCE_DIR) / rel); }

// Draft, one stage of wear after the new one: a short history.
const std::string kShort = " --fidelity draft --quiet --set wear.stages=1";

class Replicates : public ::testing::Test {
 protected:

  // A copy of the lab-mill scene under another name and seed (and wear rate), in a scenarios/
  // folder beside a link to the repository's profiles, which the scene names relatively.
  fs::path scene_copy(const std::string& name, const std::string& seed, const std::string& wear_rate = "") {
    std::string text = "\n" + read_text(fs::path(MILLWEAR_SOURCE_DIR) / "scenarios/lab-mill.toml");
    const auto replace = [&text](const std::string& key, const std::string& value) {
      const auto at = text.find("\n" + key + " =");
      if (at == std::string::npos) {
        ADD_FAILURE() << "lab-mill.toml has no " << key;
        return;
      }
      const auto end = text.find('\n', at + 1);
      text.replace(at + 1, end - at - 1, key + " = " + value);
    };
    replace("name", "\"" + name + "\"");
    replace("seed", seed);
    if (!wear_rate.empty()) replace("wear_rate", wear_rate);
    std::error_code ec;
    fs::create_directories(dir_ / "scenarios");
    if (!fs::exists(dir_ / "profiles")) fs::create_directory_symlink(fs::path(MILLWEAR_SOURCE_DIR) / "profiles", dir_ / "profiles", ec);
    const fs::path path = dir_ / "scenarios" / (name + ".toml");
    std::ofstream(path) << text.substr(1);
    return path;
  }

  TempDir dir_{"millwear-replicates"};
};

struct Row {
  double mean = 0.0, se = 0.0;
};

// A column and its _se at a design's stage in summary.csv.
Row summary_value(const fs::path& out, const std::string& design, int stage, const std::string& column) {
  const millwear::io::CsvData t = millwear::io::read_csv((out / "summary.csv").string());
  const auto designs = t.texts("design");
  const auto stages = t.numbers("stage");
  const auto values = t.numbers(column);
  const auto errors = t.numbers(column + "_se");
  for (std::size_t i = 0; i < designs.size(); ++i)
    if (designs[i] == design && static_cast<int>(stages[i]) == stage) return {values[i], errors[i]};
  ADD_FAILURE() << "no row " << design << " stage " << stage << " in " << out;
  return {};
}

TEST_F(Replicates, TheReportedErrorAgreesWithTheSpreadOfIndependentRuns) {
  // Eight seeds in two groups of four: the groups' means differ by less than three combined
  // standard errors (a 3-sigma check of a 1-degree-of-freedom difference).
  const fs::path a = dir_ / "a", b = dir_ / "b";
  const auto ra = run_millwear("run " + src("scenarios/lab-mill.toml") + " -o " + quoted(a) + kShort +
                               " --replicates 4 --set solver.seed=1");
  ASSERT_EQ(ra.exit_code, 0) << ra.output;
  const auto rb = run_millwear("run " + src("scenarios/lab-mill.toml") + " -o " + quoted(b) + kShort +
                               " --replicates 4 --set solver.seed=5");
  ASSERT_EQ(rb.exit_code, 0) << rb.output;
  for (const std::string column : {"area_loss_pct", "power_kw", "collision_kw", "liner_shear_kw"}) {
    const int stage = column == "area_loss_pct" ? 1 : 0;
    const Row x = summary_value(a, "lab-mill", stage, column), y = summary_value(b, "lab-mill", stage, column);
    EXPECT_GT(x.se, 0.0) << column;
    EXPECT_GT(y.se, 0.0) << column;
    EXPECT_LT(std::abs(x.mean - y.mean), 3.0 * std::hypot(x.se, y.se)) << column;
  }
  // The replicates' own rows, and the manifest's record of where the errors come from.
  const millwear::io::CsvData reps = millwear::io::read_csv((a / "replicates.csv").string());
  EXPECT_EQ(reps.numbers("seed").size(), 8u);  // 4 histories x 2 stages
  const auto m = nlohmann::json::parse(read_text(a / "manifest.json"));
  EXPECT_EQ(m["replicates"], 4);
  EXPECT_EQ(m["estimates"][0]["error_source"], "replicates");
  EXPECT_EQ(m["designs"].size(), 4u);
  // Replicate 1 is the design's own run: seed 1, the same files as without --replicates.
  EXPECT_TRUE(fs::exists(a / "profiles/lab-mill_stage1.csv"));
  EXPECT_TRUE(fs::exists(a / "profiles/lab-mill.r4_stage1.csv"));
  EXPECT_NE(read_text(a / "summary.csv").find(",replicates,"), std::string::npos);
  // The manifest lists every file the run wrote (what --force deletes), the replicates' too,
  // and nothing that is not there.
  std::set<std::string> listed, on_disk;
  for (const auto& f : m["files"]) listed.insert(f.get<std::string>());
  for (const auto& e : fs::recursive_directory_iterator(a))
    if (e.is_regular_file()) on_disk.insert(fs::relative(e.path(), a).string());
  for (const auto& f : on_disk) EXPECT_EQ(listed.count(f), 1u) << "written but not listed: " << f;
  for (const auto& f : listed) EXPECT_EQ(on_disk.count(f), 1u) << "listed but not written: " << f;
}

TEST_F(Replicates, OneHistorysErrorsAreLabelledBatchMeans) {
  const fs::path out = dir_ / "one";
  const auto r = run_millwear("run " + src("scenarios/lab-mill.toml") + " -o " + quoted(out) + kShort);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const millwear::io::CsvData t = millwear::io::read_csv((out / "summary.csv").string());
  for (const auto& s : t.texts("error_source")) EXPECT_EQ(s, "batch_means");
  EXPECT_NE(r.output.find("errors: batch means of each window (one history per design;"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("lower bound"), std::string::npos) << r.output;
  // The new stage, worn through, records the errors of the area and height its wear removed;
  // the last stage, not worn through, none.
  const std::string stage0 = read_text(out / "stages/lab-mill_stage0.record");
  const std::string stage1 = read_text(out / "stages/lab-mill_stage1.record");
  EXPECT_NE(stage0.find("\nworn_area_se_m2="), std::string::npos);
  EXPECT_NE(stage0.find("\nworn_height_se_m="), std::string::npos);
  EXPECT_EQ(stage1.find("worn_area_se_m2"), std::string::npos);
  EXPECT_GT(summary_value(out, "lab-mill", 0, "power_kw").se, 0.0);
  EXPECT_GT(summary_value(out, "lab-mill", 1, "area_loss_pct").se, 0.0);
  EXPECT_FALSE(fs::exists(out / "replicates.csv"));
  const auto m = nlohmann::json::parse(read_text(out / "manifest.json"));
  EXPECT_EQ(m["estimates"][0]["error_source"], "batch_means");
}

TEST_F(Replicates, OneHistorysLifterErrorsAgreeWithTheSpreadOfSeeds) {
  // Twelve seeds of the lab mill's two stages: each history's own error of the area lost (the
  // windows of every wear update of a stage, in quadrature) and of its life (through its life
  // line) lie within a factor of two of how the histories scatter.
  const fs::path out = dir_ / "seeds";
  const auto r = run_millwear("run " + src("scenarios/lab-mill.toml") + " -o " + quoted(out) +
                              " --quiet --replicates 12");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const millwear::io::CsvData t = millwear::io::read_csv((out / "replicates.csv").string());
  const auto stage = t.numbers("stage"), area = t.numbers("area_mm2"), area_se = t.numbers("area_mm2_se");
  const auto life = t.numbers("life_h"), life_se = t.numbers("life_h_se");
  const auto ratio = [](const std::vector<double>& x, const std::vector<double>& se) {
    const Estimate spread = millwear::mean_and_se(x);
    double ms = 0.0;
    for (double s : se) ms += s * s / static_cast<double>(se.size());
    return std::sqrt(ms) / (spread.se * std::sqrt(static_cast<double>(x.size())));  // rms error / sd
  };
  for (const int k : {1, 2}) {
    std::vector<double> a, s;
    for (std::size_t i = 0; i < stage.size(); ++i)
      if (static_cast<int>(stage[i]) == k) a.push_back(area[i]), s.push_back(area_se[i]);
    ASSERT_EQ(a.size(), 12u) << k;
    const double q = ratio(a, s);
    EXPECT_GT(q, 0.5) << "area at stage " << k;
    EXPECT_LT(q, 2.0) << "area at stage " << k;
  }
  std::vector<double> l, ls;
  for (std::size_t i = 0; i < stage.size(); ++i)
    if (stage[i] == 0.0) l.push_back(life[i]), ls.push_back(life_se[i]);
  const double q = ratio(l, ls);
  EXPECT_GT(q, 0.5) << "life";
  EXPECT_LT(q, 2.0) << "life";
}

// The verdict on a figure in the manifest.
nlohmann::json verdict(const fs::path& out, const std::string& figure) {
  const auto m = nlohmann::json::parse(read_text(out / "manifest.json"));
  for (const auto& v : m["verdicts"])
    if (v["figure"] == figure) return v;
  ADD_FAILURE() << "no verdict on " << figure;
  return {};
}

TEST_F(Replicates, TwoCopiesOfADesignAreNotResolvedAndADoubledWearRateIs) {
  const fs::path same = dir_ / "same", doubled = dir_ / "doubled";
  const fs::path a = scene_copy("copy-a", "11"), b = scene_copy("copy-b", "23");
  const auto r1 = run_millwear("run " + quoted(a) + " " + quoted(b) + " -o " + quoted(same) + kShort +
                               " --replicates 3 --reference copy-a");
  ASSERT_EQ(r1.exit_code, 0) << r1.output;
  for (const std::string figure : {"life_h", "area_loss_pct", "power_kw"}) {
    const auto v = verdict(same, figure);
    EXPECT_FALSE(v["resolved"].get<bool>()) << v.dump();
    EXPECT_NE(v["text"].get<std::string>().find("not resolved"), std::string::npos);
    EXPECT_EQ(v["replicates"].get<int>(), 3) << v.dump();
    EXPECT_EQ(v["error_source"], "replicates") << v.dump();
  }
  EXPECT_NE(read_text(same / "summary.md").find("not resolved"), std::string::npos);

  // The same seed, one design wearing twice as fast: its area loss is resolved as higher and
  // its life as shorter.
  const fs::path fast = scene_copy("fast", "11", "2e-10");
  const auto r2 = run_millwear("run " + quoted(a) + " " + quoted(fast) + " -o " + quoted(doubled) + kShort +
                               " --replicates 3 --reference copy-a");
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  const auto loss = verdict(doubled, "area_loss_pct");
  EXPECT_TRUE(loss["resolved"].get<bool>()) << loss.dump();
  EXPECT_GT(loss["hours"].get<double>(), 0.0) << loss.dump();
  EXPECT_TRUE(verdict(doubled, "life_h")["hours"].is_null());
  EXPECT_GT(loss["difference"].get<double>(), 0.0);
  const auto life = verdict(doubled, "life_h");
  EXPECT_TRUE(life["resolved"].get<bool>()) << life.dump();
  EXPECT_LT(life["difference"].get<double>(), 0.0);
  EXPECT_NE(life["text"].get<std::string>().find("fast wears out before copy-a"), std::string::npos) << life.dump();
}

}  // namespace

// The area-loss verdict compares two designs at equal hours: at the last stage both reached
// at the same hours, or not at all when their stages never meet (a design with 37 h stages
// against one with 100 h stages was judged on 37 h of wear against 100 h).
TEST(Verdicts, AreaLossIsComparedAtStagesOfEqualHoursOnly) {
  auto design = [](const std::string& name, std::vector<double> hours) {
    millwear::DesignEstimate d;
    d.name = name;
    d.life_h = {1000.0, 10.0};
    for (std::size_t k = 0; k < hours.size(); ++k) {
      millwear::StageEstimate s;
      s.stage = static_cast<int>(k);
      s.hours = hours[k];
      s.area_loss_fraction = {0.001 * hours[k], 0.0001};
      s.power_W = {1000.0, 10.0};
      d.stages.push_back(s);
    }
    return d;
  };
  auto area_verdicts = [](const std::vector<millwear::Verdict>& vs) {
    std::vector<millwear::Verdict> out;
    for (const auto& v : vs)
      if (v.figure == "area_loss_pct") out.push_back(v);
    return out;
  };
  const auto ref = design("ref", {0.0, 100.0, 200.0});
  const auto same = area_verdicts(millwear::study::compare_designs({ref, design("same", {0.0, 100.0, 200.0})}, "ref"));
  ASSERT_EQ(same.size(), 1u);
  EXPECT_EQ(same[0].stage, 2);
  const auto shorter = area_verdicts(millwear::study::compare_designs({ref, design("short", {0.0, 37.0, 74.0})}, "ref"));
  EXPECT_TRUE(shorter.empty());
  const auto partly = area_verdicts(millwear::study::compare_designs({ref, design("partly", {0.0, 100.0, 150.0})}, "ref"));
  ASSERT_EQ(partly.size(), 1u);
  EXPECT_EQ(partly[0].stage, 1);
  EXPECT_EQ(partly[0].hours, 100.0);
}

// A life one design does not have (no height trend to the replacement height yet) is not
// compared "by nan": the verdict says so, and a known pair of lives still reads as before.
TEST(Verdicts, AnUnknownLifeIsNotComparedByNan) {
  auto design = [](const std::string& name, double life_h) {
    millwear::DesignEstimate d;
    d.name = name;
    d.life_h = {life_h, std::isfinite(life_h) ? 10.0 : std::nan("")};
    millwear::StageEstimate s;
    s.power_W = {1000.0, 10.0};
    d.stages.push_back(s);
    return d;
  };
  auto life_text = [](const std::vector<millwear::Verdict>& vs) {
    for (const auto& v : vs)
      if (v.figure == "life_h") return v.text;
    return std::string("(none)");
  };
  const std::string unknown = life_text(
      millwear::study::compare_designs({design("ref", std::nan("")), design("new", std::nan(""))}, "ref"));
  EXPECT_EQ(unknown.find("nan"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("life: new against ref: not compared"), std::string::npos) << unknown;
  const std::string one = life_text(millwear::study::compare_designs({design("ref", 1000.0), design("new", std::nan(""))}, "ref"));
  EXPECT_NE(one.find("not compared"), std::string::npos) << one;
  const std::string known = life_text(millwear::study::compare_designs({design("ref", 1000.0), design("new", 900.0)}, "ref"));
  EXPECT_NE(known.find("new wears out before ref by 100"), std::string::npos) << known;
}
