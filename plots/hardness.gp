# hardness.gp - lifter wear rate per operating period before the ore-hardness correction,
# the ore hardness, and the wear rate after it (paper Figs. 1, 2 and 3, as three panels).
# Written by `millwear hardness`.
# Inputs (gnuplot string variables; see common.gp for formats, pngterm, scale):
#   periods    OUT/hardness_periods.csv: period,start,end,length,hardness,wear,rate,ct,
#              corrected_time,corrected_rate (one row per period; header line)
#   outbase    output path without extension (writes outbase.png, outbase.svg)
#   timeunit   "days" or "hours"            wearunit  name of the wear column
#   fit        text of the fitted correction, e.g. "CT = 0.0087 H^{1.8}"
#   cv_before, cv_after   coefficients of variation of the rate, %
# By hand: gnuplot -e "periods='OUT/hardness_periods.csv'; outbase='OUT/hardness'" plots/hardness.gp
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("periods")) { print "hardness.gp: set periods='OUT/hardness_periods.csv'"; exit status 1 }
if (!exists("outbase")) outbase = "hardness"
if (!exists("timeunit")) timeunit = "days"
if (!exists("wearunit")) wearunit = "wear"
if (!exists("fit")) fit = "CT = a H^b"
if (!exists("cv_before")) cv_before = "?"
if (!exists("cv_after")) cv_after = "?"
unit1 = (timeunit eq "days") ? "day" : "h"

stats periods using 3:7 nooutput
tmax = STATS_max_x
rmax = STATS_max_y
stats periods using 3:10 nooutput
rmax = (STATS_max_y > rmax) ? STATS_max_y : rmax
set xrange [0 : tmax]
set offsets 0, 0, graph 0.05, 0
set style fill solid 0.55 border lc rgb '#333333'
set boxwidth 1 absolute
set key off

do for [fmt in formats] {
  eval term_cmd(fmt, 820, 1020)
  set output outbase . "." . fmt
  set multiplot layout 3, 1
  set xlabel sprintf("Operating time (%s)", timeunit)

  set title sprintf("Measured lifter wear rate before correction (CV %s%%)", cv_before)
  set ylabel sprintf("%s per %s", wearunit, unit1)
  set yrange [0 : 1.15 * rmax]
  plot periods using (0.5*($2+$3)):7:($3-$2) with boxes lc rgb '#0072B2', \
       '' using (0.5*($2+$3)):7:1 with labels offset 0, 0.8 notitle

  set title "Ore hardness"
  set ylabel "Hardness"
  set yrange [0 : *]
  plot periods using (0.5*($2+$3)):5:($3-$2) with boxes lc rgb '#999999'

  set title sprintf("Measured lifter wear rate after correction, %s (CV %s%%)", fit, cv_after)
  set ylabel sprintf("%s per corrected %s", wearunit, unit1)
  set yrange [0 : 1.15 * rmax]
  plot periods using (0.5*($2+$3)):10:($3-$2) with boxes lc rgb '#009E73'

  unset multiplot
  set output
}
