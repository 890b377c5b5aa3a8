#pragma once
// Figures from a run folder, drawn by gnuplot through gnuplot-iostream.
//
// The figure scripts live in the repository's plots/ folder, installed to
// PREFIX/share/millwear/plots (one .gp per figure, inputs documented at the top of each), so
// users can restyle them and rerun them by hand. This module only prepares per-design data
// files, passes variables, runs gnuplot, checks the images exist, and moves them into place
// atomically (gnuplot draws to a temporary name, then we rename). It never prints: gnuplot's
// messages go to OUT/plots/gnuplot.log and failures come back as millwear::RunError.
#include <map>
#include <string>
#include <vector>

namespace millwear::plots {

// The folder with the figure scripts, found relative to the running executable (no path is
// compiled in), the first of:
//   $MILLWEAR_PLOTS_DIR             if set and non-empty (RunError if it is not a folder);
//   EXEDIR/../share/millwear/plots  an installed program, PREFIX/bin/millwear;
//   EXEDIR/share/millwear/plots     the build tree, where CMake links plots/ beside the binaries.
// Throws RunError naming the folders it looked in if none exists.
std::string plots_dir();

// Path of a script in plots_dir(), e.g. script_path("fig7_area") -> ".../plots/fig7_area.gp".
std::string script_path(const std::string& figure);

// The colour of each species in the charge figures ("#rrggbb"), muted so the liner's colours
// stand out: balls in steel blues, rocks in earth tones, the k-th species of a kind one shade
// further along (four shades, then again).
std::vector<std::string> species_colours(const std::vector<bool>& is_ball);

// True if a `gnuplot` executable is on PATH.
bool gnuplot_available();

// Runs one gnuplot script. Every entry of `vars` is set as a gnuplot string variable
// (name='value') before `load 'script_path'`; `scriptdir` is set to the script's folder
// unless given. Conventions shared with the scripts (see plots/common.gp):
//   outbase  output path without extension; the script writes outbase.FORMAT for each
//            word of `formats` (default "png svg"). If outbase is given, gnuplot draws to a
//            temporary base next to it and the files are renamed into place only after
//            gnuplot succeeded and each is non-empty.
// gnuplot's stderr is appended to `log_path` (default: gnuplot.log next to outbase; with
// neither, it is discarded).
// Returns the files written (outbase.FORMAT, in `formats` order).
// Throws RunError: gnuplot not installed, script missing, gnuplot reported an error (the
// message quotes the last lines of its log), or an expected image is missing or empty.
std::vector<std::string> render_figure(const std::string& script_path,
                                       const std::map<std::string, std::string>& vars,
                                       const std::string& log_path = "");

// Renders every figure whose inputs are in the run folder `out_dir` into OUT/plots:
//   fig6_profiles      needs OUT/profiles/DESIGN_stageK.csv
//   fig7_area, fig8_power, fig9_collision, fig10_utilization   need OUT/summary.csv
//   spectrum           needs OUT/spectrum.csv
//   snapshot_DESIGN    needs OUT/snapshot_DESIGN.csv and OUT/liner_DESIGN.csv
//   kinds_area         needs OUT/kinds.csv (a pattern of lifter kinds)
// First splits the run's files per design into OUT/plots/data/ (DESIGN_summary.csv sorted
// by hours, DESIGN_profiles.dat one block per stage, DESIGN_spectrum.csv, DESIGN_kindK.csv
// per lifter kind), the inputs the
// scripts read. `designs` gives the legend order; empty = the order in summary.csv (or the
// profile file names). `reference` names the design the normalised values refer to, for
// titles; empty = the design whose stage 0 has power_norm = 1, else the first design.
// Returns the figure files written (PNG and SVG). A figure without inputs is skipped. If
// some figures fail, the others are still drawn, then RunError lists the failures.
// Input files that do not parse throw InputError(file, "line N", ...).
std::vector<std::string> render_all_figures(const std::string& out_dir,
                                            const std::vector<std::string>& designs,
                                            const std::string& reference = "");
// What a set of figures came to: the files written, and "NAME: why" for each that failed.
struct FigureOutcome {
  std::vector<std::string> written, failures;
};
// render_all_figures without the throw, for a command that draws figures of its own too.
FigureOutcome draw_all_figures(const std::string& out_dir, const std::vector<std::string>& designs,
                               const std::string& reference = "");
// Returns the files written; throws RunError listing the failures if there are any.
std::vector<std::string> figures_or_throw(const FigureOutcome& outcome);

// The files render_all_figures writes besides the figures, those on disk: OUT/plots/gnuplot.log
// and, per design, OUT/plots/data/DESIGN_{summary.csv,spectrum.csv,profiles.dat} and
// DESIGN_kindK.csv.
std::vector<std::string> figure_data_files(const std::string& out_dir, const std::vector<std::string>& designs);

}  // namespace millwear::plots
