// Rule 1: the wear history at several C_model factors, replicated over seeds, and whether
// their profiles part by more than the tolerance beyond the scatter between seeds.
#include "study/rule1.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <boost/math/distributions/fisher_f.hpp>

#include "common/errors.hpp"
#include "common/parallel.hpp"
#include "common/text.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "plots/plots.hpp"
#include "scene/limits.hpp"
#include "study/plan.hpp"
#include "wear/history.hpp"

namespace millwear {

namespace {

using Clock = std::chrono::steady_clock;

// Stations per lifter height along the new surface: fine enough that a worn corner falls
// between two stations no further apart than 2.5% of the height.
constexpr double kStationsPerHeight = 40.0;
// A deviation is significant when it exceeds the tolerance by more than this many of its
// standard errors.
constexpr double kSignificance = 2.0;
// A factor's seeds scatter more than the reference's when equal spreads would give a variance
// ratio this large less often than this (one-sided).
constexpr double kScatterLevel = 0.05;

Scene factor_scene(const Scene& scene, double factor, std::uint64_t seed) {
  Scene s = scene;
  s.wear.mode = WearMode::Continuous;
  s.wear.factor = factor;
  s.solver.seed = seed;
  return s;
}

Rule1Replicate run_replicate(const Scene& s) {
  Rule1Replicate rep;
  rep.seed = s.solver.seed;
  const auto t0 = Clock::now();
  try {
    const WearHistory h = run_wear_history(s);
    for (const auto& st : h.stages) rep.simulated_s += st.simulated_s;
    rep.events = h.events;
    if (h.failure.empty() && !h.stages.empty()) rep.profile = h.stages.back().units[0].surface;
    else if (!h.failure.empty() && rep.events.empty()) rep.events = {h.failure};
  } catch (const NumericalError& e) {
    // A factor whose update the reshaping cannot take does not qualify; the others still run.
    rep.events = {e.what()};
  }
  rep.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return rep;
}


// Standard normal distribution function.
double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

void depth_statistics(Rule1Row& row, const Polyline& stations) {
  const std::size_t n = row.replicates.size();
  row.depth_mean_m.assign(stations.size(), 0.0);
  row.depth_se_m.assign(stations.size(), 0.0);
  double var_sum = 0.0;
  for (std::size_t s = 0; s < stations.size(); ++s) {
    double sum = 0.0, sum_sq = 0.0;
    for (const auto& rep : row.replicates) {
      const double d = distance_to_polyline(stations[s], rep.profile);
      sum += d;
      sum_sq += d * d;
    }
    const double mean = sum / n;
    row.depth_mean_m[s] = mean;
    if (n > 1) {
      const double var = std::max(0.0, (sum_sq - n * mean * mean) / (n - 1));
      row.depth_se_m[s] = std::sqrt(var / n);
      var_sum += var;
    }
  }
  if (!stations.empty()) row.scatter_m = std::sqrt(var_sum / stations.size());
}

std::string fmt(double v) { return io::format_number(v); }

}  // namespace

// The deviation of `row` from the reference row, station by station, against the tolerance.
void compare_rule1_row(Rule1Row& row, const Rule1Row& ref, double tolerance_m) {
  // The depths' errors are zero where a row has one replicate: then no error is known.
  bool error_known = false;
  for (std::size_t s = 0; s < row.depth_mean_m.size(); ++s)
    error_known = error_known || std::hypot(row.depth_se_m[s], ref.depth_se_m[s]) > 0.0;
  row.noise_floor_m = error_known ? 0.0 : Rule1Row::kUnknown;
  double worst_z = -HUGE_VAL;
  for (std::size_t s = 0; s < row.depth_mean_m.size(); ++s) {
    const double diff = std::fabs(row.depth_mean_m[s] - ref.depth_mean_m[s]);
    const double se = std::hypot(row.depth_se_m[s], ref.depth_se_m[s]);
    row.max_deviation_m = std::max(row.max_deviation_m, diff);
    if (error_known) row.noise_floor_m = std::max(row.noise_floor_m, kSignificance * se);
    // With no error known, the largest deviation is the worst; with one, the most standard
    // errors above the tolerance.
    const double z = se > 0.0 ? (diff - tolerance_m) / se : (diff - tolerance_m) * 1e300;
    if (z > worst_z) {
      worst_z = z;
      row.deviation_m = diff;
      row.deviation_se_m = error_known ? se : Rule1Row::kUnknown;
    }
  }
  if (row.deviation_se_m > 0.0) {
    row.chance_within = normal_cdf((tolerance_m - row.deviation_m) / row.deviation_se_m);
    row.verdict = row.deviation_m - tolerance_m > kSignificance * row.deviation_se_m ? Rule1Verdict::Deviates
                                                                                      : Rule1Verdict::Agrees;
  } else {
    // A deviation with no error: against the tolerance as it is; no chance where no error is
    // known at all (one seed).
    if (error_known) row.chance_within = row.deviation_m <= tolerance_m ? 1.0 : 0.0;
    row.verdict = row.deviation_m <= tolerance_m ? Rule1Verdict::Agrees : Rule1Verdict::Deviates;
  }
  const std::size_t n = row.replicates.size(), n_ref = ref.replicates.size();
  if (n > 1 && n_ref > 1 && ref.scatter_m > 0.0) {
    row.scatter_ratio = (row.scatter_m / ref.scatter_m) * (row.scatter_m / ref.scatter_m);
    const boost::math::fisher_f f(static_cast<double>(n - 1), static_cast<double>(n_ref - 1));
    row.scatter_p = boost::math::cdf(boost::math::complement(f, row.scatter_ratio));
    if (row.verdict == Rule1Verdict::Agrees && row.scatter_p < kScatterLevel) row.verdict = Rule1Verdict::Scatters;
  }
}

const char* verdict_name(Rule1Verdict v) {
  switch (v) {
    case Rule1Verdict::Reference: return "reference";
    case Rule1Verdict::Agrees: return "agrees";
    case Rule1Verdict::Deviates: return "deviates";
    case Rule1Verdict::Scatters: return "scatters";
    case Rule1Verdict::Failed: return "failed";
  }
  return "?";
}

Rule1Report rule1_check(const Scene& scene, const Rule1Options& options) {
  std::vector<double> factors = options.factors;
  std::stable_sort(factors.begin(), factors.end());
  // Each factor's histories are compared with the smallest factor's: one factor alone is
  // compared with nothing. (The same factor twice is a comparison: of two sets of seeds.)
  if (factors.size() < 2)
    throw InputError("", "--factors",
                     "at least two factors, each compared with the smallest; got " + std::to_string(factors.size()));
  if (options.replicates < 1 || options.replicates > study::kMaxReplicates)
    throw InputError("", "--replicates", "1 to " + std::to_string(study::kMaxReplicates) + " histories per factor, got " +
                                             std::to_string(options.replicates));
  // The profiles compared are one lifter's: a pattern's kinds of other shapes wear apart, and
  // a factor that keeps one of them would be taken as keeping all.
  if (!scene.mill.one_lifter_shape())
    throw InputError(scene.source_file, "lifters.pattern",
                     "one lifter shape: rule 1 compares one lifter's worn profile between factors, and the kinds of "
                     "this pattern wear apart; check the factor on a scene of each kind (lifters.profile = its file)");
  const auto nrep = static_cast<std::uint64_t>(options.replicates);
  check_derived_seeds(scene, factors.size() * nrep, "rule 1 (one seed per factor and replicate)");
  // Every factor's run within the limits (steps of a continuous stage, updates) before any runs.
  for (double f : factors) {
    if (!(f > 0.0 && f <= 1e12)) throw InputError("", "--factors", "factors in (0, 1e12], got " + short_number(f));
    // The factors and the stage count come from the command line, not the scene: the limit is
    // named as theirs.
    try {
      check_run_limits(factor_scene(scene, f, scene.solver.seed), scene.source_file);
    } catch (const InputError& e) {
      throw InputError("", "--factors, --stages",
                       "factors within the run's limits over " + std::to_string(scene.wear.stages) +
                           (scene.wear.stages == 1 ? " stage" : " stages") + "; factor " + short_number(f) + " gives " + e.where + ": " + e.expected);
    }
  }

  Rule1Report report;
  report.tolerance_pct_height = options.tolerance_pct_height;
  report.replicates = options.replicates;
  const MillGeometry new_mill = build_scene_mill(scene);
  report.new_profile = new_mill.units[0].surface;
  report.lifter_height_m = measure_lifter(new_mill.units[0], new_mill.radius_m).height_m;
  const double length = polyline_length(report.new_profile);
  const double spacing = report.lifter_height_m / kStationsPerHeight;
  const auto nst = static_cast<std::size_t>(std::ceil(length / spacing)) + 1;
  for (std::size_t s = 0; s < nst; ++s)
    report.stations.push_back(point_at_length(report.new_profile, length * s / (nst - 1)));

  report.rows.resize(factors.size());
  for (std::size_t i = 0; i < factors.size(); ++i) {
    report.rows[i].factor = factors[i];
    report.rows[i].replicates.resize(nrep);
  }
  for_each_index_parallel(factors.size() * nrep, jobs_for(options.jobs, factors.size() * nrep), [&](std::size_t j) {
    const std::size_t i = j / nrep, k = j % nrep;
    report.rows[i].replicates[k] = run_replicate(factor_scene(scene, factors[i], scene.solver.seed + j));
  });

  const double tolerance_m = 0.01 * options.tolerance_pct_height * report.lifter_height_m;
  for (std::size_t i = 0; i < report.rows.size(); ++i) {
    Rule1Row& row = report.rows[i];
    const bool failed = std::any_of(row.replicates.begin(), row.replicates.end(), [](const Rule1Replicate& r) {
      return !r.events.empty() || r.profile.empty();
    });
    if (failed) {
      row.verdict = Rule1Verdict::Failed;
      continue;
    }
    depth_statistics(row, report.stations);
    if (i == 0) {
      row.verdict = Rule1Verdict::Reference;
      row.chance_within = 1.0;
    } else if (report.rows[0].verdict == Rule1Verdict::Reference) {
      compare_rule1_row(row, report.rows[0], tolerance_m);
    }
  }
  // Largest factor that agrees, every smaller one agreeing too.
  for (std::size_t i = 0; i < report.rows.size(); ++i) {
    const Rule1Row& row = report.rows[i];
    if (row.verdict != Rule1Verdict::Reference && row.verdict != Rule1Verdict::Agrees) break;
    report.recommended_factor = row.factor;
    report.recommended_chance = row.chance_within;
    report.recommended_row = static_cast<int>(i);
  }
  return report;
}

std::vector<double> default_rule1_factors(double scene_factor) {
  return {0.5 * scene_factor, scene_factor, 2.0 * scene_factor, 10.0 * scene_factor};
}

double mean_simulated_s(const Rule1Row& row) {
  if (row.replicates.empty()) return 0.0;
  double sim = 0.0;
  for (const auto& rep : row.replicates) sim += rep.simulated_s;
  return sim / static_cast<double>(row.replicates.size());
}

std::vector<std::string> write_rule1_outputs(const std::string& out, const Scene& scene, const Rule1Report& r) {
  io::ensure_dir(out);
  const double height = r.lifter_height_m;
  std::ostringstream csv;
  // `entry` (last): the factor's place in --factors (from 1), which tells a factor given twice apart.
  csv << "scene,factor,replicates,simulated_s,verdict,deviation_mm,deviation_se_mm,deviation_pct_height,"
         "deviation_se_pct_height,max_deviation_mm,noise_floor_mm,scatter_ratio,scatter_p,tolerance_pct_height,"
         "chance_within,recommended,entry\n";
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const Rule1Row& row = r.rows[i];
    csv << scene.name << ',' << fmt(row.factor) << ',' << row.replicates.size() << ','
        << fmt(mean_simulated_s(row)) << ',' << verdict_name(row.verdict) << ',';
    // A comparison only for the factors compared; the reference and failed rows leave it empty.
    if (row.verdict == Rule1Verdict::Agrees || row.verdict == Rule1Verdict::Deviates ||
        row.verdict == Rule1Verdict::Scatters)
      csv << fmt(in_mm(row.deviation_m)) << ',' << fmt(in_mm(row.deviation_se_m)) << ','
          << fmt(100.0 * row.deviation_m / height) << ',' << fmt(100.0 * row.deviation_se_m / height) << ','
          << fmt(in_mm(row.max_deviation_m)) << ',' << fmt(in_mm(row.noise_floor_m)) << ','
          << fmt(row.scatter_ratio) << ',' << fmt(row.scatter_p) << ',';
    else
      csv << ",,,,,,,,";
    csv << fmt(r.tolerance_pct_height) << ',' << fmt(row.chance_within) << ','
        << (static_cast<int>(i) == r.recommended_row ? 1 : 0) << ',' << i + 1 << '\n';
  }
  std::ostringstream reps;
  reps << "factor,seed,simulated_s,wall_s,events,entry\n";
  for (std::size_t i = 0; i < r.rows.size(); ++i)
    for (const auto& rep : r.rows[i].replicates) {
      const Rule1Row& row = r.rows[i];
      std::string ev;
      for (const auto& e : rep.events) ev += (ev.empty() ? "" : "; ") + e;
      for (char& c : ev)
        if (c == '"' || c == '\n' || c == '\r') c = ' ';
      reps << fmt(row.factor) << ',' << rep.seed << ',' << fmt(rep.simulated_s) << ',' << fmt(rep.wall_s) << ",\""
           << ev << "\"," << i + 1 << '\n';
    }
  // gnuplot blocks (two blank lines apart): the new profile, then one block per factor with
  // a line per replicate (one blank line apart). Lifter-local mm.
  std::ostringstream dat;
  dat << "new lifter,-\n";
  for (const Vec2& p : r.new_profile) dat << fmt(p.x * 1e3) << ',' << fmt(p.y * 1e3) << '\n';
  for (const Rule1Row& row : r.rows) {
    char head[96];
    std::snprintf(head, sizeof head, "factor %.3g (%s),-\n", row.factor, verdict_name(row.verdict));
    dat << "\n\n" << head;
    bool first = true;
    for (const auto& rep : row.replicates) {
      if (rep.profile.empty()) continue;
      if (!first) dat << '\n';
      first = false;
      for (const Vec2& p : rep.profile) dat << fmt(p.x * 1e3) << ',' << fmt(p.y * 1e3) << '\n';
    }
    if (first) dat << "NaN,NaN\n";  // a failed factor keeps its block (and legend entry)
  }
  const std::vector<std::string> files = {out + "/rule1.csv", out + "/rule1_replicates.csv",
                                          out + "/rule1_profiles.dat"};
  io::write_file_atomic(files[0], csv.str());
  io::write_file_atomic(files[1], reps.str());
  io::write_file_atomic(files[2], dat.str());
  return files;
}

std::vector<std::string> render_rule1_figure(const std::string& out, const Scene& scene, const Rule1Report& r) {
  io::ensure_dir(out + "/plots");
  char title[256];
  if (r.recommended_factor > 0.0)
    std::snprintf(title, sizeof title, "%s, %d seed(s) per factor, tolerance %.3g%% of the height: recommended %.3g",
                  scene.name.c_str(), r.replicates, r.tolerance_pct_height, r.recommended_factor);
  else
    std::snprintf(title, sizeof title, "%s, %d seed(s) per factor: no factor qualified", scene.name.c_str(),
                  r.replicates);
  return plots::render_figure(plots::script_path("fig5_rule1"),
                              {{"datadir", out}, {"outbase", out + "/plots/fig5_rule1"}, {"title_extra", title}},
                              out + "/plots/gnuplot.log");
}

}  // namespace millwear
