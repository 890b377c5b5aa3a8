# fig8_power.gp - Mill power draw, normalised to that of the reference design new stage (paper Fig. 8).
# Inputs (see common.gp for the shared variables):
#   designs, reference                 design names; reference names the normalisation
#   OUT/plots/data/DESIGN_summary.csv  columns used: hours, power_norm and its _se (error bars)
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/fig8_power).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
figname = "fig8_power"
ycolumn = "power_norm"
ylabeltext = "Power draw / power of " . reference . " new (-)"
titletext = "Mill power draw, normalised to that of the " . reference . " new stage"
load scriptdir . "/normalised_vs_hours.gp"
