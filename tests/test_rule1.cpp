// Rule 1 decided by statistics: the deviation of a factor's profile from the smallest
// factor's, against the seed-to-seed scatter and the tolerance.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "cli_support.hpp"
#include "engine_fixtures.hpp"
#include "io/csv.hpp"
#include "study/rule1.hpp"
#include "temp_dir.hpp"

namespace millwear {
namespace {

namespace fs = std::filesystem;
using millwear::testing::TempDir;
using testing::read_text;
using testing::run_millwear;

Rule1Row row_with(std::vector<double> mean_m, std::vector<double> se_m) {
  Rule1Row r;
  r.depth_mean_m = std::move(mean_m);
  r.depth_se_m = std::move(se_m);
  return r;
}

// Tolerance 1 mm (5% of a 20 mm lifter). A 3 mm difference known to 0.1 mm is a real
// deviation; a 1.2 mm difference known to 0.5 mm is not significantly above the tolerance.
TEST(Rule1Statistics, ADeviationFarAboveTheToleranceAndItsErrorDeviates) {
  const Rule1Row ref = row_with({1e-3, 2e-3, 1e-3}, {0.07e-3, 0.07e-3, 0.07e-3});
  Rule1Row row = row_with({1e-3, 5e-3, 1e-3}, {0.07e-3, 0.07e-3, 0.07e-3});
  compare_rule1_row(row, ref, 1e-3);
  EXPECT_EQ(row.verdict, Rule1Verdict::Deviates);
  EXPECT_NEAR(row.deviation_m, 3e-3, 1e-15);
  EXPECT_NEAR(row.deviation_se_m, std::hypot(0.07e-3, 0.07e-3), 1e-15);
  EXPECT_LT(row.chance_within, 1e-6);
}

TEST(Rule1Statistics, ADeviationWithinItsErrorOfTheToleranceAgrees) {
  const Rule1Row ref = row_with({1e-3, 2e-3}, {0.3e-3, 0.4e-3});
  Rule1Row row = row_with({1e-3, 3.2e-3}, {0.3e-3, 0.3e-3});
  compare_rule1_row(row, ref, 1e-3);
  EXPECT_EQ(row.verdict, Rule1Verdict::Agrees);
  EXPECT_NEAR(row.deviation_m, 1.2e-3, 1e-15);
  EXPECT_NEAR(row.deviation_se_m, 0.5e-3, 1e-15);
  // (1.0 - 1.2) / 0.5 = -0.4 standard errors: Phi(-0.4) = 0.3446.
  EXPECT_NEAR(row.chance_within, 0.3446, 1e-4);
  // Noise floor: twice the largest combined error, here at the second station.
  EXPECT_NEAR(row.noise_floor_m, 1e-3, 1e-15);
}

// One seed per factor: the depths have no error, so the noise floor and the chance of being
// within the tolerance are unknown (NaN, printed "-"), not a noise of zero and a chance of 100%.
TEST(Rule1Statistics, OneSeedPerFactorLeavesTheNoiseAndTheChanceUnknown) {
  const Rule1Row ref = row_with({1e-3, 2e-3}, {0.0, 0.0});
  Rule1Row row = row_with({1e-3, 2.5e-3}, {0.0, 0.0});
  compare_rule1_row(row, ref, 1e-3);
  EXPECT_EQ(row.verdict, Rule1Verdict::Agrees);  // 0.5 mm against a 1 mm tolerance
  EXPECT_NEAR(row.deviation_m, 0.5e-3, 1e-15);
  EXPECT_TRUE(std::isnan(row.deviation_se_m));
  EXPECT_TRUE(std::isnan(row.noise_floor_m));
  EXPECT_TRUE(std::isnan(row.chance_within));
}

// The worst station is the one most standard errors above the tolerance, not the largest
// difference: a large difference where the seeds scatter widely says less than a smaller
// one where they agree.
TEST(Rule1Statistics, TheWorstStationIsTheMostSignificantOne) {
  const Rule1Row ref = row_with({0.0, 0.0}, {2e-3, 0.1e-3});
  Rule1Row row = row_with({4e-3, 2e-3}, {2e-3, 0.1e-3});
  compare_rule1_row(row, ref, 1e-3);
  EXPECT_NEAR(row.deviation_m, 2e-3, 1e-15);
  EXPECT_NEAR(row.max_deviation_m, 4e-3, 1e-15);
  EXPECT_EQ(row.verdict, Rule1Verdict::Deviates);
}

// Rule 1 asks for the same profile, so the same spread: a factor whose seeds scatter far more
// than the reference's does not agree even when its mean does. Four seeds each: a variance
// ratio of 25 has a chance of 1.27% under equal spreads (F with 3 and 3 degrees of
// freedom); a ratio of 2, about 29%.
TEST(Rule1Statistics, SeedsThatScatterFarMoreThanTheReferencesDoNotAgree) {
  Rule1Row ref = row_with({1e-3, 2e-3}, {0.1e-3, 0.1e-3});
  ref.replicates.resize(4);
  ref.scatter_m = 0.2e-3;
  Rule1Row wide = row_with({1e-3, 2e-3}, {0.5e-3, 0.5e-3});
  wide.replicates.resize(4);
  wide.scatter_m = 1.0e-3;
  compare_rule1_row(wide, ref, 1e-3);
  EXPECT_EQ(wide.verdict, Rule1Verdict::Scatters);
  EXPECT_NEAR(wide.scatter_ratio, 25.0, 1e-12);
  EXPECT_NEAR(wide.scatter_p, 0.01266, 1e-4);
  Rule1Row close = row_with({1e-3, 2e-3}, {0.1e-3, 0.1e-3});
  close.replicates.resize(4);
  close.scatter_m = 0.2e-3 * std::sqrt(2.0);
  compare_rule1_row(close, ref, 1e-3);
  EXPECT_EQ(close.verdict, Rule1Verdict::Agrees);
  EXPECT_NEAR(close.scatter_p, 0.2918, 1e-3);
}

// The same factor twice is pure noise (its replicates run with other seeds): the largest
// factor tried is recommended. Lab mill at draft, 3 seeds each.
TEST(Rule1Statistics, TheSameFactorTwiceIsNoiseAndTheLargestIsRecommended) {
  Scene s = testing::lab_mill();
  s.wear.stages = 1;
  Rule1Options o;
  o.factors = {1e5, 1e5};
  o.replicates = 3;
  const Rule1Report r = rule1_check(s, o);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[0].verdict, Rule1Verdict::Reference);
  EXPECT_EQ(r.rows[1].verdict, Rule1Verdict::Agrees);
  EXPECT_EQ(r.recommended_row, 1);
  // Independent seeds: the two rows' profiles are not the same bits.
  EXPECT_GT(r.rows[1].max_deviation_m, 0.0);
  // And the worn depth is real: the lifter wore over a tenth of its height somewhere.
  double deepest = 0.0;
  for (double d : r.rows[0].depth_mean_m) deepest = std::max(deepest, d);
  EXPECT_GT(deepest, 0.1 * r.lifter_height_m);
  // The tables tell the two entries of one factor apart: each history says which it ran for.
  const TempDir out("millwear-test-rule1-twice");
  write_rule1_outputs(out.path().string(), s, r);
  const io::CsvData table = io::read_csv((out.path() / "rule1.csv").string());
  ASSERT_EQ(table.row_count(), 2u);
  EXPECT_EQ(table.text(0, table.column("entry")), "1");
  EXPECT_EQ(table.text(1, table.column("entry")), "2");
  const io::CsvData reps = io::read_csv((out.path() / "rule1_replicates.csv").string());
  ASSERT_EQ(reps.row_count(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(reps.text(k, reps.column("entry")), k < 3 ? "1" : "2") << k;
    EXPECT_EQ(reps.text(k, reps.column("seed")), std::to_string(r.rows[k / 3].replicates[k % 3].seed)) << k;
  }
}

// A factor that wears more than a quarter of the lifter in one update fails and is never
// recommended; the smaller factor still is. The failed runs still report the time they
// simulated up to the stop (their charge was settled, spun up and worn for a while).
TEST(Rule1Statistics, AFactorPastTheOneUpdateBoundFails) {
  Scene s = testing::lab_mill();
  s.wear.stages = 1;
  Rule1Options o;
  o.factors = {1e5, 1e8};
  o.replicates = 2;
  const Rule1Report r = rule1_check(s, o);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[1].verdict, Rule1Verdict::Failed);
  ASSERT_FALSE(r.rows[1].replicates[0].events.empty());
  EXPECT_NE(r.rows[1].replicates[0].events[0].find("too large for rule 1"), std::string::npos);
  for (const auto& rep : r.rows[1].replicates) EXPECT_GT(rep.simulated_s, 0.0) << rep.seed;
  EXPECT_EQ(r.recommended_row, 0);
}

// `millwear rule1 -o OUT` writes the table, the replicates, the profiles and Fig. 5 as PNG
// and SVG.
TEST(Rule1Cli, WritesTheTableAndFigureFive) {
  const TempDir out("millwear-test-rule1");
  const auto r = run_millwear("rule1 " + testing::quoted(fs::path(testing::source_path("scenarios/lab-mill.toml"))) +
                              " --factors 1e5 2e5 --replicates 2 -o " + testing::quoted(out) +
                              " --set solver.seed=11");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // What made the folder: the overrides and the seed they give, the factors, every file.
  const std::string manifest = read_text(out / "manifest.json");
  for (const char* s : {"\"command\": \"rule1\"", "\"solver.seed=11\"", "\"seed\": 11", "\"factors\": \"100000 200000\"",
                        "\"replicates\": \"2\"", "\"rule1.csv\"", "\"plots/fig5_rule1.svg\""})
    EXPECT_NE(manifest.find(s), std::string::npos) << s << " in\n" << manifest;
  const std::string csv = read_text(out / "rule1.csv");
  EXPECT_EQ(csv.rfind("scene,factor,replicates,", 0), 0u) << csv;
  EXPECT_NE(csv.find("lab-mill,100000,2,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("lab-mill,200000,2,"), std::string::npos) << csv;
  for (const char* f : {"rule1_replicates.csv", "rule1_profiles.dat", "plots/fig5_rule1.png", "plots/fig5_rule1.svg"})
    EXPECT_GT(fs::file_size(out / f), 0u) << f;
}

// The help shows the defaults the command runs with: they are read from the options' structs.
TEST(Rule1Cli, TheHelpShowsTheLibrarysDefaults) {
  const auto r = run_millwear("rule1 --help");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Rule1Options defaults;
  EXPECT_NE(r.output.find("(default " + std::to_string(defaults.replicates) + ")"), std::string::npos) << r.output;
  char tolerance[32];
  std::snprintf(tolerance, sizeof tolerance, "(default %g)", defaults.tolerance_pct_height);
  EXPECT_NE(r.output.find(tolerance), std::string::npos) << r.output;
}

}  // namespace
}  // namespace millwear
