// Archard's law per liner edge: shear work -> depth, and the wear rate C a scene asks for.
#include "wear/archard.hpp"

#include <algorithm>
#include <cmath>

#include "common/errors.hpp"
#include "common/units.hpp"

namespace millwear {

bool is_lifter_edge(const LinerUnit& u, int j) {
  const double mid_x = 0.5 * (u.surface[j].x + u.surface[j + 1].x);
  return std::fabs(mid_x) <= u.lifter_half_base_m + 1e-9;
}

std::vector<std::vector<double>> unit_edge_work(const MillGeometry& mill,
                                                const std::vector<double>& edge_work,
                                                bool average_rows) {
  const std::size_t kinds = static_cast<std::size_t>(mill.kinds);
  const bool shared = average_rows || mill.units.size() == kinds;
  const std::size_t n_units = shared ? kinds : static_cast<std::size_t>(mill.rows);
  std::vector<std::vector<double>> out(n_units);
  for (std::size_t u = 0; u < n_units; ++u)
    out[u].assign(static_cast<std::size_t>(mill.unit_edge_count(static_cast<int>(u))), 0.0);
  // Each kind has rows / kinds rows: the mean over them.
  const double scale = shared ? static_cast<double>(kinds) / mill.rows : 1.0;
  for (std::size_t e = 0; e < edge_work.size(); ++e) {
    const LinerEdgeInfo& info = mill.edges[e];
    const std::size_t u = shared ? static_cast<std::size_t>(info.row) % kinds : static_cast<std::size_t>(info.row);
    out[u][static_cast<std::size_t>(info.unit_edge)] += scale * edge_work[e];
  }
  return out;
}

std::vector<double> unit_edge_lengths(const LinerUnit& u, double radius_m) {
  std::vector<double> len(u.surface.size() - 1);
  for (std::size_t j = 0; j + 1 < u.surface.size(); ++j)
    len[j] = length(local_to_mill(u.surface[j + 1], 0, 1, radius_m) - local_to_mill(u.surface[j], 0, 1, radius_m));
  return len;
}

std::vector<double> edge_depths(const LinerUnit& unit, const std::vector<double>& work_J,
                                const std::vector<double>& len_m, double min_length_m, double thickness_m,
                                double rate_m3_per_J, bool shell_wear, double shell_rate_m3_per_J) {
  if (shell_rate_m3_per_J < 0.0) shell_rate_m3_per_J = rate_m3_per_J;
  const std::size_t n = len_m.size();
  std::vector<double> depth(n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    const bool lifter = is_lifter_edge(unit, static_cast<int>(j));
    if (!shell_wear && !lifter) continue;
    double work = work_J[j], len = len_m[j];
    for (std::size_t a = j, b = j; len < min_length_m && (a > 0 || b + 1 < n);) {
      if (a > 0) { --a; work += work_J[a]; len += len_m[a]; }
      if (len < min_length_m && b + 1 < n) { ++b; work += work_J[b]; len += len_m[b]; }
    }
    depth[j] = archard_depth_m(work, len, thickness_m, lifter ? rate_m3_per_J : shell_rate_m3_per_J);
  }
  return depth;
}

double shell_wear_rate(const Scene& scene, double c_real) {
  return scene.wear.shell_wear_rate_m3_per_J > 0.0 ? scene.wear.shell_wear_rate_m3_per_J : c_real;
}

double boundary_edge_wear_rate_m_per_s(const Scene& scene, const MillGeometry& mill, std::size_t e,
                                       double power_W, double thickness_m, double c_real) {
  if (mill.edges[e].owner != EdgeOwner::Shell)
    return archard_depth_m(power_W, mill.edge_length_m[e], thickness_m, c_real);
  if (!scene.wear.shell_wear) return 0.0;
  return archard_depth_m(power_W, mill.edge_length_m[e], thickness_m, shell_wear_rate(scene, c_real));
}

std::vector<std::vector<double>> archard_depths(const Scene& scene, const MillGeometry& mill,
                                                const std::vector<std::vector<double>>& unit_work,
                                                double c_real, double factor) {
  std::vector<std::vector<double>> depths(unit_work.size());
  const double t = scene.slice_thickness();
  // Half a lifter edge: the shortest edge whose own work is more signal than noise.
  const double min_length_m = 0.5 * scene.mill.mesh.lifter_edge_m;
  for (std::size_t u = 0; u < depths.size(); ++u)
    depths[u] = edge_depths(mill.units[u], unit_work[u], unit_edge_lengths(mill.units[u], mill.radius_m),
                            min_length_m, t, factor * c_real, scene.wear.shell_wear,
                            factor * shell_wear_rate(scene, c_real));
  return depths;
}

double deepest(const std::vector<std::vector<double>>& depths) {
  double m = 0.0;
  for (const auto& unit : depths)
    for (double d : unit) m = std::max(m, d);
  return m;
}

namespace {

// Shear power on a unit's lifter edges: all of them, or (top_only) those that reach the
// lifter's highest point.
double unit_lifter_power(const LinerUnit& unit, const std::vector<double>& power, bool top_only) {
  double top = -INFINITY;
  if (top_only)
    for (std::size_t j = 0; j < power.size(); ++j)
      if (is_lifter_edge(unit, static_cast<int>(j))) top = std::max({top, unit.surface[j].y, unit.surface[j + 1].y});
  double p = 0.0;
  for (std::size_t j = 0; j < power.size(); ++j)
    if (is_lifter_edge(unit, static_cast<int>(j)) &&
        (!top_only || std::max(unit.surface[j].y, unit.surface[j + 1].y) >= top))
      p += power[j];
  return p;
}

// Per row of each kind (unit u is of kind u % kinds).
std::vector<double> power_by_kind(const MillGeometry& mill, const std::vector<std::vector<double>>& unit_power,
                                  std::size_t kinds, bool top_only) {
  std::vector<double> sum(kinds, 0.0), count(kinds, 0.0);
  for (std::size_t u = 0; u < unit_power.size(); ++u) {
    sum[u % kinds] += unit_lifter_power(mill.units[u], unit_power[u], top_only);
    count[u % kinds] += 1.0;
  }
  for (std::size_t k = 0; k < kinds; ++k) sum[k] = count[k] > 0.0 ? sum[k] / count[k] : 0.0;
  return sum;
}

}  // namespace

double lifter_power_W(const MillGeometry& mill, const std::vector<std::vector<double>>& unit_power) {
  double sum = 0.0;
  for (std::size_t u = 0; u < unit_power.size(); ++u)
    for (std::size_t j = 0; j < unit_power[u].size(); ++j)
      if (is_lifter_edge(mill.units[u], static_cast<int>(j))) sum += unit_power[u][j];
  return sum / static_cast<double>(unit_power.size());
}

std::vector<double> kind_lifter_power_W(const MillGeometry& mill, const std::vector<std::vector<double>>& unit_power) {
  return power_by_kind(mill, unit_power, static_cast<std::size_t>(mill.kinds), false);
}

double lifter_top_power_W(const MillGeometry& mill, const std::vector<std::vector<double>>& unit_power) {
  return power_by_kind(mill, unit_power, 1, true).front();
}

std::vector<double> kind_lifter_top_power_W(const MillGeometry& mill,
                                            const std::vector<std::vector<double>>& unit_power) {
  return power_by_kind(mill, unit_power, static_cast<std::size_t>(mill.kinds), true);
}

double real_wear_rate(const Scene& scene, const MillGeometry& mill,
                      const std::vector<double>& shear_power_W) {
  const WearDef& w = scene.wear;
  if (w.rate_source == WearRateSource::Given) return w.wear_rate_m3_per_J;
  const auto unit_power = unit_edge_work(mill, shear_power_W, true);
  const LinerUnit& unit = mill.units[0];
  const double t = scene.slice_thickness();
  if (w.rate_source == WearRateSource::AreaLossRate) {
    // Area loss rate of the lifter = C * sum(P_e) / t over lifter edges.
    double p = 0.0;
    for (std::size_t j = 0; j < unit_power[0].size(); ++j)
      if (is_lifter_edge(unit, static_cast<int>(j))) p += unit_power[0][j];
    if (!(p > 0.0)) throw RunError("cannot calibrate the wear rate: no shear work on the lifter");
    return w.target_loss_rate * t / p;
  }
  // Height loss rate: depth rate at the lifter's top edges (within 10% of its height).
  const LifterMetrics m = measure_lifter(unit, mill.radius_m);
  const auto len = unit_edge_lengths(unit, mill.radius_m);
  double sum = 0.0, count = 0.0;
  for (std::size_t j = 0; j < len.size(); ++j) {
    const double y = 0.5 * (unit.surface[j].y + unit.surface[j + 1].y);
    if (!is_lifter_edge(unit, static_cast<int>(j)) || y < 0.9 * m.height_m) continue;
    sum += unit_power[0][j] / (len[j] * t);
    count += 1.0;
  }
  if (!(sum > 0.0)) throw RunError("cannot calibrate the wear rate: no shear work on the lifter top");
  return w.target_loss_rate / (sum / count);
}

}  // namespace millwear
