# fig6_profiles.gp - lifter profile evolution, one panel per design, one line per stage
# (paper Fig. 6a and 6b). Equal scales on both axes and the same window for every panel.
# Inputs (see common.gp for the shared variables):
#   designs                              space-separated design names (one panel each)
#   OUT/plots/data/DESIGN_profiles.dat   one data block per stage, blocks separated by two
#                                        blank lines; each block is a title line
#                                        "stage K (H h),-" then x_mm,y_mm rows (lifter-local:
#                                        x along the shell, y inward from the shell)
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/fig6_profiles).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/fig6_profiles"
if (words(designs) == 0) { print "fig6_profiles.gp: set designs='A B ...'"; exit status 1 }

n = words(designs)
# One window for all panels, so the designs compare at the same scale.
xmin = 1e30; xmax = -1e30; ymax = -1e30; maxblocks = 1
do for [i = 1:n] {
  stats profiles_file(word(designs, i)) using 1:2 nooutput
  xmin = (STATS_min_x < xmin) ? STATS_min_x : xmin
  xmax = (STATS_max_x > xmax) ? STATS_max_x : xmax
  ymax = (STATS_max_y > ymax) ? STATS_max_y : ymax
  maxblocks = (STATS_blocks > maxblocks) ? STATS_blocks : maxblocks
}
pad = 0.06 * (xmax - xmin)
set xrange [xmin - pad : xmax + pad]
set yrange [0 : ymax + 0.25 * (xmax - xmin)]
set size ratio -1
set offsets 0, 0, 0, 0
# Stage colours run from black (new) through blue and orange to red (most worn).
set palette defined (0 '#000000', 0.35 '#0072B2', 0.7 '#E69F00', 1 '#D55E00')
unset colorbox
stage_frac(k) = (maxblocks > 1) ? real(k) / (maxblocks - 1) : 0.0

do for [fmt in formats] {
  eval term_cmd(fmt, 150 + 550 * n, 520)
  set output outbase . "." . fmt
  set multiplot layout 1, n title "Lifter wear history (profile after each stage)" font ",13"
  do for [i = 1:n] {
    d = word(designs, i)
    stats profiles_file(d) using 1:2 nooutput
    nb = STATS_blocks
    set title sprintf("(%c) %s lifter", 96 + i, d)
    set xlabel "x along the shell (mm)"
    set ylabel "Height above the shell (mm)"
    set key top right
    plot for [k = 0:nb-1] profiles_file(d) index k using 1:2 with lines lw 2.2 \
         lc palette frac stage_frac(k) title columnheader(1), \
         0 with lines lc rgb '#555555' lw 1 notitle
  }
  unset multiplot
  set output
}
