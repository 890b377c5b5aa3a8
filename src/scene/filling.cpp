// Disk counts of a filling (see filling.hpp).
#include "scene/filling.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "common/units.hpp"

namespace millwear {

std::vector<double> distribution_mass_fractions(SizeForm form, const std::vector<double>& sizes_m,
                                                double scale_m, double exponent, double* held,
                                                double* coarse) {
  auto passing = [&](double d) {
    if (form == SizeForm::GatesGaudinSchuhmann) return d >= scale_m ? 1.0 : std::pow(d / scale_m, exponent);
    return 1.0 - std::exp(-std::pow(d / scale_m, exponent));
  };
  std::vector<double> sorted = sizes_m;
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> out(sizes_m.size(), 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < sizes_m.size(); ++i) {
    const auto at = static_cast<std::size_t>(std::lower_bound(sorted.begin(), sorted.end(), sizes_m[i]) - sorted.begin());
    const double lower = at == 0 ? sorted[0] : std::sqrt(sorted[at - 1] * sorted[at]);
    const double upper_p = at + 1 == sorted.size() ? 1.0 : passing(std::sqrt(sorted[at] * sorted[at + 1]));
    out[i] = upper_p - passing(lower);
    total += out[i];
  }
  if (held) *held = total;
  if (coarse) *coarse = 1.0 - passing(sorted.back());
  for (double& f : out) f /= total;
  return out;
}

double species_area_m2(const Scene& scene, std::size_t k) {
  const ChargeDef& c = scene.charge;
  const double mill_area_m2 = kPi * scene.radius_m() * scene.radius_m();
  int balls = 0, rocks = 0;
  for (const auto& sp : c.species) (sp.is_ball ? balls : rocks)++;
  const bool ball = c.species[k].is_ball;
  const double kind_area = (ball ? c.ball_filling : c.filling - c.ball_filling) * mill_area_m2 * c.bulk_packing;
  return kind_area / std::max(ball ? balls : rocks, 1);
}

std::vector<std::int64_t> disks_per_size(const Scene& scene, std::size_t k) {
  const SpeciesDef sp = scene.species_as_placed()[k];  // the cut-off applied, fractions renormalised
  const SpeciesDef& given = scene.charge.species[k];
  std::vector<std::int64_t> count(given.diameters_m.size(), 0);
  if (given.diameters_m.empty() || sp.diameters_m.empty()) return count;
  const double area = species_area_m2(scene, k);
  // Real-valued counts of the sizes kept, in the order given, and their disks' areas.
  std::vector<double> exact(given.diameters_m.size(), 0.0), disk_m2(given.diameters_m.size(), 0.0);
  std::size_t kept = 0;
  for (std::size_t j = 0; j < given.diameters_m.size(); ++j) {
    if (kept == sp.diameters_m.size() || given.diameters_m[j] != sp.diameters_m[kept]) continue;
    const double d = sp.diameters_m[kept];
    disk_m2[j] = 0.25 * kPi * d * d;
    exact[j] = area * sp.mass_fractions[kept] / disk_m2[j];
    ++kept;
  }
  double left_m2 = area;
  for (std::size_t j = 0; j < exact.size(); ++j) {
    count[j] = static_cast<std::int64_t>(std::floor(exact[j]));
    left_m2 -= static_cast<double>(count[j]) * disk_m2[j];
  }
  // One more disk for the sizes of the largest remainders (ties to the earlier size), each
  // while the area left holds at least half of it: the species' area ends within half its
  // largest disk of its share, however many sizes hold less than a disk.
  std::vector<std::size_t> order(exact.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return exact[a] - std::floor(exact[a]) > exact[b] - std::floor(exact[b]);
  });
  for (std::size_t j : order)
    if (exact[j] > std::floor(exact[j]) && left_m2 >= 0.5 * disk_m2[j]) {
      ++count[j];
      left_m2 -= disk_m2[j];
    }
  return count;
}

