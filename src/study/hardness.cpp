#include "study/hardness.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <numeric>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "study/surveys.hpp"

namespace millwear::validation {

namespace {

// The smallest spread of the hardness values, max / min - 1, from which b is fitted.
constexpr double kMinHardnessSpread = 1e-3;

// A period label that is a number (periods 1, 2, 3 ...), as that number.
bool label_number(const std::string& label, double& v) {
  char* end = nullptr;
  v = std::strtod(label.c_str(), &end);
  return !label.empty() && *end == '\0';
}

// The one column of `names` the file has; InputError if none or several.
std::string exactly_one(const io::CsvData& d, const std::vector<std::string>& names, const std::string& what) {
  std::string found;
  int count = 0;
  for (const auto& n : names)
    if (d.has_column(n)) { found = n; ++count; }
  if (count != 1) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw InputError(d.path, "line " + std::to_string(d.header_line), "exactly one " + what + " column of: " + list +
                                           (count == 0 ? " (none found)" : " (several found)"));
  }
  return found;
}

}  // namespace

double coefficient_of_variation(const std::vector<double>& v) {
  const double n = static_cast<double>(v.size());
  if (v.size() < 2) return 0.0;
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / n;
  double var = 0.0;
  for (double x : v) var += (x - mean) * (x - mean);
  return std::sqrt(var / (n - 1.0)) / mean;
}

HardnessData parse_hardness(const std::string& text, const std::string& name) {
  io::CsvData d = io::parse_csv(strip_comment_lines(text), name);
  HardnessData data;
  data.path = name;
  data.time_unit = exactly_one(d, {"days", "hours"}, "period length");
  data.wear_column = exactly_one(d, {"area_loss_mm2", "mass_loss_kg", "height_loss_mm", "wear_rate"}, "wear");
  const std::size_t ct = d.column(data.time_unit), cw = d.column(data.wear_column), ch = d.column("hardness");
  const bool labelled = d.has_column("period");
  double t = 0.0;
  for (std::size_t r = 0; r < d.row_count(); ++r) {
    HardnessPeriod p;
    p.line = d.row_line[r];
    const std::string where = "line " + std::to_string(p.line);
    p.label = labelled ? trim(d.text(r, d.column("period"))) : std::to_string(r + 1);
    // One row per period, in time order: a label given twice, or blank, is a copy-paste slip,
    // and numbered periods must count up (the periods' start times follow the rows).
    if (labelled) {
      if (p.label.empty()) throw InputError(name, where, "a period label in column period");
      for (const auto& q : data.periods)
        if (q.label == p.label)
          throw InputError(name, where, "each period once; period " + p.label + " is on line " + std::to_string(q.line) + " too");
      double num = 0.0, prev = 0.0;
      if (!data.periods.empty() && label_number(p.label, num) && label_number(data.periods.back().label, prev) &&
          !(num > prev))
        throw InputError(name, where, "periods in time order, each row after the one before; period " + p.label +
                                          " follows period " + data.periods.back().label);
    }
    p.length = d.number(r, ct);
    p.wear = d.number(r, cw);
    p.hardness = d.number(r, ch);
    // Bounds that keep the log-log fit finite: a period of 1e-3 to 1e6 (days or hours), a wear
    // and a hardness of 1e-9 to 1e9 in the file's units.
    if (!(p.length >= 1e-3 && p.length <= 1e6))
      throw InputError(name, where, "a period length in [0.001, 1e6] in column " + data.time_unit);
    if (!(p.wear >= 1e-9 && p.wear <= 1e9))
      throw InputError(name, where,
                       "a wear in [1e-9, 1e9] in column " + data.wear_column + " (the fit uses its logarithm)");
    if (!(p.hardness >= 1e-9 && p.hardness <= 1e9))
      throw InputError(name, where, "an ore hardness in [1e-9, 1e9] in column hardness");
    p.start = t;
    t += p.length;
    p.rate = data.wear_column == "wear_rate" ? p.wear : p.wear / p.length;
    p.corrected_rate = p.rate;
    data.periods.push_back(p);
  }
  if (data.periods.size() < 3)
    throw InputError(name, "line " + std::to_string(d.row_line.empty() ? 2 : d.row_line.back() + 1),
                     "at least 3 periods (two fit parameters and one degree of freedom), found " +
                         std::to_string(data.periods.size()));
  // b is the slope against log hardness: values that differ in their tenth digit give a slope
  // of 1e10 and NaN for a; a tenth of a per cent is below any hardness test's resolution.
  double lo = data.periods.front().hardness, hi = lo;
  for (const auto& p : data.periods) {
    lo = std::min(lo, p.hardness);
    hi = std::max(hi, p.hardness);
  }
  if (!(hi >= lo * (1.0 + kMinHardnessSpread)))
    throw InputError(name, "column hardness",
                     "at least two hardness values 0.1% or more apart (b is fitted from their logarithms)");
  return data;
}

