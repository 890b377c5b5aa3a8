# kinds_area.gp - each kind of lifter of a pattern (hi-lo, mixed): its cross-section area and
# its area loss rate against running time.
# Inputs (see common.gp for the shared variables):
#   series                              space-separated DESIGN_kindK names, one per curve
#   OUT/plots/data/DESIGN_kindK.csv     the rows of OUT/kinds.csv for one design and kind, by
#                                       hours; columns used: hours, area_mm2,
#                                       area_loss_rate_mm2_per_1000h
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/kinds_area).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/kinds_area"
if (!exists("series") || words(series) == 0) { print "kinds_area.gp: set series='DESIGN_kind0 ...'"; exit status 1 }

n = words(series)
kind_file(s) = datafolder . "/" . s . ".csv"
do for [fmt in formats] {
  eval term_cmd(fmt, 1300, 560)
  set output outbase . "." . fmt
  set multiplot layout 1,2 title "Each kind of lifter of the pattern, worn on its own" font ",13"
  set xlabel "Running time (h)"
  set ylabel "Cross-section area (mm^2)"
  set title "(a) Lifter cross-section area"
  set key bottom left
  set yrange [0:*]
  plot for [i = 1:n] kind_file(word(series, i)) using "hours":"area_mm2" \
       with linespoints ls i title word(series, i)
  set ylabel "Area loss rate (mm^2 per 1000 h)"
  set title "(b) Area loss rate at each stage's geometry"
  set key top left
  plot for [i = 1:n] kind_file(word(series, i)) using "hours":"area_loss_rate_mm2_per_1000h" \
       with linespoints ls i title word(series, i)
  unset multiplot
  set output
}
