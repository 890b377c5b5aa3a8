// A run's plan from scene and comparison files.
#include "study/plan.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "engine/engine.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/hash.hpp"
#include "io/run_folder.hpp"
#include "scene/fidelity.hpp"
#include "study/run_outputs.hpp"
#include "study/stage_files.hpp"
#include "wear/history.hpp"
#include "wear/reshape.hpp"

namespace millwear::study {

namespace fs = std::filesystem;

namespace {

// Whether two charges hold the same disks (radius, species and mass, in any order). The
// masses within a millionth: the library backend hands its bodies' masses back in single
// precision.
bool same_disks(const ChargeState& a, const ChargeState& b) {
  if (a.size() != b.size()) return false;
  using Disk = std::tuple<double, int, double>;
  const auto disks = [](const ChargeState& c) {
    std::vector<Disk> d;
    d.reserve(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) d.emplace_back(c.radius_m[i], c.species[i], c.mass_kg[i]);
    std::sort(d.begin(), d.end());
    return d;
  };
  const std::vector<Disk> da = disks(a), db = disks(b);
  for (std::size_t i = 0; i < da.size(); ++i) {
    const auto& [ra, sa, ma] = da[i];
    const auto& [rb, sb, mb] = db[i];
    if (ra != rb || sa != sb || !(std::abs(ma - mb) <= 1e-6 * std::max(std::abs(ma), std::abs(mb)))) return false;
  }
  return true;
}

// The mill of a stage's record: its liner units in the scene's mill.
MillGeometry stage_mill(const Scene& scene, const StageRecord& rec) {
  return build_mill(scene.radius_m(), scene.mill.rows, rec.units, scene.mill.kind_count());
}

// A profile's file and every profile file it read (match_area_of), in reading order, each
// once in `files`.
void add_profile_files(const LifterProfile& p, std::vector<std::string>& files) {
  if (p.source_file.empty()) return;  // built in code
  const auto add = [&files](const std::string& f) {
    if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
  };
  add(p.source_file);
  for (const std::string& f : p.referenced_files) add(f);
}

void add_design(Plan& plan, const std::string& scene_file, const std::string& fidelity_override,
                const std::vector<std::string>& overrides) {
  Scene scene = load_checked_scene(scene_file, overrides, fidelity_override);
  for (const auto& d : plan.designs) {
    if (d.name != scene.name) continue;
    // One file given twice (q.toml and ./q.toml) is one design run twice, not a name clash.
    std::error_code ec;
    if (std::filesystem::equivalent(d.scene.source_file, scene_file, ec))
      throw InputError(scene_file, "",
                       "each scene once; this is " + d.scene.source_file + " again (the same design twice would "
                       "run the same history: --replicates N runs more seeds of it)");
    throw InputError(scene_file, "name",
                     "a design name different from that of " + d.scene.source_file + " ('" +
                         scene.name + "'): each design names its output files");
  }
  DesignInput d;
  d.name = scene.name;
  d.design = scene.name;
  d.files.push_back(scene_file);
  for (int k = 0; k < scene.mill.kind_count(); ++k) add_profile_files(scene.mill.kind(k), d.files);
  // (scene_input_files, with the file as given rather than as the scene records it)
  std::string all = scene.fidelity;
  for (const auto& o : overrides) all += "\n--set " + o;  // a resumed run needs the same overrides
  for (const auto& f : d.files) all += "\n--\n" + io::read_file(f);
  d.fingerprint = io::stable_hash_hex(all);
  d.scene = std::move(scene);
  plan.designs.push_back(std::move(d));
}

// Returns the comparison table if the file is a comparison file, else nullopt (a scene,
// or a file load_scene will reject with a better message).
std::optional<toml::table> comparison_table(const std::string& path) {
  try {
    toml::table t = toml::parse_file(path);
    if (t.contains("comparison")) return t;
  } catch (const toml::parse_error&) {
  }
  return std::nullopt;
}

void add_comparison(Plan& plan, const std::string& file, const toml::table& root,
                    const std::string& fidelity_override, const std::vector<std::string>& overrides,
                    std::string& reference) {
  for (const auto& [k, v] : root)
    if (k.str() != "comparison")
      throw InputError(file, std::string(k.str()),
                       "only a [comparison] table in a comparison file (designs, reference, "
                       "name, description)");
  const toml::table* c = root["comparison"].as_table();
  if (!c) throw InputError(file, "comparison", "a table: [comparison] with designs = [...]");
  const std::set<std::string> allowed{"designs", "reference", "name", "description"};
  for (const auto& [k, v] : *c)
    if (!allowed.count(std::string(k.str())))
      throw InputError(file, "comparison." + std::string(k.str()),
                       "one of designs, reference, name, description");
  for (const char* key : {"name", "description"})
    if (c->contains(key) && !(*c)[key].is_string())
      throw InputError(file, std::string("comparison.") + key, "a string");
  const toml::array* designs = (*c)["designs"].as_array();
  if (!designs)
    throw InputError(file, "comparison.designs",
                     "an array of scene files, relative to this file, e.g. designs = "
                     "[\"sag-2x30.toml\", \"sag-1x30.toml\"]");
  if (designs->empty())
    throw InputError(file, "comparison.designs", "at least one scene file");
  const fs::path dir = fs::path(file).parent_path();
  const std::size_t first = plan.designs.size();
  for (std::size_t i = 0; i < designs->size(); ++i) {
    const std::string key = "comparison.designs[" + std::to_string(i) + "]";
    auto rel = (*designs)[i].value<std::string>();
    if (!rel || rel->empty()) throw InputError(file, key, "a scene file name (a string)");
    const std::string path = (dir / *rel).lexically_normal().string();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      throw InputError(file, key, "an existing scene file, relative to the comparison file; tried '" + path + "'");
    if (comparison_table(path))
      throw InputError(file, key, "a scene file, not another comparison file ('" + path + "')");
    add_design(plan, path, fidelity_override, overrides);
  }
  if (c->contains("reference")) {
    auto ref = (*c)["reference"].value<std::string>();
    if (!ref) throw InputError(file, "comparison.reference", "a design name (a string)");
    bool found = false;
    std::string names;
    for (std::size_t i = first; i < plan.designs.size(); ++i) {
      found = found || plan.designs[i].name == *ref;
      names += (names.empty() ? "" : ", ") + plan.designs[i].name;
    }
    if (!found)
      throw InputError(file, "comparison.reference",
                       "the name of one of its designs (" + names + "), found '" + *ref + "'");
    if (reference.empty()) reference = *ref;
  }
  plan.comparison_files.push_back(file);
}

// Each design followed by its replicates 2..n (seeds s+1 .. s+n-1, named DESIGN.rK).
void add_replicates(Plan& plan, int n) {
  std::vector<DesignInput> all;
  std::set<std::string> names;
  for (const auto& d : plan.designs) names.insert(d.name);
  for (auto& d : plan.designs) {
    check_derived_seeds(d.scene, static_cast<std::uint64_t>(n), "--replicates " + std::to_string(n));
    const DesignInput first = d;
    all.push_back(std::move(d));
    for (int k = 2; k <= n; ++k) {
      DesignInput r = first;
      r.replicate = k;
      r.name = first.design + ".r" + std::to_string(k);
      if (!names.insert(r.name).second)
        throw InputError(first.files.front(), "name",
                         "a design name that does not clash with the replicate names (" + r.name + " is both)");
      r.scene.solver.seed = first.scene.solver.seed + static_cast<std::uint64_t>(k - 1);
      r.fingerprint = io::stable_hash_hex(first.fingerprint + "\n--replicate " + std::to_string(k));
      all.push_back(std::move(r));
    }
  }
  plan.designs = std::move(all);
  plan.replicates = n;
}

}  // namespace

std::vector<std::string> scene_input_files(const Scene& scene) {
  std::vector<std::string> files{scene.source_file};
  for (int k = 0; k < scene.mill.kind_count(); ++k) add_profile_files(scene.mill.kind(k), files);
  return files;
}

// --continue: each design's stage in RUN, its hours and what changed since.
void continue_designs(Plan& plan, const PlanArgs& args) {
  const std::string& run = args.continue_from;
  std::error_code ec;
  if (!fs::is_directory(run, ec) || !io::file_exists(io::manifest_path(run)))
    throw InputError(run, "--continue", "a run folder of `millwear run` (with manifest.json)");
  if (!args.out.empty()) {
    // OUT may not be RUN, nor a folder inside it, which the run's own files would then hold.
    const fs::path r = fs::weakly_canonical(run, ec), o = fs::weakly_canonical(args.out, ec);
    const auto mismatch = std::mismatch(r.begin(), r.end(), o.begin(), o.end());
    if (!r.empty() && mismatch.first == r.end())
      throw InputError(args.out, "-o", "an output folder other than the run it continues (" + run + ") and outside it");
  }
  if (const std::string holder = io::folder_holder(run); !holder.empty())
    throw InputError(run, "--continue", "a run no process is writing, but " + holder +
                                            " holds its lock; wait for it to end");
  for (DesignInput& d : plan.designs) {
    const int last = io::last_finished_stage(run, d.name);
    if (last < 0 && d.replicate > 1)  // the run had fewer replicates: say so, not a name
      throw InputError(run, "--continue",
                       "a run with replicate " + std::to_string(d.replicate) + " of design '" + d.design +
                           "' (--replicates " + std::to_string(plan.replicates) + "), but it holds no finished "
                           "stage of '" + d.name + "': continue it with --replicates at most the run's");
    if (last < 0)
      throw InputError(run, "--continue", "finished stages of design '" + d.name + "' (the scene's name)");
    const int k = args.continue_stage >= 0 ? args.continue_stage : last;
    if (k > last)
      throw InputError(run, "--stage", "a stage of design '" + d.name + "' finished in the run (0 to " +
                                           std::to_string(last) + "), got " + std::to_string(k));
    if (k >= d.scene.wear.stages)
      throw InputError(d.files.front(), "wear.stages",
                       "more stages than the one the run continues from (" + std::to_string(k) +
                           "): the continued run goes on to the scene's last stage, so give it more stages, e.g. "
                           "--set wear.stages=" + std::to_string(k + d.scene.wear.stages));
    d.continue_run = run;
    d.continue_stage = k;
    const StageRecord from = study::read_stage_state(run, d.name, k);
    d.continue_hours = from.hours;
    // The run's stage k sets the clock: a start of the scene's own other than the run's would
    // be overwritten without a word.
    for (const std::string& change : study::settings_changes(run, d.name, d.scene))
      if (change.rfind("wear.start_hours: ", 0) == 0)
        throw InputError(d.files.front(), "lifters.start_hours",
                         "the start of the run it continues or none (" + run + " -> the scene: " +
                             change.substr(std::strlen("wear.start_hours: ")) + " h): --continue goes on from stage " +
                             std::to_string(k) + " at " + io::format_number(from.hours) +
                             " h as the run recorded them, so the run's stages set the clock");
    // Stage k at the hours RUN recorded: stage j is then at start + j * stage_hours.
    d.scene.wear.start_hours = d.continue_hours - k * d.scene.wear.stage_hours;
    d.changes = study::settings_changes(run, d.name, d.scene);
    // That start follows from the run's clock and the stage length (checked above against the
    // scene's own): not a change the scene made, though other stage hours move it.
    d.changes.erase(std::remove_if(d.changes.begin(), d.changes.end(),
                                   [](const std::string& c) { return c.rfind("wear.start_hours: ", 0) == 0; }),
                    d.changes.end());
    // A run of more histories per design than this continuation takes on: the rows copied and
    // continued are the first ones' alone, not the run's mean over its histories.
    int run_replicates = 1;
    while (d.replicate == 1 && io::last_finished_stage(run, d.design + ".r" + std::to_string(run_replicates + 1)) >= 0)
      ++run_replicates;
    if (run_replicates > plan.replicates)
      d.changes.push_back("replicates: " + std::to_string(run_replicates) + " histories of '" + d.design + "' in the run -> " +
                          std::to_string(plan.replicates) + " continued (its rows are the first " +
                          (plan.replicates == 1 ? std::string("history's") : std::to_string(plan.replicates) + "'s") +
                          ", not the run's mean over " + std::to_string(run_replicates) + "; --replicates " +
                          std::to_string(run_replicates) + " continues them all)");
    // The liner goes on from the run's stage as it is: a mill of another size or other lifters
    // would wear a liner that does not fit it. Nor may the mill's length, the slice's
    // thickness or the liner's density change: the copied stages' figures per mill and their
    // liner wear in g/kWh are worked out from them, and would change with them.
    // (The manifest's name of the setting, the scene's key, and a hint.)
    struct Fixed {
      const char* setting;
      const char* key;
      const char* hint;
    };
    // The lifters are the scene's own key, profile or pattern: a pattern's first kind is also
    // the manifest's lifter_profile, so kinds given in another order change that too.
    const char* lifters_key = d.scene.mill.pattern.empty() ? "lifters.profile" : "lifters.pattern";
    const Fixed fixed[] = {
        {"mill.diameter_m: ", "mill.diameter", ""},
        {"mill.length_m: ", "mill.length", ""},
        {"mill.slice_thickness_m: ", "mill.slice_thickness",
         " (without mill.slice_thickness the slice is the largest rock's diameter: give the run's)"},
        {"mill.rows: ", "lifters.rows", ""},
        {"mill.lifter_profile: ", lifters_key, ""},
        {"mill.lifter_shape: ", lifters_key, ""},
        {"mill.lifter_pattern: ", lifters_key, ""},
        {"wear.liner_density_kg_m3: ", "wear.liner_density", ""}};
    for (const std::string& change : d.changes)
      for (const Fixed& f : fixed)
        if (change.rfind(f.setting, 0) == 0)
          throw InputError(d.files.front(), f.key,
                           "the mill of the run it continues (" + run + ": " + change.substr(std::strlen(f.setting)) +
                               ")" + f.hint + ": --continue goes on with that liner under new conditions (speed, "
                               "filling, wear rate); another mill, slice or liner is a new run");
    // A lifter at or under the replacement height at stage k (the mill is the run's, so are its
    // kinds) was due for relining before that stage: its life is behind it, and the life
    // counted from stage k would be negative. Refused, as a scene whose lifter starts there is.
    {
      const double limit_m = d.scene.wear.replacement_height_m;
      std::vector<LifterMetrics> lifters = {from.lifter};
      if (from.kinds.size() > 1) lifters = from.kinds;
      for (std::size_t i = 0; i < lifters.size(); ++i) {
        if (lifters[i].height_m > limit_m) continue;
        const std::string whose =
            lifters.size() > 1 ? "kind " + std::to_string(i) + " ('" + d.scene.mill.kind(static_cast<int>(i)).name + "')"
                               : "the lifter";
        throw InputError(d.files.front(), "wear.replacement_height",
                         "a lifter above the replacement height at the stage the run continues from: at stage " +
                             std::to_string(k) + " of " + run + " (" + io::format_number(from.hours) + " h) " + whose +
                             " is " + io::format_number(in_mm(lifters[i].height_m), 4) + " mm high, at or under the "
                             "replacement height of " + io::format_number(in_mm(limit_m), 4) +
                             " mm, so it was due for relining before that stage and has no life left to run; "
                             "continue from an earlier stage (--stage), or give a lower wear.replacement_height");
      }
    }
    // A carried charge of other disks would run the old filling under the new one's name.
    if (from.start_charge.size() > 0 && !same_disks(fill_charge(d.scene, stage_mill(d.scene, from)), from.start_charge)) {
      d.refill = true;
      d.changes.push_back("charge: other disks than stage " + std::to_string(k) +
                          " started with; filled anew on its liner, settled and spun up");
    } else if (from.start_charge.size() > 0) {
      // The seed only places and draws the disks of a fill: a charge carried on does not see it.
      for (std::string& change : d.changes)
        if (change.rfind("solver.seed: ", 0) == 0)
          change += " (no effect: the charge is carried on from stage " + std::to_string(k) +
                    " as it was; only sizes drawn from a size_range would change with it)";
    }
    d.fingerprint = io::stable_hash_hex(d.fingerprint + "\n--continue " + run + " --stage " + std::to_string(k));
  }
}

Plan make_plan(const PlanArgs& args) {
  if (!args.fidelity.empty()) fidelity_preset(args.fidelity);  // InputError for a bad name
  Plan plan;
  std::string reference;
  for (const auto& path : args.scenes) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      throw InputError(path, "", "a scene or comparison file (not found or not a regular file)");
    if (auto t = comparison_table(path))
      add_comparison(plan, path, *t, args.fidelity, args.overrides, reference);
    else
      add_design(plan, path, args.fidelity, args.overrides);
  }
  if (plan.designs.empty()) throw InputError("", "SCENE", "at least one scene file");
  if (!args.reference.empty()) {
    bool found = false;
    for (const auto& d : plan.designs) found = found || d.name == args.reference;
    if (!found) throw InputError("", "--reference", "the name of one of the designs, found '" + args.reference + "'");
    reference = args.reference;
  }
  plan.reference = reference.empty() ? plan.designs.front().name : reference;
  if (!args.fidelity.empty()) {
    plan.fidelity = args.fidelity;
  } else {
    plan.fidelity = plan.designs.front().scene.fidelity;
    for (const auto& d : plan.designs)
      if (d.scene.fidelity != plan.fidelity) plan.fidelity = "mixed";
  }
  std::error_code ec;
  if (!args.out.empty() && fs::exists(args.out, ec) && !fs::is_directory(args.out, ec))
    throw InputError(args.out, "-o", "an output folder, but a file of that name exists");
  if (args.replicates < 1 || args.replicates > kMaxReplicates)
    throw InputError("", "--replicates", "1 to " + std::to_string(kMaxReplicates) + " histories per design, got " +
                                             std::to_string(args.replicates));
  if (args.replicates > 1) add_replicates(plan, args.replicates);
  if (!args.continue_from.empty()) continue_designs(plan, args);
  return plan;
}

void check_fills(const Plan& plan) {
  for (const DesignInput& d : plan.designs)
    if (d.continue_run.empty()) fill_charge(d.scene, starting_mill(d.scene));
}

std::vector<std::string> design_names(const Plan& plan) {
  std::vector<std::string> names;
  for (const auto& d : plan.designs)
    if (std::find(names.begin(), names.end(), d.design) == names.end()) names.push_back(d.design);
  return names;
}

Scene load_checked_scene(const std::string& file, const std::vector<std::string>& overrides,
                         const std::string& fidelity, const std::function<void(Scene&)>& adjust) {
  Scene scene = load_scene(file, overrides);
  if (!fidelity.empty()) apply_fidelity(scene, fidelity);
  if (adjust) adjust(scene);
  check_scene(scene, file);
  return scene;
}

std::vector<Scene> load_designs(const std::string& path, const std::vector<std::string>& overrides) {
  PlanArgs args;
  args.scenes = {path};
  args.overrides = overrides;
  std::vector<Scene> scenes;
  for (auto& d : make_plan(args).designs) scenes.push_back(std::move(d.scene));
  return scenes;
}

}  // namespace millwear::study
