# validate_profiles.gp - measured (dashed) against simulated (solid) lifter profiles, one
# colour per survey (paper Fig. 4). Written by `millwear validate`.
# Inputs (gnuplot string variables; see common.gp for formats, pngterm, scale):
#   measured    data file: one block per survey, blocks separated by two blank lines; each
#               block is a title line "H h,-" then x_mm,y_mm rows (lifter-local)
#   simulated   same layout, the simulated profiles at the same hours, same block order
#   outbase     output path without extension (writes outbase.png, outbase.svg)
#   title       figure title (optional)
# By hand: gnuplot -e "measured='OUT/plots/validate_measured.dat'; \
#   simulated='OUT/plots/validate_simulated.dat'; outbase='OUT/validate_profiles'" plots/validate_profiles.gp
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("measured") || !exists("simulated")) { print "validate_profiles.gp: set measured='...' and simulated='...'"; exit status 1 }
if (!exists("outbase")) outbase = "validate_profiles"
if (!exists("title")) title = "Measured (dashed) and simulated (solid) lifter profiles"

stats measured using 1:2 nooutput
nb = STATS_blocks
xmin = STATS_min_x; xmax = STATS_max_x; ymax = STATS_max_y
stats simulated using 1:2 nooutput
xmin = (STATS_min_x < xmin) ? STATS_min_x : xmin
xmax = (STATS_max_x > xmax) ? STATS_max_x : xmax
ymax = (STATS_max_y > ymax) ? STATS_max_y : ymax
pad = 0.04 * (xmax - xmin)
set xrange [xmin - pad : xmax + pad]
set yrange [0 : ymax + 0.15 * (xmax - xmin)]
set size ratio -1
set offsets 0, 0, 0, 0
# Survey colours from black (first) through blue and orange to red (last).
set palette defined (0 '#000000', 0.35 '#0072B2', 0.7 '#E69F00', 1 '#D55E00')
unset colorbox
frac(k) = (nb > 1) ? real(k) / (nb - 1) : 0.0

do for [fmt in formats] {
  eval term_cmd(fmt, 900, 560)
  set output outbase . "." . fmt
  set title title
  set xlabel "x along the shell (mm)"
  set ylabel "Height above the shell (mm)"
  set key top right
  plot for [k = 0:nb-1] simulated index k using 1:2 with lines lw 2.2 dt 1 lc palette frac frac(k) \
         title "simulated ".columnhead(1), \
       for [k = 0:nb-1] measured index k using 1:2 with lines lw 2.2 dt 2 lc palette frac frac(k) \
         title "measured ".columnhead(1), \
       0 with lines lc rgb '#555555' lw 1 notitle
  set output
}
