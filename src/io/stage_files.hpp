#pragma once
// The files of a `millwear run` folder that belong to one design and stage: the exact
// stage state a resumed run reads back, and the readable outputs (profile, snapshot,
// liner) the figures use. Shared by `run` (writes, reads on --resume) and `animate`
// (reads a finished run's stages).
//
// Stage state, OUT/stages/DESIGN_stageK.* (every double %.17g, so strtod returns the same
// bits and a resumed run continues from exactly the same numbers):
//   .record        key=value: stage, hours, the unit count and half bases, lifter metrics,
//                  charge figures, rates, mill angle, timings, disk count, worn_out
//   .units.csv     unit,x_m,y_m            liner unit surfaces, lifter-local, m
//   .spectrum.csv  bin,count_per_s,energy_W
//   .edges.csv     edge,wear_rate_m_per_s  per mill boundary edge (m per operating second)
//   .charge.csv    x_m,y_m,vx_m_s,vy_m_s,angle_rad,spin_rad_s,radius_m,mass_kg,species,active
// then the done marker OUT/stages/DESIGN_stageK.done (io/run_folder.hpp), written last.
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "wear/wear.hpp"

namespace millwear::io {

// Writes every state file of the stage, then its done marker. Throws RunError.
void write_stage_state(const std::string& out, const std::string& design, const StageRecord& rec);
// Reads stage K back. Throws InputError naming the file if anything is missing or bad.
StageRecord read_stage_state(const std::string& out, const std::string& design, int stage);
// The state files and marker of stage K of a design that are on disk (paths under OUT).
std::vector<std::string> stage_state_files(const std::string& out, const std::string& design, int stage);
// Deletes the state files and marker of every stage of a design (a fresh run).
void remove_stage_state(const std::string& out, const std::string& design);

// The lifter part of a liner unit: points with |x| <= kProfileMargin * lifter half base.
constexpr double kProfileMargin = 1.25;
// OUT/profiles/DESIGN_stageK.csv: x_mm,y_mm (lifter-local, unit of row 0).
void write_profile_csv(const std::string& out, const std::string& design, const StageRecord& rec);
// OUT/snapshot_DESIGN.csv: x_m,y_m,radius_m,species,species_name (active disks, world).
void write_snapshot_csv(const std::string& out, const std::string& design, const Scene& scene,
                        const StageRecord& rec);
// OUT/liner_DESIGN.csv: edge,owner,x1_m,y1_m,x2_m,y2_m,wear_rate_mm_per_1000h,stage,hours,
// mill_angle_rad. Segments in the world frame at the snapshot's mill angle.
void write_liner_csv(const std::string& out, const std::string& design, const Scene& scene,
                     const StageRecord& rec);

}  // namespace millwear::io
