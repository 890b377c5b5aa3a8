# validate_areas.gp - measured lifter areas (points) on the simulated area history (line).
# Written by `millwear validate` when the measured file holds areas only.
# Inputs (gnuplot string variables; see common.gp for formats, pngterm, scale):
#   measured    CSV with a header line, hours,area_mm2: the measured areas, one row per survey
#               row (for area_loss_mm2 files: the scene's new lifter area minus the loss)
#   simulated   CSV with a header line, hours,area_mm2: the simulated lifter area at every stage
#   outbase     output path without extension (writes outbase.png, outbase.svg)
#   title       figure title (optional)
# By hand: gnuplot -e "measured='OUT/plots/validate_area_measured.csv'; \
#   simulated='OUT/plots/validate_area_simulated.csv'; outbase='OUT/validate_areas'" plots/validate_areas.gp
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("measured") || !exists("simulated")) { print "validate_areas.gp: set measured='...' and simulated='...'"; exit status 1 }
if (!exists("outbase")) outbase = "validate_areas"
if (!exists("title")) title = "Measured (points) and simulated (line) lifter area"

set yrange [0:*]

do for [fmt in formats] {
  eval term_cmd(fmt, 800, 520)
  set output outbase . "." . fmt
  set title title
  set xlabel "Operating hours (h)"
  set ylabel "Lifter area (mm^2)"
  set key top right
  plot simulated using 1:2 skip 1 with linespoints ls 1 title "simulated", \
       measured using 1:2 skip 1 with points ls 2 pt 6 ps 1.8 lw 2 title "measured"
  set output
}
