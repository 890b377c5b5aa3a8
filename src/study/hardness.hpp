#pragma once
// The ore-hardness correction of operating time (the paper's Figs. 1 to 3): measured
// lifter wear rates differ from period to period; with a corrected operating time
// CT x t, CT = a * H^b, the corrected wear rates W / (CT t) become about constant, which is
// what Archard's law with a constant C predicts.
//
// Hardness file format (CSV, '#' comment lines allowed, one row per operating period, in
// time order; periods follow one another from time 0):
//   period,days,area_loss_mm2,hardness
//   1,54,950.2,14.1
//   ...
// - period: optional label (any text).
// - length: exactly one of the columns `days` or `hours` (> 0).
// - wear: exactly one of `area_loss_mm2` (lifter cross-section lost in the period),
//   `mass_loss_kg`, `height_loss_mm`, or `wear_rate` (already per day or per hour, in the
//   length column's unit; any wear unit). Must be > 0 (the fit is on logarithms).
// - hardness: ore hardness in any consistent unit (Bond work index, A*b, ...; > 0).
// Extra columns are ignored. At least 3 periods and two different hardness values.
// Errors throw InputError naming the file and line.
//
// Fit. The wear rate of period i is r_i = W_i / t_i. Archard with the corrected time says
// r_i = R * a * H_i^b for one constant R, so log r_i = log(R a) + b log H_i: an ordinary
// least-squares line (Eigen, QR) in log-log makes the corrected rates r_i / (a H_i^b) as
// constant as the data allow (least squares in their logarithms). Only the product R a is
// identified by wear data; a is fixed by a normalisation:
//   default         a such that sum a H_i^b t_i = sum t_i (the corrected total time equals
//                   the actual total time, so the corrected rate is the record's average);
//   reference H0    a = H0^(-b) (CT = 1 at hardness H0).
// Standard errors: b from the regression's covariance; a from b's by propagation through
// the normalisation. Coefficient of variation: sample standard deviation / mean of the rates
// (each period counts once), before and after the correction.
#include <string>
#include <vector>

namespace millwear::validation {

struct HardnessPeriod {
  std::string label;
  std::size_t line = 0;        // 1-based line in the file
  double start = 0.0;          // in time_unit, cumulative from 0
  double length = 0.0;         // in time_unit
  double wear = 0.0;           // in wear_unit (the amount lost, or the rate as given)
  double hardness = 0.0;
  double rate = 0.0;           // wear per time_unit
  double ct = 1.0;             // correction factor a H^b (after fit_hardness)
  double corrected_rate = 0.0; // rate / ct
};

struct HardnessData {
  std::string path;
  std::string time_unit;       // "days" or "hours"
  std::string wear_column;     // area_loss_mm2 | mass_loss_kg | height_loss_mm | wear_rate
  std::vector<HardnessPeriod> periods;
};

HardnessData parse_hardness(const std::string& text, const std::string& name);
HardnessData read_hardness(const std::string& path);

// How far outside the file's hardness values --reference-hardness may lie (a factor).
constexpr double kReferenceHardnessSpan = 1000.0;

struct HardnessFit {
  double a = 1.0, b = 0.0;
  double a_se = 0.0, b_se = 0.0;
  double reference_hardness = 0.0;   // 0: default normalisation (total corrected time)
  double cv_before = 0.0, cv_after = 0.0;
  double mean_rate = 0.0, mean_corrected_rate = 0.0;
  double r_squared = 0.0;            // of the log-log line; NaN where the rates do not vary
};

// Fits CT = a H^b and fills every period's ct and corrected_rate. reference_hardness > 0
// selects the a = H0^-b normalisation.
HardnessFit fit_hardness(HardnessData& data, double reference_hardness = 0.0);

// Sample coefficient of variation (standard deviation with n - 1, over the mean).
double coefficient_of_variation(const std::vector<double>& v);

// Written atomically into OUT (times in the file's unit, days or hours):
//   hardness_periods.csv   period,start,end,length,hardness,wear,rate,ct,corrected_time,
//                          corrected_rate
//   hardness_fit.csv       a,a_se,b,b_se,reference_hardness,cv_before,cv_after,mean_rate,
//                          mean_corrected_rate,r_squared,periods,time_unit,wear_column
// Returns the files.
std::vector<std::string> write_hardness_outputs(const std::string& out, const HardnessData& data,
                                                const HardnessFit& fit);
// OUT/hardness.{png,svg} from OUT/hardness_periods.csv: the rate per period before the
// correction, the ore hardness, the rate after. Returns the files; throws RunError when
// gnuplot is missing or fails (plots/plots.hpp).
std::vector<std::string> render_hardness_figure(const std::string& out, const HardnessData& data,
                                                const HardnessFit& fit);

}  // namespace millwear::validation
