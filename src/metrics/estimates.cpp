// Means, standard errors and the verdict of a difference.
#include "metrics/estimates.hpp"

#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cmath>

namespace millwear {

Estimate mean_and_se(const std::vector<double>& values) {
  Estimate e;
  const auto n = static_cast<double>(values.size());
  if (values.empty()) return e;
  // Equal values (every replicate's new lifter): their mean and a zero error exactly, where
  // the sum's rounding would leave an error of 1e-12 that reads as a measured spread.
  if (std::all_of(values.begin(), values.end(), [&](double x) { return x == values.front(); })) {
    e.mean = values.front();
    if (values.size() >= 2) e.se = 0.0;
    return e;
  }
  double sum = 0.0;
  for (double x : values) sum += x;
  e.mean = sum / n;
  if (values.size() < 2) return e;
  double var = 0.0;
  for (double x : values) var += (x - e.mean) * (x - e.mean);
  e.se = std::sqrt(var / (n - 1.0) / n);
  return e;
}

const char* error_source_name(ErrorSource s) {
  return s == ErrorSource::Replicates ? "replicates" : "batch_means";
}

double resolved_threshold(double dof) {
  if (!(dof < 1e7)) return kResolvedSigmas;
  static const double level = 0.5 * std::erfc(-kResolvedSigmas / std::sqrt(2.0));  // Phi(2)
  return boost::math::quantile(boost::math::students_t(std::max(dof, 1.0)), level);
}

double welch_dof(double se_a, double se_b, int n) {
  const double va = se_a * se_a, vb = se_b * se_b;
  if (n < 2 || !(va + vb > 0.0)) return INFINITY;
  const double r = va / (va + vb);  // (va + vb)^2 / ((va^2 + vb^2) / (n - 1)), without underflow
  return (n - 1.0) / (r * r + (1.0 - r) * (1.0 - r));
}

Difference compare(const Estimate& a, const Estimate& b, int replicates, ErrorSource source) {
  Difference d;
  d.value = a.mean - b.mean;
  d.se = std::sqrt(a.se * a.se + b.se * b.se);
  if (!std::isfinite(d.value) || !std::isfinite(d.se)) return d;
  const bool spread = source == ErrorSource::Replicates && replicates > 1;
  const auto threshold_at = [&](int n) {
    return spread ? resolved_threshold(welch_dof(a.se, b.se, n)) : kResolvedSigmas;
  };
  d.threshold = threshold_at(replicates);
  d.resolved = std::abs(d.value) > d.threshold * d.se;
  if (d.resolved) {
    d.replicates_needed = 0;
    return d;
  }
  if (d.value == 0.0 || d.se == 0.0) return d;
  // With n histories per design the combined error is se_now * sqrt(replicates / n) (the
  // per-history spread kept): the smallest whole n past its own threshold. The normal count
  // is a lower bound (every threshold is at least kResolvedSigmas); from there upwards.
  const double per_history = d.se * std::sqrt(static_cast<double>(std::max(1, replicates)));
  const double ratio = kResolvedSigmas * per_history / std::abs(d.value);
  const double normal = ratio * ratio;
  if (!(normal < 1e6)) return d;  // -1: no count worth running
  for (int n = std::max(2, static_cast<int>(std::floor(normal)) + 1);; ++n) {
    // The count is run as replicates; scaling both errors alike keeps their ratio, so the
    // degrees of freedom at n follow from today's errors.
    const double t = resolved_threshold(welch_dof(a.se, b.se, n));
    if (std::abs(d.value) > t * per_history / std::sqrt(static_cast<double>(n))) {
      d.replicates_needed = n;
      return d;
    }
  }
}

namespace {

Estimate mean_of(const std::vector<DesignEstimate>& hs, std::size_t stage_index, Estimate StageEstimate::*field) {
  std::vector<double> x;
  for (const DesignEstimate& h : hs) {
    const double v = (h.stages[stage_index].*field).mean;
    if (std::isfinite(v)) x.push_back(v);
  }
  return mean_and_se(x);
}

}  // namespace

DesignEstimate combine_histories(const std::string& name, const std::vector<DesignEstimate>& histories) {
  DesignEstimate d;
  d.name = name;
  d.replicates = static_cast<int>(histories.size());
  d.source = ErrorSource::Replicates;
  if (histories.empty()) return d;
  std::size_t stages = histories.front().stages.size();
  for (const DesignEstimate& h : histories) stages = std::min(stages, h.stages.size());
  for (std::size_t k = 0; k < stages; ++k) {
    StageEstimate s;
    s.stage = histories.front().stages[k].stage;
    s.hours = histories.front().stages[k].hours;
    for (Estimate StageEstimate::*f :
         {&StageEstimate::area_m2, &StageEstimate::area_loss_fraction, &StageEstimate::height_m,
          &StageEstimate::power_W, &StageEstimate::collision_W, &StageEstimate::liner_shear_W,
          &StageEstimate::utilization, &StageEstimate::charge_mass_kg, &StageEstimate::specific_power_W_per_kg,
          &StageEstimate::liner_wear_kg_per_J, &StageEstimate::centre_of_mass_deg, &StageEstimate::toe_deg,
          &StageEstimate::shoulder_deg, &StageEstimate::packed_shear_share})
      s.*f = mean_of(histories, k, f);
    for (const DesignEstimate& h : histories) s.centrifuged += h.stages[k].centrifuged;
    std::size_t kinds = histories.front().stages[k].kinds.size();
    for (const DesignEstimate& h : histories) kinds = std::min(kinds, h.stages[k].kinds.size());
    for (std::size_t i = 0; i < kinds; ++i) {
      KindEstimate e;
      for (Estimate KindEstimate::*f : {&KindEstimate::area_m2, &KindEstimate::area_loss_fraction,
                                        &KindEstimate::height_m, &KindEstimate::area_loss_rate_m2_per_s}) {
        std::vector<double> x;
        for (const DesignEstimate& h : histories) {
          const double v = (h.stages[k].kinds[i].*f).mean;
          if (std::isfinite(v)) x.push_back(v);
        }
        e.*f = mean_and_se(x);
      }
      s.kinds.push_back(e);
    }
    d.stages.push_back(s);
  }
  std::size_t kinds = histories.front().kind_life_h.size();
  for (const DesignEstimate& h : histories) kinds = std::min(kinds, h.kind_life_h.size());
  for (std::size_t i = 0; i < kinds; ++i) {
    std::vector<double> x;
    bool extrapolated = false;
    for (const DesignEstimate& h : histories) {
      if (std::isfinite(h.kind_life_h[i].mean)) x.push_back(h.kind_life_h[i].mean);
      extrapolated = extrapolated || (i < h.kind_life_extrapolated.size() ? h.kind_life_extrapolated[i] : true);
    }
    d.kind_life_h.push_back(x.size() == histories.size() ? mean_and_se(x) : Estimate{std::nan(""), std::nan("")});
    d.kind_life_extrapolated.push_back(extrapolated);
  }
  std::vector<double> life;
  d.life_extrapolated = false;
  for (const DesignEstimate& h : histories) {
    if (std::isfinite(h.life_h.mean)) life.push_back(h.life_h.mean);
    d.life_extrapolated = d.life_extrapolated || h.life_extrapolated;
  }
  // A life is known only when every history has one.
  if (life.size() == histories.size()) d.life_h = mean_and_se(life);
  return d;
}

}  // namespace millwear
