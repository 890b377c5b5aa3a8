# screen_pareto.gp - a screen's designs: lifter life against power draw and against energy
# utilisation, with the life's statistical error bars, Pareto fronts marked.
# Inputs (see common.gp for the shared variables):
#   datadir          the screen's output folder OUT
#   OUT/ranking.csv  columns used: design, life_h, life_sigma_h, power_kw, utilization,
#                    pareto_power, pareto_utilization, tied_with_best
#   power_sense      "min" or "max": which way the power front goes (titles only)
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/screen_pareto).
# Error bars are +-2 sigma of the life (life_sigma_h, docs/screen.md); filled points are on the
# Pareto front; designs tied with the best (within uncertainty) are ringed.
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/screen_pareto"
if (!exists("power_sense")) power_sense = "min"
ranking = datadir . "/ranking.csv"
front(c) = (column(c) == 1) ? column("life_h") : NaN
tied(c) = (column("tied_with_best") == 1) ? column("life_h") : NaN
# Each front's points in a table of their own, for the line that joins them: read from the
# whole ranking, the designs off the front (NaN) would break a smoothed line. The NaN row
# keeps a table of no front points plottable.
$front_power << EOD
NaN,NaN
EOD
$front_utilization << EOD
NaN,NaN
EOD
set table $front_power append separator comma
plot ranking using "power_kw":"life_h" with table if (column("pareto_power") == 1)
set table $front_utilization append separator comma
plot ranking using "utilization":"life_h" with table if (column("pareto_utilization") == 1)
unset table

do for [fmt in formats] {
  eval term_cmd(fmt, 1300, 560)
  set output outbase . "." . fmt
  set multiplot layout 1,2 title "Screen: lifter life against what the design does to the mill" font ",13"
  set ylabel "Lifter life (h), error bars +-2 sigma"
  set key top right
  set xlabel "Power draw, new liner (kW)"
  set title sprintf("(a) Life against power draw (front: longer life, %s power)", power_sense eq "max" ? "more" : "less")
  plot ranking using "power_kw":"life_h":(2*column("life_sigma_h")) with yerrorbars ls 1 pt 6 title "design", \
       $front_power using 1:2 smooth unique with lines ls 2 dt 2 notitle, \
       ranking using "power_kw":(front("pareto_power")) with points ls 2 pt 7 ps 1.6 title "Pareto front", \
       ranking using "power_kw":(tied(0)) with points ls 7 pt 6 ps 2.6 title "tied with the best", \
       ranking using "power_kw":"life_h":"design" with labels offset 0,1.2 font ",9" notitle
  set xlabel "Energy utilisation, new liner (collision / power, -)"
  set title "(b) Life against energy utilisation (front: longer life, higher utilisation)"
  plot ranking using "utilization":"life_h":(2*column("life_sigma_h")) with yerrorbars ls 1 pt 6 title "design", \
       $front_utilization using 1:2 smooth unique with lines ls 2 dt 2 notitle, \
       ranking using "utilization":(front("pareto_utilization")) with points ls 2 pt 7 ps 1.6 title "Pareto front", \
       ranking using "utilization":(tied(0)) with points ls 7 pt 6 ps 2.6 title "tied with the best", \
       ranking using "utilization":"life_h":"design" with labels offset 0,1.2 font ",9" notitle
  unset multiplot
  set output
}
