# screen_heatmap.gp - lifter life over the two parameters of a two-parameter screen family.
# Inputs (see common.gp for the shared variables):
#   datadir   the screen's output folder OUT
#   xlabel_text, ylabel_text   the two parameters (column names of designs.csv)
#   OUT/plots/data/heatmap.dat  x,y,life_h,design rows (finished designs)
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/screen_heatmap).
# Each design is a square coloured by its life (grid and Latin-hypercube families alike).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/screen_heatmap"
file = datafolder . "/heatmap.dat"
do for [fmt in formats] {
  eval term_cmd(fmt, 900, 640)
  set output outbase . "." . fmt
  set title "Lifter life over the family's two parameters"
  set xlabel xlabel_text
  set ylabel ylabel_text
  set cblabel "Lifter life (h)"
  unset key
  set palette defined (0 '#440154', 1 '#3b528b', 2 '#21918c', 3 '#5ec962', 4 '#fde725')
  set offsets graph 0.08, graph 0.08, graph 0.08, graph 0.08
  plot file using 1:2:3 with points pt 5 ps 5 palette notitle, \
       file using 1:2:(sprintf("%.0f", $3)) with labels offset 0,-1.6 font ",9" notitle
  set output
}
