#pragma once
// How many disks of each size the scene's filling asks for. The charge's solid area (the
// filling times the bulk packing, of the mill's area) goes to the ball and rock species in
// equal shares within each kind, and within a species to its sizes by mass fraction (area
// fraction in a slice of one density). Counts are whole disks: each size gets the whole
// part of its share, and then one more disk goes to each size in order of the largest
// remainders while the species' area left holds at least half of it. Each size is within one
// disk of its share, and the species' area within half its largest disk of its own, however
// many sizes hold less than a disk. The filling (engine/fill.cpp) places exactly these counts; the limits
// (scene/limits.hpp) bound them before anything is placed.
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace millwear {

// A rock size distribution given by its cumulative mass passing P(d):
//   Gates-Gaudin-Schuhmann  P(d) = (d / d_top)^m            (d <= d_top; 1 above)
//   Rosin-Rammler           P(d) = 1 - exp(-(d / d_63)^m)   (d_63: 63.2% passing)
// Each listed size stands for the class between the geometric means with its neighbours
// among the listed sizes; the largest class reaches up to every size (P = 1), the smallest
// down to its own size (what is finer is left out of the slice, as with a cut-off). The
// classes' masses, P(upper) - P(lower), normalised to sum to 1, are the mass fractions, in
// the order the sizes are given.
enum class SizeForm { GatesGaudinSchuhmann, RosinRammler };
// `held` (when given): the share of the distribution's mass the classes hold, before the
// normalising; `coarse` (when given): the share coarser than the largest size, which its
// class holds.
std::vector<double> distribution_mass_fractions(SizeForm form, const std::vector<double>& sizes_m,
                                                double scale_m, double exponent, double* held = nullptr,
                                                double* coarse = nullptr);

// Solid area (m^2 of the slice) species k of scene.species_as_placed() is to fill.
double species_area_m2(const Scene& scene, std::size_t k);

// Disks per size of a species with discrete sizes (same order as its diameters_m; sizes left
// out by the cut-off get 0). Empty for a species with a uniform size range.
std::vector<std::int64_t> disks_per_size(const Scene& scene, std::size_t k);

// The disks species k will get: exact for discrete sizes; for a uniform range, the share
// over the mean disk area (the draw stops within half a disk of the share).
double expected_disks(const Scene& scene, std::size_t k);
// Whether species k gets at least one disk: for discrete sizes, whole disks are placed; for a
// uniform range, whatever size the draw's first disk takes (its share holds half the largest).
bool species_gets_a_disk(const Scene& scene, std::size_t k);
// The disks of the whole charge: expected_disks summed over the species in use.
double expected_charge_disks(const Scene& scene);
// For each species in use (balls too) with a size distribution, what its classes hold of the
// distribution's mass: "charge.species[1] ('rock'): its classes hold 84.2% of its
// distribution's mass; the 15.8% finer than 25 mm goes to them"; with a size cut-off that
// leaves classes out (of a distribution or of listed sizes), what the classes it keeps hold
// and what is finer than them: "its classes from 112.5 mm (the size cut-off, 100 mm) hold
// 52.3% of ...; the 47.7% finer than 99.22 mm (the 112.5 mm class's lower edge) goes to
// them"; and the share coarser than the largest size, which its class holds, when there is
// any (a scale far above the sizes gives the largest class nearly all the mass). For --check.
std::vector<std::string> distribution_notes(const Scene& scene);

}  // namespace millwear
