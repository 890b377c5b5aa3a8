// Tests for src/plots: every figure script renders from a small synthetic run folder
// (two designs, stages 0..4 of 750 h, made-up but plausible numbers), and failures come
// back as RunError with a usable message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace millwear;
using millwear::testing::TempDir;

namespace {



// Writes a run folder in the app's formats: summary.csv, profiles/, spectrum.csv,
// snapshot_DESIGN.csv and liner_DESIGN.csv. The 1x30 design wears faster (as in the
// paper's Fig. 7) and is the reference (its stage 0 normalised values are 1).
void write_synthetic_run(const std::string& out, bool with_everything = true) {
  io::create_run_folder(out);
  const std::vector<std::string> designs = {"2x30", "1x30"};
  io::CsvTable summary({"design", "stage", "hours", "area_mm2", "area_norm", "area_loss_pct",
                        "height_mm", "power_kw", "power_norm", "collision_kw", "collision_norm",
                        "utilization", "utilization_norm", "life_h", "life_extrapolated"});
  io::CsvTable spectrum({"design", "energy_J_lower", "energy_J_upper", "count_per_s", "energy_W"});
  for (std::size_t di = 0; di < designs.size(); ++di) {
    const std::string& d = designs[di];
    const double loss_per_stage = (d == "1x30") ? 0.085 : 0.06;
    const double p0 = (d == "1x30") ? 1.0 : 0.97, c0 = (d == "1x30") ? 1.0 : 1.04;
    for (int k = 0; k <= 4; ++k) {
      const double an = 1.0 - loss_per_stage * k;
      const double pn = p0 * (1.0 + 0.01 * k - 0.004 * k * k), cn = c0 * (1.0 - 0.03 * k);
      summary.add_row({d, k, 750.0 * k, 30000.0 * an, an, 100.0 * (1.0 - an), 150.0 * an,
                       1200.0 * pn, pn, 300.0 * cn, cn, 0.25 * cn / pn, cn / pn,
                       3000.0 / (loss_per_stage * 4 / 0.6), k == 4 ? 1 : 0});
      // Trapezoid (2x30: both faces at 30 deg) or one face vertical (1x30), lower each stage.
      const double h = 150.0 * an, w = 200.0, t = std::tan(30.0 * kPi / 180.0);
      io::CsvTable prof({"x_mm", "y_mm"});
      prof.add_row({-w / 2 - h * t, 0.0}).add_row({-w / 2, h}).add_row({w / 2, h});
      prof.add_row({d == "2x30" ? w / 2 + h * t : w / 2, 0.0});
      prof.write(io::profile_path(out, d, k));
    }
    for (int b = 0; b < 16; ++b) {
      const double lo = 1e-4 * std::pow(10.0, 0.3 * b), up = lo * std::pow(10.0, 0.3);
      const double count = (b == 15) ? 0.0 : 5e4 * std::pow(lo / 1e-4, -1.2) * (1.0 + 0.1 * di);
      spectrum.add_row({d, lo, up, count, count * std::sqrt(lo * up)});
    }
    if (!with_everything) continue;
    io::CsvTable snap({"x_m", "y_m", "radius_m", "species", "species_name", "ball"});
    const double R = 4.0;
    for (int i = 0; i < 300; ++i) {  // a kidney of disks in the lower left of the mill
      const double a = 2.0 * kPi * std::fmod(i * 0.618033988749895, 1.0);
      const double r = (R - 0.3) * std::sqrt(std::fmod(i * 0.7548776662, 1.0));
      const double x = r * std::cos(a), y = r * std::sin(a);
      if (y > -0.5 * x - 1.0) continue;
      snap.add_row({x, y, 0.05 + 0.03 * (i % 3), i % 2, i % 2 ? "steel-ball" : "ore-rock", i % 2});
    }
    snap.write(io::snapshot_path(out, d));
    // The 2x30 liner carries the marks a run writes (toe, shoulder, centre of mass, turning);
    // the 1x30 liner only the columns every liner file has.
    std::vector<std::string> cols = {"x1_m", "y1_m", "x2_m", "y2_m", "wear_rate_mm_per_1000h"};
    if (di == 0)
      for (const char* c : {"toe_deg", "shoulder_deg", "centrifuged", "com_x_m", "com_y_m", "turning"}) cols.push_back(c);
    io::CsvTable liner(cols);
    for (int i = 0; i < 120; ++i) {
      const double a1 = 2.0 * kPi * i / 120, a2 = 2.0 * kPi * (i + 1) / 120;
      std::vector<double> values = {R * std::cos(a1), R * std::sin(a1), R * std::cos(a2), R * std::sin(a2),
                                    std::max(0.0, 20.0 * std::cos(a1 + 2.0)) * (di ? 1.3 : 1.0)};
      if (di == 0) values.insert(values.end(), {-35.0, 125.0, 0.0, 1.2, -1.8, 1.0});
      liner.add_row(std::vector<io::CsvCell>(values.begin(), values.end()));
    }
    liner.write(io::liner_path(out, d));
  }
  summary.write(io::summary_path(out));
  if (with_everything) spectrum.write(io::spectrum_path(out));
}

bool is_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  return in.gcount() == 8 && std::memcmp(magic, png, 8) == 0 && fs::file_size(path) > 1000;
}

