# fig7_area.gp - lifter cross-section area against running time (paper Fig. 7a and 7b).
# Inputs (see common.gp for the shared variables):
#   designs                             space-separated design names
#   OUT/plots/data/DESIGN_summary.csv   columns used: hours, area_norm, area_loss_pct and their _se (error bars)
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/fig7_area).
# Panel (a): area normalised to the reference design's new area (area_norm); panel (b): area
# reduction in % of the design's own new area.
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/fig7_area"
if (words(designs) == 0) { print "fig7_area.gp: set designs='A B ...'"; exit status 1 }

n = words(designs)
do for [fmt in formats] {
  eval term_cmd(fmt, 1300, 560)
  set output outbase . "." . fmt
  set multiplot layout 1,2 title "Lifter wear history: cross-section area against running time (bars: one standard error)" font ",13"
  set xlabel "Running time (h)"
  set ylabel "Normalised cross-section area (-)"
  set title "(a) Cross-section area, normalised to the reference design's new area"
  set key bottom left
  set yrange [*:1.02]
  plot for [i = 1:n] summary_file(word(designs, i)) using "hours":"area_norm":"area_norm_se" \
       with yerrorlines ls design_ls(i) title word(designs, i)
  set ylabel "Area reduction (%)"
  set title "(b) Cross-section area reduction from its own new area"
  set key top left
  set yrange [0:*]
  plot for [i = 1:n] summary_file(word(designs, i)) using "hours":"area_loss_pct":"area_loss_pct_se" \
       with yerrorlines ls design_ls(i) title word(designs, i)
  unset multiplot
  set output
}
