# kinds_area.gp - each kind of lifter of a pattern (hi-lo, mixed): its cross-section area, its
# area loss rate and its height against running time, with each kind's life.
# Inputs (see common.gp for the shared variables):
#   series                              space-separated DESIGN_kindK names, one per curve
#   title1, title2, ...                 optional: each curve's title (default: its series name),
#                                       e.g. "sag-hi-lo hi-2x30: life 9475 h*"
#   OUT/plots/data/DESIGN_kindK.csv     the rows of OUT/kinds.csv for one design and kind, by
#                                       hours; columns used: hours, area_mm2,
#                                       area_loss_rate_mm2_per_1000h, height_mm, life_h,
#                                       replacement_height_mm
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/kinds_area).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/kinds_area"
if (!exists("series") || words(series) == 0) { print "kinds_area.gp: set series='DESIGN_kind0 ...'"; exit status 1 }

n = words(series)
kind_file(s) = datafolder . "/" . s . ".csv"
curve_title(i) = exists(sprintf("title%d", i)) ? value(sprintf("title%d", i)) : word(series, i)
# A life that is a number (not inf or nan) marks the point where the kind reaches the
# replacement height.
finite(x) = (x == x && abs(x) < 1e30) ? x : NaN
do for [fmt in formats] {
  eval term_cmd(fmt, 1800, 560)
  set output outbase . "." . fmt
  set multiplot layout 1,3 title "Each kind of lifter of the pattern, worn on its own (* life extrapolated)" font ",13"
  set xlabel "Running time (h)"
  set ylabel "Cross-section area (mm^2)"
  set title "(a) Lifter cross-section area"
  set key bottom left
  set yrange [0:*]
  plot for [i = 1:n] kind_file(word(series, i)) using "hours":"area_mm2" \
       with linespoints ls i title curve_title(i)
  set ylabel "Area loss rate (mm^2 per 1000 h)"
  set title "(b) Area loss rate at each stage's geometry"
  # A rate may rise or fall: the key sits in room kept free above the highest point.
  set key top left
  set offsets graph 0.03, graph 0.03, graph 0.12 * (n + 1), graph 0.05
  plot for [i = 1:n] kind_file(word(series, i)) using "hours":"area_loss_rate_mm2_per_1000h" \
       with linespoints ls i title curve_title(i)
  set offsets graph 0.03, graph 0.03, graph 0.05, graph 0.05  # common.gp's again
  set ylabel "Lifter height (mm)"
  set title "(c) Height; filled: the life, at the replacement height"
  set key bottom left
  stats kind_file(word(series, 1)) using "replacement_height_mm" nooutput
  set arrow 1 from graph 0, first STATS_min to graph 1, first STATS_min nohead dt 2 lc "gray"
  plot for [i = 1:n] kind_file(word(series, i)) using "hours":"height_mm" \
         with linespoints ls i title curve_title(i), \
       for [i = 1:n] kind_file(word(series, i)) every ::0::0 \
         using (finite(column("life_h"))):"replacement_height_mm" with points ls i pt 7 ps 2 notitle, \
       NaN with lines dt 2 lc "gray" title "replacement height"
  unset arrow 1
  unset multiplot
  set output
}