bool is_svg(const std::string& path) {
  std::string text = io::read_file(path);
  return text.size() > 1000 && text.find("<svg") != std::string::npos &&
         text.find("</svg>") != std::string::npos;
}

bool has_temp_files(const std::string& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (io::is_temp_name(e.path().filename().string())) return true;
  return false;
}

// One synthetic run folder rendered once for all the per-figure checks.
class PlotsRendered : public ::testing::TestWithParam<std::string> {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("millwear-plots");
    write_synthetic_run(dir_->path());
    written_ = plots::render_all_figures(dir_->path(), {"2x30", "1x30"});
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static TempDir* dir_;
  static std::vector<std::string> written_;
};
TempDir* PlotsRendered::dir_ = nullptr;
std::vector<std::string> PlotsRendered::written_;

}  // namespace

TEST(Plots, PlotsDirHoldsEveryFigureScript) {
  const std::string dir = plots::plots_dir();
  for (const char* s : {"common", "fig6_profiles", "fig7_area", "fig8_power", "fig9_collision",
                        "fig10_utilization", "normalised_vs_hours", "spectrum", "snapshot"})
    EXPECT_TRUE(io::file_exists(dir + "/" + s + ".gp")) << s;
}

TEST_P(PlotsRendered, FigureIsWrittenAsPngAndSvg) {
  const std::string base = io::plots_out_dir(dir_->path()) + "/" + GetParam();
  EXPECT_TRUE(is_png(base + ".png")) << base;
  EXPECT_TRUE(is_svg(base + ".svg")) << base;
  EXPECT_NE(std::find(written_.begin(), written_.end(), base + ".png"), written_.end());
  EXPECT_NE(std::find(written_.begin(), written_.end(), base + ".svg"), written_.end());
}

INSTANTIATE_TEST_SUITE_P(EveryFigure, PlotsRendered,
                         ::testing::Values("fig6_profiles", "fig7_area", "fig8_power",
                                           "fig9_collision", "fig10_utilization", "spectrum",
                                           "snapshot_2x30", "snapshot_1x30"));

TEST_F(PlotsRendered, WritesExactlyTheFiguresAndNoTemporaries) {
  EXPECT_EQ(written_.size(), 16u);  // 8 figures x (png, svg)
  EXPECT_FALSE(has_temp_files(io::plots_out_dir(dir_->path())));
  EXPECT_FALSE(has_temp_files(io::plots_data_dir(dir_->path())));
  // The per-design summary is sorted by hours and keeps the header.
  io::CsvData s = io::read_csv(io::plots_data_dir(dir_->path()) + "/1x30_summary.csv");
  EXPECT_EQ(s.row_count(), 5u);
  EXPECT_DOUBLE_EQ(s.number(4, "hours"), 3000.0);
}

