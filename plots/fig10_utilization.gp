# fig10_utilization.gp - Energy utilisation (collision energy / power draw), normalised to the reference design new stage (paper Fig. 10).
# Inputs (see common.gp for the shared variables):
#   designs, reference                 design names; reference names the normalisation
#   OUT/plots/data/DESIGN_summary.csv  columns used: hours, utilization_norm and its _se (error bars)
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/fig10_utilization).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
figname = "fig10_utilization"
ycolumn = "utilization_norm"
ylabeltext = "Energy utilisation / that of " . reference . " new (-)"
titletext = "Energy utilisation (collision energy / power draw), normalised to the " . reference . " new stage"
load scriptdir . "/normalised_vs_hours.gp"
