# spectrum.gp - collision-energy spectrum: collision rate and dissipated power per
# energy bin against the energy of one collision, log-log, one line per design.
# Inputs (see common.gp for the shared variables):
#   designs                              space-separated design names
#   OUT/plots/data/DESIGN_spectrum.csv   columns used: energy_J_lower, energy_J_upper,
#                                        count_per_s, energy_W (one row per energy bin)
# Each bin is drawn at its geometric centre sqrt(lower*upper); empty bins (0) are skipped,
# a log axis cannot show them.
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/spectrum).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("outbase")) outbase = datadir . "/plots/spectrum"
if (words(designs) == 0) { print "spectrum.gp: set designs='A B ...'"; exit status 1 }

n = words(designs)
bin_centre(lo, up) = (lo > 0 && up > 0) ? sqrt(lo * up) : NaN
positive(v) = (v > 0) ? v : NaN
set logscale xy
set format x "10^{%T}"
set format y "10^{%T}"
set offsets 0, 0, 0, 0
set autoscale xfix

do for [fmt in formats] {
  eval term_cmd(fmt, 1300, 560)
  # 10^{n} needs enhanced text for the exponents; names stay literal with noenhanced titles.
  set termoption enhanced
  set output outbase . "." . fmt
  set multiplot layout 1,2 title "Collision-energy spectrum" font ",13"
  set xlabel "Energy dissipated in one collision (J)"
  set ylabel "Collisions per second in the bin (1/s)"
  set title "(a) Collision frequency"
  set key top right
  plot for [i = 1:n] spectrum_file(word(designs, i)) \
       using (bin_centre(column("energy_J_lower"), column("energy_J_upper"))):(positive(column("count_per_s"))) \
       with linespoints ls design_ls(i) title word(designs, i) noenhanced
  set ylabel "Power dissipated in the bin (W)"
  set title "(b) Collision power"
  set key top left
  plot for [i = 1:n] spectrum_file(word(designs, i)) \
       using (bin_centre(column("energy_J_lower"), column("energy_J_upper"))):(positive(column("energy_W"))) \
       with linespoints ls design_ls(i) title word(designs, i) noenhanced
  unset multiplot
  set output
}
