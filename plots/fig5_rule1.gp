# fig5_rule1.gp - rule 1: the final lifter profile at each C_model factor over the new lifter
# (paper Fig. 5). One colour per factor, one line per replicate (seed), the new profile black.
# Inputs (see common.gp for the shared variables):
#   OUT/rule1_profiles.dat   data blocks separated by two blank lines: the new profile first,
#                            then one block per factor, each starting with a title line
#                            "factor F (verdict),-", replicates one blank line apart; x_mm,y_mm
#                            rows (lifter-local: x along the shell, y inward from the shell)
#   title_extra              optional text for the title (scene, tolerance, recommendation)
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/fig5_rule1).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/fig5_rule1"
if (!exists("title_extra")) title_extra = ""
file = datadir . "/rule1_profiles.dat"

stats file using 1:2 nooutput
nb = STATS_blocks
xmin = STATS_min_x; xmax = STATS_max_x; ymax = STATS_max_y
# Zoom on the lifter: the shell either side is flat and wears little.
stats file index 0 using ($2 > 0.02 * ymax ? $1 : NaN) nooutput
if (STATS_records > 0) { xmin = STATS_min - 0.25 * (STATS_max - STATS_min); xmax = STATS_max + 0.25 * (STATS_max - STATS_min) }
set xrange [xmin : xmax]
set yrange [-0.05 * ymax : 1.2 * ymax]
set size ratio -1
# One colour per factor (colour-blind safe, in order), repeating after eight.
colours = "#0072B2 #E69F00 #009E73 #D55E00 #CC79A7 #56B4E9 #999933 #882255"
colour(k) = word(colours, (k - 1) % 8 + 1)

do for [fmt in formats] {
  eval term_cmd(fmt, 900, 620)
  set output outbase . "." . fmt
  set title "Rule 1: final profile at each C_model factor (one line per seed)" . (title_extra ne "" ? "\n" . title_extra : "")
  set xlabel "x along the shell (mm)"
  set ylabel "Height above the shell (mm)"
  set key top right
  plot file index 0 using 1:2 with lines lw 2.5 lc rgb '#000000' title "new lifter", \
       for [k = 1:nb-1] file index k using 1:2 with lines lw 1.4 lc rgb colour(k) title columnheader(1), \
       0 with lines lc rgb '#555555' lw 1 notitle
  set output
}