HardnessData read_hardness(const std::string& path) { return parse_hardness(io::read_file(path), path); }

HardnessFit fit_hardness(HardnessData& data, double reference_hardness) {
  auto& ps = data.periods;
  const int n = static_cast<int>(ps.size());
  if (reference_hardness > 0.0 && n > 0) {
    // CT = (H / H0)^b: an H0 far outside the data's hardness puts a = H0^-b past what a double
    // holds (a = 0 or inf, the corrected rates inf or NaN) without saying anything of the ore.
    double lo = ps[0].hardness, hi = ps[0].hardness;
    for (const auto& p : ps) {
      lo = std::min(lo, p.hardness);
      hi = std::max(hi, p.hardness);
    }
    if (!(reference_hardness >= lo / kReferenceHardnessSpan && reference_hardness <= hi * kReferenceHardnessSpan)) {
      char range[96];
      std::snprintf(range, sizeof range, "%.6g to %.6g", lo / kReferenceHardnessSpan, hi * kReferenceHardnessSpan);
      throw InputError(data.path, "--reference-hardness",
                       std::string("a hardness in the file's units within a factor of 1000 of its hardness values: ") +
                           range);
    }
  }
  Eigen::MatrixXd A(n, 2);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    A(i, 0) = 1.0;
    A(i, 1) = std::log(ps[i].hardness);
    y(i) = std::log(ps[i].rate);
  }
  const Eigen::Vector2d beta = A.colPivHouseholderQr().solve(y);
  const Eigen::VectorXd res = y - A * beta;
  const double rss = res.squaredNorm();
  const double dof = n - 2;
  const Eigen::Matrix2d cov = (rss / dof) * (A.transpose() * A).inverse();

  HardnessFit f;
  f.b = beta(1);
  f.b_se = std::sqrt(std::max(0.0, cov(1, 1)));
  const double ymean = y.mean();
  const double tss = (y.array() - ymean).square().sum();
  // Rates that do not vary leave nothing for the line to explain: no R^2 (NaN), not a
  // perfect one.
  f.r_squared = tss > 0.0 ? 1.0 - rss / tss : std::nan("");
  f.reference_hardness = reference_hardness;
  double dadb;
  if (reference_hardness > 0.0) {
    f.a = std::pow(reference_hardness, -f.b);
    dadb = -f.a * std::log(reference_hardness);
  } else {
    double st = 0.0, sth = 0.0, sthl = 0.0;
    for (const auto& p : ps) {
      const double w = p.length * std::pow(p.hardness, f.b);
      st += p.length;
      sth += w;
      sthl += w * std::log(p.hardness);
    }
    f.a = st / sth;
    dadb = -f.a * sthl / sth;
  }
  f.a_se = std::fabs(dadb) * f.b_se;
  std::vector<double> before, after;
  for (auto& p : ps) {
    p.ct = f.a * std::pow(p.hardness, f.b);
    p.corrected_rate = p.rate / p.ct;
    before.push_back(p.rate);
    after.push_back(p.corrected_rate);
  }
  f.cv_before = coefficient_of_variation(before);
  f.cv_after = coefficient_of_variation(after);
  // Wear rates orders of magnitude apart over hardness values a hair apart give an exponent
  // whose correction factor no double holds: the fit says nothing of the ore then.
  bool finite = std::isfinite(f.a) && f.a > 0.0 && std::isfinite(f.b) && std::isfinite(f.cv_after);
  for (const auto& p : ps) finite = finite && std::isfinite(p.ct) && p.ct > 0.0 && std::isfinite(p.corrected_rate);
  if (!finite) {
    double lo = ps[0].hardness, hi = lo, rlo = ps[0].rate, rhi = rlo;
    for (const auto& p : ps) {
      lo = std::min(lo, p.hardness);
      hi = std::max(hi, p.hardness);
      rlo = std::min(rlo, p.rate);
      rhi = std::max(rhi, p.rate);
    }
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "wear rates that a power of the hardness fits with a correction a double holds; the fitted "
                  "exponent b = %.3g (rates %.3g to %.3g over hardness %.6g to %.6g) puts it past that",
                  f.b, rlo, rhi, lo, hi);
    throw InputError(data.path, "column hardness", buf);
  }
  f.mean_rate = std::accumulate(before.begin(), before.end(), 0.0) / n;
  f.mean_corrected_rate = std::accumulate(after.begin(), after.end(), 0.0) / n;
  return f;
}