// The snapshot's legend names the species as the scene does, and the marks are drawn where
// the liner file has them.
TEST_F(PlotsRendered, SnapshotNamesTheSpeciesAndMarksToeAndShoulder) {
  const std::string marked = io::read_file(io::plots_out_dir(dir_->path()) + "/snapshot_2x30.svg");
  for (const char* text : {"ore-rock", "steel-ball", "toe", "shoulder", "centre of mass", "turning counter-clockwise"})
    EXPECT_NE(marked.find(text), std::string::npos) << text;
  const std::string plain = io::read_file(io::plots_out_dir(dir_->path()) + "/snapshot_1x30.svg");
  EXPECT_NE(plain.find("ore-rock"), std::string::npos);
  EXPECT_EQ(plain.find("shoulder"), std::string::npos);
}

TEST(Plots, MissingInputsSkipTheirFigures) {
  TempDir dir{"millwear-plots"};
  write_synthetic_run(dir.path(), /*with_everything=*/false);  // summary and profiles only
  auto written = plots::render_all_figures(dir.path(), {});
  EXPECT_EQ(written.size(), 10u);  // fig6..fig10, png + svg; no spectrum, no snapshots
  EXPECT_FALSE(io::file_exists((dir / "plots/spectrum.png").string()));
  EXPECT_TRUE(is_png((dir / "plots/fig10_utilization.png").string()));
}

TEST(Plots, ScriptErrorIsRunErrorQuotingTheLog) {
  TempDir dir{"millwear-plots"};
  const std::string script = (dir / "bad.gp").string();
  io::write_file_atomic(script, "set output outbase.'.png'\nthis_is_not_a_command 1\n");
  try {
    plots::render_figure(script, {{"outbase", (dir / "bad").string()}});
    FAIL() << "expected RunError";
  } catch (const RunError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("gnuplot failed on " + script), std::string::npos) << msg;
    EXPECT_NE(msg.find("invalid command"), std::string::npos) << msg;
  }
  EXPECT_FALSE(io::file_exists((dir / "bad.png").string()));
  EXPECT_FALSE(has_temp_files(dir.path()));
  EXPECT_TRUE(io::file_exists((dir / "gnuplot.log").string()));
}

TEST(Plots, ScriptThatWritesNothingIsRunError) {
  TempDir dir{"millwear-plots"};
  const std::string script = (dir / "quiet.gp").string();
  io::write_file_atomic(script, "a = 1\n");
  EXPECT_THROW(plots::render_figure(script, {{"outbase", (dir / "quiet").string()}}), RunError);
}

TEST(Plots, MissingGnuplotIsClearRunError) {
  TempDir dir{"millwear-plots"};
  write_synthetic_run(dir.path());
  const std::string old_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", dir.path().c_str(), 1);  // a folder without gnuplot
  std::string msg;
  try {
    plots::render_figure(plots::script_path("fig7_area"),
                         {{"datadir", dir.path().string()}, {"designs", "2x30"}});
  } catch (const RunError& e) {
    msg = e.what();
  }
  ::setenv("PATH", old_path.c_str(), 1);
  EXPECT_NE(msg.find("gnuplot not found"), std::string::npos) << msg;
}

TEST(Plots, EnvironmentOverridesPlotsDir) {
  TempDir dir{"millwear-plots"};
  ::setenv("MILLWEAR_PLOTS_DIR", dir.path().c_str(), 1);
  EXPECT_EQ(plots::plots_dir(), dir.path());
  ::setenv("MILLWEAR_PLOTS_DIR", ((dir / "missing").string()).c_str(), 1);
  EXPECT_THROW(plots::plots_dir(), RunError);
  ::unsetenv("MILLWEAR_PLOTS_DIR");
}
