# fig9_collision.gp - Particle collision energy, normalised to that of the reference design new stage (paper Fig. 9).
# Inputs (see common.gp for the shared variables):
#   designs, reference                 design names; reference names the normalisation
#   OUT/plots/data/DESIGN_summary.csv  columns used: hours, collision_norm and its _se (error bars)
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/fig9_collision).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
figname = "fig9_collision"
ycolumn = "collision_norm"
ylabeltext = "Collision energy rate / that of " . reference . " new (-)"
titletext = "Particle collision energy, normalised to that of the " . reference . " new stage"
load scriptdir . "/normalised_vs_hours.gp"