double expected_disks(const Scene& scene, std::size_t k) {
  const SpeciesDef sp = scene.species_as_placed()[k];
  if (!sp.diameters_m.empty()) {
    const auto n = disks_per_size(scene, k);
    return static_cast<double>(std::accumulate(n.begin(), n.end(), std::int64_t{0}));
  }
  // Mean area of a disk whose diameter is uniform in [lo, hi]: pi/4 (lo^2 + lo hi + hi^2)/3.
  const double lo = sp.d_min_m, hi = sp.d_max_m;
  const double mean_area = 0.25 * kPi * (lo * lo + lo * hi + hi * hi) / 3.0;
  return species_area_m2(scene, k) / mean_area;
}

bool species_gets_a_disk(const Scene& scene, std::size_t k) {
  const SpeciesDef sp = scene.species_as_placed()[k];
  if (!sp.diameters_m.empty()) return expected_disks(scene, k) >= 1.0;
  // The draw stops before a disk whose half overfills the share (engine/fill.cpp): the first
  // disk is placed whatever it draws when the share holds half the largest.
  return species_area_m2(scene, k) >= 0.125 * kPi * sp.d_max_m * sp.d_max_m;
}

double expected_charge_disks(const Scene& scene) {
  const auto placed = scene.species_as_placed();
  double total = 0.0;
  for (std::size_t k = 0; k < placed.size(); ++k)
    if (scene.species_in_use(placed[k])) total += expected_disks(scene, k);
  return total;
}

namespace {

// A share as a per cent, to one decimal, or to three digits when it rounds to nothing there.
std::string per_cent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, 100.0 * share >= 0.05 ? "%.1f%%" : "%.3g%%", 100.0 * share);
  return buf;
}

// A size in mm to four digits: "48.41 mm".
std::string mm_text(double m) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.4g mm", in_mm(m));
  return buf;
}

}  // namespace

std::vector<std::string> distribution_notes(const Scene& scene) {
  std::vector<std::string> notes;
  const std::vector<SpeciesDef> placed = scene.species_as_placed();
  for (std::size_t k = 0; k < scene.charge.species.size(); ++k) {
    const SpeciesDef& sp = scene.charge.species[k];
    if (sp.diameters_m.empty() || !scene.species_in_use(placed[k])) continue;
    // What the classes the cut-off keeps hold of the classes' mass (all of it without one).
    double listed = 0.0, kept = 0.0;
    const std::vector<double>& kept_sizes = placed[k].diameters_m;
    for (std::size_t i = 0; i < sp.diameters_m.size(); ++i) {
      listed += sp.mass_fractions[i];
      if (std::find(kept_sizes.begin(), kept_sizes.end(), sp.diameters_m[i]) != kept_sizes.end())
        kept += sp.mass_fractions[i];
    }
    const bool distribution = sp.distribution_held > 0.0;
    const bool cut = kept < listed;
    if (!distribution && !cut) continue;
    const double held = (distribution ? sp.distribution_held : 1.0) * (listed > 0.0 ? kept / listed : 0.0);
    char from[96];
    if (cut)
      std::snprintf(from, sizeof from, "its classes from %.4g mm (the size cut-off, %.4g mm)",
                    in_mm(placed[k].smallest_diameter_m()), in_mm(scene.solver.size_cutoff_m));
    else
      std::snprintf(from, sizeof from, "its classes");
    // What is finer than the kept classes: for a distribution, below the smallest kept class's
    // lower edge (the geometric mean with the next listed size down, filling.hpp).
    const double smallest_kept = placed[k].smallest_diameter_m();
    double below = 0.0;
    for (double d : sp.diameters_m)
      if (d < smallest_kept) below = std::max(below, d);
    std::string finer = mm_text(smallest_kept);
    if (distribution && below > 0.0)
      finer = mm_text(std::sqrt(below * smallest_kept)) + " (the " + finer + " class's lower edge)";
    std::string note = "charge.species[" + std::to_string(k) + "] ('" + sp.name + "'): " + from + " hold " +
                       per_cent(held) + " of its " + (distribution ? "distribution's" : "listed") + " mass; the " +
                       per_cent(1.0 - held) + " finer than " + finer + " goes to them";
    if (distribution && sp.distribution_coarse >= 0.0005)
      note += "; the " + mm_text(sp.largest_diameter_m()) + " class also holds the " +
              per_cent(sp.distribution_coarse) + " coarser than its size";
    notes.push_back(note);
  }
  return notes;
}

}  // namespace millwear
