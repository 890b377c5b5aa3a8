// Figures with errors from a history's stage records, and the designs compared.
#include "study/design_estimates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/units.hpp"
#include "metrics/charge_summary.hpp"
#include "wear/life.hpp"

namespace millwear::study {

namespace {

Estimate scaled(const Estimate& e, double by) { return {e.mean * by, e.se * std::abs(by)}; }

// The estimate `value` with the relative error `rel` of another figure it follows.
Estimate with_rel_error(double value, double rel) { return {value, std::abs(value) * rel}; }

// The variances of the area and the height stage k removed on its way to the next stage's
// hours: recorded over its wear updates, or, from a record older than that, the stage's first
// rate's error over those hours, the height's in proportion to the area lost by the next stage.
struct StageVariance {
  double area_m4 = 0.0, height_m2 = 0.0;
};
StageVariance stage_variance(const LifterAtStage& stage, const LifterAtStage& next, double area0, double height0) {
  StageVariance v;
  if (std::isfinite(stage.worn_area_se_m2)) {
    v.area_m4 = stage.worn_area_se_m2 * stage.worn_area_se_m2;
  } else {
    const double s = stage.rate_m2_per_s * stage.rate_rel_sem * (next.hours - stage.hours) * kSecondsPerHour;
    v.area_m4 = s * s;
  }
  if (std::isfinite(stage.worn_height_se_m)) {
    v.height_m2 = stage.worn_height_se_m * stage.worn_height_se_m;
  } else {
    const double lost = area0 - next.area_m2;
    const double per_area = lost > 0.0 ? (height0 - next.height_m) / lost : 0.0;
    v.height_m2 = per_area * per_area * v.area_m4;
  }
  return v;
}

}  // namespace

double life_error_h(const std::vector<LifterAtStage>& at, double area0, double height0, double replacement_height_m) {
  std::vector<double> hours, height;
  for (const LifterAtStage& r : at) {
    hours.push_back(r.hours);
    height.push_back(r.height_m);
  }
  const LifeLine line = life_line(hours, height, replacement_height_m);
  if (at.empty() || !std::isfinite(line.hours)) return std::nan("");
  // At or under the replacement height from the first stage: the life is that stage's hours.
  if (line.a < 0) return 0.0;
  const LifterAtStage &a = at[static_cast<std::size_t>(line.a)], &b = at[static_cast<std::size_t>(line.b)];
  const double T = b.hours - a.hours, D = a.height_m - b.height_m;
  if (!(D > 0.0)) return std::nan("");
  // life = h_a + (H_a - H_r) T / D: its derivatives by the two heights.
  const double g_a = T * (replacement_height_m - b.height_m) / (D * D);
  const double g_b = T * (a.height_m - replacement_height_m) / (D * D);
  // H_b's error is H_a's plus that of the height removed between a and b: independent parts.
  double var_before = 0.0, var_between = 0.0;
  for (std::size_t k = 0; k < static_cast<std::size_t>(line.b); ++k) {
    const double v = stage_variance(at[k], at[k + 1], area0, height0).height_m2;
    (k < static_cast<std::size_t>(line.a) ? var_before : var_between) += v;
  }
  return std::sqrt((g_a + g_b) * (g_a + g_b) * var_before + g_b * g_b * var_between);
}

std::vector<KindEstimate> track_lifter(const std::vector<LifterAtStage>& at, double area0, double height0,
                                       double life_h, double replacement_height_m, Estimate& life) {
  std::vector<KindEstimate> out;
  StageVariance sum;
  for (std::size_t k = 0; k < at.size(); ++k) {
    const LifterAtStage& r = at[k];
    if (k > 0) {
      const StageVariance v = stage_variance(at[k - 1], r, area0, height0);
      sum.area_m4 += v.area_m4;
      sum.height_m2 += v.height_m2;
    }
    KindEstimate e;
    const double area_se = std::sqrt(sum.area_m4);
    e.area_m2 = {r.area_m2, area_se};
    e.area_loss_fraction = {1.0 - r.area_m2 / area0, area_se / area0};
    e.height_m = {r.height_m, std::sqrt(sum.height_m2)};
    e.area_loss_rate_m2_per_s = with_rel_error(r.rate_m2_per_s, r.rate_rel_sem);
    out.push_back(e);
  }
  life = Estimate{};
  if (std::isfinite(life_h)) life = {life_h, life_error_h(at, area0, height0, replacement_height_m)};
  return out;
}

namespace {

// A pattern's kinds, each tracked as the design's lifter is, from its own rates.
void add_kind_estimates(const std::map<int, StageRecord>& stages, double replacement_height_m,
                        const std::vector<double>& kind_life_h,
                        const std::vector<bool>& kind_life_extrapolated, DesignEstimate& d) {
  const auto own0 = stages.find(0);
  if (own0 == stages.end() || own0->second.kinds.size() < 2) return;
  const std::size_t kinds = own0->second.kinds.size();
  for (std::size_t i = 0; i < kinds; ++i) {
    std::vector<LifterAtStage> at;
    for (const auto& [k, r] : stages) {
      (void)k;
      const bool has = i < r.kinds.size();
      const double nan = std::nan("");
      at.push_back({r.hours, has ? r.kinds[i].area_m2 : nan, has ? r.kinds[i].height_m : nan,
                    i < r.kind_area_loss_rate_m2_per_s.size() ? r.kind_area_loss_rate_m2_per_s[i] : nan,
                    i < r.kind_area_loss_rate_rel_sem.size() ? r.kind_area_loss_rate_rel_sem[i] : nan,
                    i < r.kind_worn_se.size() ? r.kind_worn_se[i].area_m2 : nan,
                    i < r.kind_worn_se.size() ? r.kind_worn_se[i].height_m : nan});
    }
    Estimate life;
    const std::vector<KindEstimate> track =
        track_lifter(at, own0->second.kinds[i].area_m2, own0->second.kinds[i].height_m,
                     i < kind_life_h.size() ? kind_life_h[i] : std::nan(""), replacement_height_m, life);
    for (std::size_t k = 0; k < track.size(); ++k) d.stages[k].kinds.push_back(track[k]);
    d.kind_life_h.push_back(life);
    d.kind_life_extrapolated.push_back(i < kind_life_extrapolated.size() ? kind_life_extrapolated[i] : true);
  }
}

}  // namespace

DesignEstimate estimate_history(const std::string& name, const Scene& scene, const std::map<int, StageRecord>& stages,
                                double life_h, bool life_extrapolated, const std::vector<double>& kind_life_h,
                                const std::vector<bool>& kind_life_extrapolated) {
  DesignEstimate d;
  d.name = name;
  d.replicates = 1;
  d.source = ErrorSource::BatchMeans;
  d.life_extrapolated = life_extrapolated;
  const double len = scene.mill.length_m;
  const double per_mill = len / scene.slice_thickness();
  const auto own0 = stages.find(0);
  const double area0 = own0 != stages.end() ? own0->second.lifter.area_m2 : std::nan("");
  const double height0 = own0 != stages.end() ? own0->second.lifter.height_m : std::nan("");
  std::vector<LifterAtStage> at;
  for (const auto& [k, r] : stages) {
    (void)k;
    // A pattern's lifter is its first kind's: that kind's rate and error, not all lifters'.
    const bool kind0 = r.kinds.size() > 1 && !r.kind_area_loss_rate_m2_per_s.empty() &&
                       !r.kind_area_loss_rate_rel_sem.empty();
    at.push_back({r.hours, r.lifter.area_m2, r.lifter.height_m,
                  kind0 ? r.kind_area_loss_rate_m2_per_s[0] : r.area_loss_rate_m2_per_s,
                  kind0 ? r.kind_area_loss_rate_rel_sem[0] : r.area_loss_rate_rel_sem, r.worn_se.area_m2,
                  r.worn_se.height_m});
  }
  const std::vector<KindEstimate> lifter = track_lifter(at, area0, height0, life_h, scene.wear.replacement_height_m, d.life_h);
  std::size_t index = 0;
  for (const auto& [k, r] : stages) {
    StageEstimate s;
    s.stage = k;
    s.hours = r.hours;
    const KindEstimate& l = lifter[index++];
    s.area_m2 = l.area_m2;
    s.area_loss_fraction = l.area_loss_fraction;
    s.height_m = l.height_m;
    if (r.worn_out || r.charge.summary.escaped > 0) {
      // The lifter worn to the shell ends the history: its geometry is measured, but no
      // charge ran on it, so its charge figures are left unknown (NaN), not the last stage's.
      // So are those of a window that lost disks (which ends the history too): its liner is
      // real, its charge is not the scene's, and its power would be compared as a design's.
      d.stages.push_back(s);
      continue;
    }
    const ChargeFigures& f = r.charge;
    const ChargeFigureErrors& e = r.charge_errors;
    s.power_W = {f.power_kW_per_m * 1e3 * len, e.power_kW_per_m * 1e3 * len};
    s.collision_W = {f.collision_kW_per_m * 1e3 * len, e.collision_kW_per_m * 1e3 * len};
    s.liner_shear_W = {f.liner_shear_kW_per_m * 1e3 * len, e.liner_shear_kW_per_m * 1e3 * len};
    s.utilization = {f.power_kW_per_m != 0.0 ? f.collision_kW_per_m / f.power_kW_per_m : std::nan(""), e.utilization};
    s.charge_mass_kg = {f.summary.mass_kg * per_mill, e.mass_kg * per_mill};
    const MillEnergyFigures m = mill_energy_figures(f.summary, scene.slice_thickness(), len, r.liner_loss_rate_m2_per_s,
                                                    scene.wear.liner_density_kg_m3);
    const double power_rel = s.power_W.se / std::abs(s.power_W.mean);
    const double mass_rel = s.charge_mass_kg.se / s.charge_mass_kg.mean;
    s.specific_power_W_per_kg = with_rel_error(m.specific_power_W_per_kg, std::hypot(power_rel, mass_rel));
    // The liner's loss follows the lifter's shear power's error.
    s.liner_wear_kg_per_J = with_rel_error(m.liner_wear_kg_per_J, std::hypot(r.area_loss_rate_rel_sem, power_rel));
    s.centre_of_mass_deg = {f.summary.centre_of_mass_deg, e.centre_of_mass_deg};
    s.centrifuged = f.summary.centrifuged ? 1 : 0;
    if (!f.summary.centrifuged) {
      s.toe_deg = {f.summary.toe_deg, e.toe_deg};
      s.shoulder_deg = {f.summary.shoulder_deg, e.shoulder_deg};
    }
    s.packed_shear_share = {f.summary.packed_shear_share, e.packed_shear_share};
    d.stages.push_back(s);
  }
  add_kind_estimates(stages, scene.wear.replacement_height_m, kind_life_h, kind_life_extrapolated, d);
  // A pattern lasts as long as its shortest-lived kind (compute_life): that kind's life error.
  // A kind that never reaches the replacement height has no life (NaN) and cannot be it.
  if (d.kind_life_h.size() > 1 && std::isfinite(life_h)) {
    for (std::size_t i = 0; i < d.kind_life_h.size() && i < kind_life_h.size(); ++i)
      if (kind_life_h[i] == life_h) {
        d.life_h = d.kind_life_h[i];
        break;
      }
  }
  return d;
}

namespace {

struct Figure {
  const char* column;
  const char* unit;
  Estimate StageEstimate::*field;
  double scale;  // SI -> the file edge's unit
};

std::string number_text(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

std::string verdict_text(const Verdict& v) {
  const double d = v.difference.value;
  // A figure one of the two does not have: nothing to compare, rather than "by nan".
  if (!std::isfinite(d)) {
    if (v.figure == "life_h")
      return "life: " + v.design + " against " + v.reference +
             ": not compared (a life not known: no height trend down to the replacement height yet)";
    return v.figure + (v.stage >= 0 ? " at stage " + std::to_string(v.stage) : std::string()) + ": " + v.design +
           " against " + v.reference + ": not compared (not known for both)";
  }
  const std::string pm =
      number_text(std::abs(d)) + " +- " + number_text(v.difference.se) + (v.unit.empty() ? "" : " " + v.unit);
  std::string what;
  if (d == 0.0)  // the same figure to the last bit (the same history under two names)
    what = (v.figure == "life_h" ? std::string("life")
                                 : v.figure + (v.stage >= 0 ? " at stage " + std::to_string(v.stage) : std::string())) +
           ": " + v.design + " and " + v.reference + " are equal (0 +- " + number_text(v.difference.se) +
           (v.unit.empty() ? "" : " " + v.unit) + ")";
  else if (v.figure == "life_h")
    what = v.design + (d >= 0.0 ? " outlasts " : " wears out before ") + v.reference + " by " + pm;
  else
    what = v.figure + (v.stage >= 0 ? " at stage " + std::to_string(v.stage) : std::string()) + ": " + v.design +
           (d >= 0.0 ? " is higher than " : " is lower than ") + v.reference + " by " + pm;
  const char* errors = v.source == ErrorSource::Replicates ? "" : "; one history's batch-means errors";
  if (!std::isfinite(v.difference.se)) return what + " (no error known)";
  if (v.difference.resolved)
    return what + " (resolved: more than " + number_text(v.difference.threshold) + " combined standard errors" + errors + ")";
  std::string more = v.difference.replicates_needed > 0
                         ? "run more replicates (about " + std::to_string(v.difference.replicates_needed) +
                               " per design would resolve it)"
                         : "no difference to resolve";
  const std::string under = v.difference.threshold != kResolvedSigmas
                                ? ", under " + number_text(v.difference.threshold) + " combined standard errors"
                                : std::string();
  return what + " (not resolved" + under + ": " + more + errors + ")";
}

}  // namespace

std::vector<Verdict> compare_designs(const std::vector<DesignEstimate>& designs, const std::string& reference) {
  std::vector<Verdict> out;
  const auto ref = std::find_if(designs.begin(), designs.end(), [&](const DesignEstimate& d) { return d.name == reference; });
  if (ref == designs.end()) return out;
  const Figure at_new[] = {
      {"power_kw", "kW", &StageEstimate::power_W, 1e-3},
      {"specific_power_kw_per_t", "kW/t", &StageEstimate::specific_power_W_per_kg, kW_per_t(1.0)},
      {"collision_kw", "kW", &StageEstimate::collision_W, 1e-3},
      {"utilization", "", &StageEstimate::utilization, 1.0},
      {"liner_shear_kw", "kW", &StageEstimate::liner_shear_W, 1e-3},
      {"liner_wear_g_per_kwh", "g/kWh", &StageEstimate::liner_wear_kg_per_J, g_per_kWh(1.0)},
  };
  for (const DesignEstimate& d : designs) {
    if (d.name == reference) continue;
    const int replicates = std::min(d.replicates, ref->replicates);
    const ErrorSource source = d.source == ErrorSource::Replicates && ref->source == ErrorSource::Replicates
                                   ? ErrorSource::Replicates : ErrorSource::BatchMeans;
    auto add = [&](const char* figure, const char* unit, int stage, double hours, Estimate a, Estimate b) {
      Verdict v;
      v.figure = figure;
      v.unit = unit;
      v.stage = stage;
      v.hours = hours;
      v.design = d.name;
      v.reference = reference;
      v.value = a;
      v.reference_value = b;
      v.difference = compare(a, b, replicates, source);
      v.replicates = replicates;
      v.source = source;
      v.text = verdict_text(v);
      out.push_back(v);
    };
    add("life_h", "h", -1, 0.0, d.life_h, ref->life_h);
    // The area loss at the last worn stage both reached at the same hours (designs with other
    // stage hours are compared at a stage they share, or not at all).
    const std::size_t last = std::min(d.stages.size(), ref->stages.size());
    for (std::size_t k = last; k-- > 1;) {
      const StageEstimate& a = d.stages[k];
      const StageEstimate& b = ref->stages[k];
      if (std::abs(a.hours - b.hours) > 1e-9 * std::max(1.0, std::abs(b.hours))) continue;
      add("area_loss_pct", "%", a.stage, a.hours, scaled(a.area_loss_fraction, 100.0), scaled(b.area_loss_fraction, 100.0));
      break;
    }
    if (last > 0)
      for (const Figure& f : at_new)
        add(f.column, f.unit, 0, d.stages[0].hours, scaled(d.stages[0].*f.field, f.scale),
            scaled(ref->stages[0].*f.field, f.scale));
  }
  return out;
}

}  // namespace millwear::study