std::vector<std::string> write_hardness_outputs(const std::string& out, const HardnessData& data,
                                                const HardnessFit& fit) {
  io::CsvTable t({"period", "start", "end", "length", "hardness", "wear", "rate", "ct", "corrected_time",
                  "corrected_rate"});
  for (const auto& p : data.periods)
    t.add_row({p.label, p.start, p.start + p.length, p.length, p.hardness, p.wear, p.rate, p.ct, p.ct * p.length,
               p.corrected_rate});
  io::CsvTable ft({"a", "a_se", "b", "b_se", "reference_hardness", "cv_before", "cv_after", "mean_rate",
                   "mean_corrected_rate", "r_squared", "periods", "time_unit", "wear_column"});
  // No --reference-hardness: an empty cell, not a hardness of 0.
  const io::CsvCell reference = fit.reference_hardness > 0.0 ? io::CsvCell(fit.reference_hardness) : io::CsvCell("");
  // Rates that do not vary: no R^2, an empty cell.
  const io::CsvCell r_squared = std::isfinite(fit.r_squared) ? io::CsvCell(fit.r_squared) : io::CsvCell("");
  ft.add_row({fit.a, fit.a_se, fit.b, fit.b_se, reference, fit.cv_before, fit.cv_after, fit.mean_rate,
              fit.mean_corrected_rate, r_squared, static_cast<int>(data.periods.size()), data.time_unit,
              data.wear_column});
  const std::vector<std::string> files = {io::join_path(out, "hardness_periods.csv"),
                                          io::join_path(out, "hardness_fit.csv")};
  t.write(files[0]);
  ft.write(files[1]);
  return files;
}

std::vector<std::string> render_hardness_figure(const std::string& out, const HardnessData& data,
                                                const HardnessFit& fit) {
  io::ensure_dir(io::join_path(out, "plots"));
  char fit_text[160];
  std::snprintf(fit_text, sizeof fit_text, "CT = %.4g H^%.3g", fit.a, fit.b);
  char cv_before[32], cv_after[32];
  std::snprintf(cv_before, sizeof cv_before, "%.1f", 100.0 * fit.cv_before);
  std::snprintf(cv_after, sizeof cv_after, "%.1f", 100.0 * fit.cv_after);
  return plots::render_figure(plots::script_path("hardness"),
                              {{"periods", io::join_path(out, "hardness_periods.csv")},
                               {"outbase", io::join_path(out, "hardness")},
                               {"timeunit", data.time_unit},
                               {"wearunit", data.wear_column},
                               {"fit", fit_text},
                               {"cv_before", cv_before},
                               {"cv_after", cv_after}},
                              io::join_path(out, "plots/gnuplot.log"));
}

}  // namespace millwear::validation
