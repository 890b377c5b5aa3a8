# common.gp - shared settings for the millwear figure scripts (loaded by each of them).
#
# Variables a figure script may be given with -e (all strings); defaults in brackets:
#   datadir   run output folder OUT                               ["."]
#   outbase   output path without extension; the script writes outbase.'.png' and
#             outbase.'.svg' (one per word of `formats`)          [per script: OUT/plots/NAME]
#   designs   space-separated design names, in legend order        [required by most scripts]
#   reference design the normalised values refer to (titles only)  [first word of designs]
#   formats   output formats, words from "png svg"                 ["png svg"]
#   pngterm   gnuplot terminal for PNG                             [pngcairo if present, else png]
#   scale     size factor for the images                           [1]
#
# Per-design files made by the C++ side (render_all_figures) from the run folder:
#   OUT/plots/data/DESIGN_summary.csv   the rows of OUT/summary.csv for DESIGN, by hours
#   OUT/plots/data/DESIGN_profiles.dat  every OUT/profiles/DESIGN_stageK.csv, one gnuplot
#                                       data block per stage (two blank lines between
#                                       blocks); each block starts with a title line
#                                       "stage K (H h),..." then x_mm,y_mm rows
#   OUT/plots/data/DESIGN_spectrum.csv  the rows of OUT/spectrum.csv for DESIGN
# To restyle a figure, edit its script and run it by hand, e.g.
#   gnuplot -e "datadir='OUT'; designs='2x30 1x30'" plots/fig7_area.gp

if (!exists("datadir")) datadir = "."
if (!exists("designs")) designs = ""
if (!exists("reference")) reference = word(designs, 1)
if (!exists("formats")) formats = "png svg"
if (!exists("pngterm")) pngterm = (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) ? "pngcairo" : "png"
if (!exists("scale")) scale = "1"

datafolder = datadir . "/plots/data"
summary_file(d) = datafolder . "/" . d . "_summary.csv"
profiles_file(d) = datafolder . "/" . d . "_profiles.dat"
spectrum_file(d) = datafolder . "/" . d . "_spectrum.csv"

# The set-terminal command for one format at a size in pixels (svg: same size in points).
term_cmd(fmt, w, h) = (fmt eq "svg") \
  ? sprintf("set terminal svg size %d,%d dynamic noenhanced font 'Sans,12' background rgb 'white'", \
            int(w * real(scale)), int(h * real(scale))) \
  : sprintf("set terminal %s size %d,%d noenhanced font 'Sans,11'", pngterm, \
            int(w * real(scale)), int(h * real(scale)))

set datafile separator comma
set encoding utf8

# Design colours (line style i = i-th design): colour-blind safe (Okabe-Ito).
set style line 1 lc rgb '#0072B2' lw 2.5 pt 7 ps 1.3 dt 1
set style line 2 lc rgb '#D55E00' lw 2.5 pt 5 ps 1.3 dt 1
set style line 3 lc rgb '#009E73' lw 2.5 pt 9 ps 1.5 dt 1
set style line 4 lc rgb '#CC79A7' lw 2.5 pt 11 ps 1.5 dt 1
set style line 5 lc rgb '#E69F00' lw 2.5 pt 13 ps 1.5 dt 1
set style line 6 lc rgb '#56B4E9' lw 2.5 pt 3 ps 1.5 dt 1
set style line 7 lc rgb '#000000' lw 2.5 pt 1 ps 1.5 dt 1
set style line 8 lc rgb '#999999' lw 2.5 pt 2 ps 1.5 dt 1
design_ls(i) = ((i - 1) % 8) + 1

set grid lc rgb '#d8d8d8' lw 1 dt 1
set offsets graph 0.03, graph 0.03, graph 0.05, graph 0.05
set autoscale xfix
set border lw 1.2
set key box opaque samplen 3 spacing 1.2
