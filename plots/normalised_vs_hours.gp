# normalised_vs_hours.gp - one normalised quantity against running time, one line per
# design; the body of fig8_power.gp, fig9_collision.gp and fig10_utilization.gp, which set:
#   figname   default output name (OUT/plots/figname)
#   ycolumn   column of DESIGN_summary.csv to plot against "hours"
#   ylabeltext, titletext
# Inputs: designs; OUT/plots/data/DESIGN_summary.csv (columns hours, ycolumn and ycolumn_se,
# its standard error, drawn as error bars).
if (!exists("outbase")) outbase = datadir . "/plots/" . figname
if (words(designs) == 0) { print figname . ".gp: set designs='A B ...'"; exit status 1 }

n = words(designs)
do for [fmt in formats] {
  eval term_cmd(fmt, 900, 620)
  set output outbase . "." . fmt
  set title titletext . "\n(bars: one standard error)" font ",13"
  set xlabel "Running time (h)"
  set ylabel ylabeltext
  set key top right
  plot for [i = 1:n] summary_file(word(designs, i)) using "hours":ycolumn:ycolumn."_se" \
       with yerrorlines ls design_ls(i) title word(designs, i), \
       1 with lines lc rgb '#888888' dt 2 lw 1 notitle
  set output
}
