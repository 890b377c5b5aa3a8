# screen_top_profiles.gp - the best few designs of a screen, new (dashed) and worn (solid)
# lifter profiles overlaid, lifter-local mm.
# Inputs (see common.gp for the shared variables):
#   datadir   the screen's output folder OUT
#   designs   the designs drawn, best first (made by millwear screen: the top 3 by life)
#   OUT/plots/data/top_profiles.dat  two gnuplot data blocks per design (new, then the last
#             stage), in `designs` order; x_mm,y_mm rows
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/screen_top_profiles).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/screen_top_profiles"
if (words(designs) == 0) { print "screen_top_profiles.gp: set designs='A B ...'"; exit status 1 }
file = datafolder . "/top_profiles.dat"
n = words(designs)
do for [fmt in formats] {
  eval term_cmd(fmt, 900, 560)
  set output outbase . "." . fmt
  set title "Best designs by life: new (dashed) and worn at the last stage (solid)"
  set xlabel "Along the shell, x (mm; +x = leading face)"
  set ylabel "Height above the shell, y (mm)"
  set size ratio -1
  set key top right
  plot for [i = 1:n] file index (2*i-2) using 1:2 with lines ls design_ls(i) dt 2 notitle, \
       for [i = 1:n] file index (2*i-1) using 1:2 with lines ls design_ls(i) title sprintf("%d. %s", i, word(designs, i))
  set output
}
