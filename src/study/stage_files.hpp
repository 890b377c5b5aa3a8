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
//   .start.csv     the same columns: the charge the stage started from, when it was carried
//                  over from the stage before (not filled afresh)
// then the done marker OUT/stages/DESIGN_stageK.done (io/run_folder.hpp), written last, with
// each file's content hash (hash.EXT=, io/hash.hpp): read_stage_state refuses a file that no
// longer matches it.
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "wear/wear.hpp"

namespace millwear::study {

// Writes every state file of the stage, then its done marker. Throws RunError.
void write_stage_state(const std::string& out, const std::string& design, const StageRecord& rec);
// Reads stage K back. Throws InputError naming the file if anything is missing or bad.
StageRecord read_stage_state(const std::string& out, const std::string& design, int stage);
// A command that draws on a finished run (validate --from, animate --history) with a scene:
// throws InputError(run, option, ...) unless stage `rec` of the run is of this scene's mill,
// one liner unit per lifter kind (one per row when the rows wear on their own,
// wear.average_rows = false), each one pitch (2 pi R / rows) wide. A run of another mill
// or row count under the same design name is refused, not drawn on.
void check_stage_of_scene(const StageRecord& rec, const Scene& scene, const std::string& run,
                          const std::string& option);
// The state files and marker of stage K of a design that are on disk (paths under OUT).
std::vector<std::string> stage_state_files(const std::string& out, const std::string& design, int stage);
// Every file stage K of a design writes (state files, marker, stage profile), relative to OUT.
std::vector<std::string> stage_file_names(const std::string& design, int stage);
// Whether a file name in OUT/stages is one of a design's stage state files or markers
// (DESIGN_stageN followed by one of their extensions); a user's other file there is not.
bool is_stage_state_name(const std::string& name, const std::string& design);
// Whether a file name in OUT/profiles is one of a design's stage profiles (DESIGN_stageN.csv).
bool is_stage_profile_name(const std::string& name, const std::string& design);
// Deletes the state files and marker of every stage of a design (a fresh run), and its
// stage profiles; other files in those folders stay.
void remove_stage_state(const std::string& out, const std::string& design);

// The lifter part of a liner unit: points with |x| <= kProfileMargin * lifter half base.
constexpr double kProfileMargin = 1.25;
// OUT/profiles/DESIGN_stageK.csv: x_mm,y_mm (lifter-local, unit of row 0).
void write_profile_csv(const std::string& out, const std::string& design, const StageRecord& rec);
// The text write_profile_csv writes.
std::string profile_csv_text(const StageRecord& rec);
// A charge snapshot as CSV: x_m,y_m,radius_m,species,species_name,ball (active disks, in the
// frame the state is in). species indexes `species` (the scene's charge.species).
void write_snapshot_table(const std::string& path, const ChargeState& state,
                          const std::vector<SpeciesDef>& species);
// The marks a snapshot figure draws: where the charge's toe and shoulder are, its centre of
// mass, and which way the mill turns (+1 counter-clockwise, -1 clockwise, 0 at rest).
struct SnapshotMarks {
  double toe_deg = 0.0, shoulder_deg = 0.0;  // from 6 o'clock, + toward the rising side
  bool centrifuged = false;
  Vec2 centre_of_mass_m;
  int turning = 0;
};
SnapshotMarks snapshot_marks(const ChargeSummary& summary, double mill_speed_rad_s);
// A mill's boundary edges as CSV: edge,owner,x1_m,y1_m,x2_m,y2_m,VALUE,stage,hours,
// mill_angle_rad,toe_deg,shoulder_deg,centrifuged,com_x_m,com_y_m,turning; the edges in the
// world frame at mill_angle_rad, VALUE (named value_column) per edge (NaN past its end).
void write_liner_table(const std::string& path, const MillGeometry& mill, double mill_angle_rad,
                       const std::string& value_column, const std::vector<double>& value_per_edge,
                       int stage, double hours, const SnapshotMarks& marks);
// OUT/snapshot_DESIGN.csv: write_snapshot_table of the stage's snapshot (world frame).
void write_snapshot_csv(const std::string& out, const std::string& design, const Scene& scene,
                        const StageRecord& rec);
// OUT/liner_DESIGN.csv: write_liner_table of the stage's liner at the snapshot's mill angle,
// VALUE wear_rate_mm_per_1000h.
void write_liner_csv(const std::string& out, const std::string& design, const Scene& scene,
                     const StageRecord& rec);

}  // namespace millwear::study
