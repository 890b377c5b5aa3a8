# tradeoff.gp - speed against accuracy: error of each fidelity setting against wall time,
# the Pareto front marked (millwear tradeoff, src/study/tradeoff.hpp).
# Inputs (see common.gp for the shared variables):
#   OUT/tradeoff.csv        columns used: label, knob, cpu_s, dev_max_pct, dev_mean_pct
#   OUT/tradeoff_front.csv  the front rows by CPU time: label, cpu_s, dev_max_pct
# Output: outbase.png, outbase.svg (default outbase = OUT/tradeoff).
# x: CPU time of the whole wear history (log; wall time varies with the load); y: final-profile deviation from the
# reference, largest normal distance in % of the new lifter height (filled points) and the
# mean (open points). Presets are labelled in bold colours; one-knob settings in grey.
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/tradeoff"
table = datadir . "/tradeoff.csv"
front = datadir . "/tradeoff_front.csv"

is_preset(k) = (k eq "preset")
# The y range follows the presets (3x the worst of them): a setting that breaks the profile
# (e.g. a smoothing radius that removes the lifter) would flatten everything else; it is
# clipped and named in a note instead.
stats table using (is_preset(strcol("knob")) ? column("dev_max_pct") : NaN) nooutput name "P"
ytop = 3.0 * P_max + 0.5
stats table using (column("dev_max_pct") > ytop ? 1 : 0) nooutput name "OFF"
offscale = int(OFF_sum)
do for [fmt in formats] {
  eval term_cmd(fmt, 1000, 650)
  set output outbase . "." . fmt
  set title "Speed against accuracy: final-profile deviation from the reference run" font ",13"
  set xlabel "CPU time of the wear history (s, log scale; one thread)"
  set ylabel "Final-profile deviation (% of lifter height)"
  set logscale x
  set format x "%g"
  set mxtics 10
  set yrange [0:ytop]
  if (offscale > 0) { set label 99 sprintf("%d setting(s) above %.1f%% off the scale (see tradeoff.csv)", offscale, ytop) at graph 0.02, graph 0.96 left font ",9" } else { unset label 99 }
  set key top right
  plot front using "cpu_s":"dev_max_pct" with steps ls 8 dt 2 lw 2 title "Pareto front (largest deviation)", \
       table using "cpu_s":(is_preset(strcol("knob")) ? NaN : column("dev_max_pct")) \
             with points pt 7 ps 1.2 lc rgb '#999999' title "one knob from standard (largest)", \
       table using "cpu_s":(is_preset(strcol("knob")) ? NaN : column("dev_max_pct")):"label" \
             with labels left offset 0.8,0 font ",8" tc rgb '#666666' notitle, \
       table using "cpu_s":(is_preset(strcol("knob")) ? column("dev_max_pct") : NaN) \
             with points ls 2 pt 7 ps 2 title "presets (largest)", \
       table using "cpu_s":(is_preset(strcol("knob")) ? column("dev_mean_pct") : NaN) \
             with points ls 1 pt 6 ps 2 title "presets (mean)", \
       table using "cpu_s":(is_preset(strcol("knob")) ? column("dev_max_pct") : NaN):"label" \
             with labels left offset 1,0.6 font ",11" notitle, \
       front using "cpu_s":"dev_max_pct" with points pt 6 ps 2.6 lc rgb '#000000' title "on the front"
  unset logscale x
  set output
}
