# impacts.gp - where the lifters throw the charge (`millwear charge`): the first impacts of
# the flights from the lifters against the angle round the mill, by species. Top: impact
# power per 5 deg bin (W per metre of mill), the part that strikes the bare liner shaded;
# bottom: impacts per second (in the simulated slice). The toe and shoulder are marked and
# the arc above the toe (outside the bed) is tinted: impact energy there that strikes the
# liner is what damages it (docs/trajectories.md).
# Inputs (see common.gp for the shared variables):
#   design                          the scene's name (titles)
#   species_names, species_colours  one word per species index: its name and colour "#rrggbb"
#                                   [species_0, ...; grey]
#   toe_deg, shoulder_deg, centrifuged   from 6 o'clock, + toward the rising side [none]
#   liner_share_text, above_toe_share_text  the shares as the title gives them [none]
#   OUT/impacts.csv                 angle_deg_lower, angle_deg_upper, impacts_per_s,
#                                   impact_power_W_per_m, liner_impact_power_W_per_m, then per
#                                   species impacts_per_s_NAME, impact_power_W_per_m_NAME
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/impacts_DESIGN).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("design")) design = "charge"
if (!exists("outbase")) outbase = datadir . "/plots/impacts_" . design
datafile = datadir . "/impacts.csv"

# Species: columns 6 + 2 s (impacts) and 7 + 2 s (power) of impacts.csv.
if (exists("species_names")) { nspecies = words(species_names) } else { stats datafile using 1 nooutput; nspecies = int((STATS_columns - 5) / 2) }
if (!exists("species_names")) { species_names = ""; do for [s = 0:nspecies-1] { species_names = species_names . sprintf(" species_%d", s) } }
if (!exists("species_colours")) { species_colours = ""; do for [s = 0:nspecies-1] { species_colours = species_colours . " #8f8f7a" } }
species_col(s) = word(species_colours, s + 1)
mid(x) = 0.5 * (column("angle_deg_lower") + column("angle_deg_upper"))

have_marks = exists("toe_deg") && exists("shoulder_deg") ? 1 : 0
is_centrifuged = exists("centrifuged") ? int(real(centrifuged)) : 0
if (!exists("liner_share_text")) liner_share_text = "none"
if (!exists("above_toe_share_text")) above_toe_share_text = "none"

set xrange [-180 : 180]
set lmargin 12
set xtics -180, 30, 180
set offsets 0, 0, graph 0.05, 0
set style fill transparent solid 0.35 noborder
set key top left opaque box

do for [fmt in formats] {
  eval term_cmd(fmt, 1000, 820)
  set output outbase . "." . fmt
  set multiplot layout 2, 1 title sprintf("First impacts of the flights from the lifters: %s\nimpact energy above the toe %s, on the bare liner above the toe %s", \
      design, above_toe_share_text, liner_share_text) font ",12"
  unset object; unset arrow; unset label
  # NaN (no disk reached the shell band) is not equal to itself: then no marks.
  if (have_marks && is_centrifuged == 0 && real(toe_deg) == real(toe_deg) && real(shoulder_deg) == real(shoulder_deg)) {
    # The arc above the toe (outside the bed) tinted; toe and shoulder drawn.
    set object 1 rect from -180, graph 0 to real(toe_deg), graph 1 fc rgb '#f6e3d4' fs solid 0.6 noborder behind
    set object 2 rect from real(shoulder_deg), graph 0 to 180, graph 1 fc rgb '#f6e3d4' fs solid 0.6 noborder behind
    set arrow 1 from real(toe_deg), graph 0 to real(toe_deg), graph 1 nohead lw 2 dt 2 lc rgb '#000000' front
    set arrow 2 from real(shoulder_deg), graph 0 to real(shoulder_deg), graph 1 nohead lw 2 dt 2 lc rgb '#000000' front
    set label 1 "toe" at real(toe_deg), graph 0.94 left offset 0.5, 0 front
    set label 2 "shoulder" at real(shoulder_deg), graph 0.94 right offset -0.5, 0 front
  }
  if (is_centrifuged == 1) { set label 3 "centrifuged: no toe or shoulder" at graph 0.5, graph 0.9 center front }
  set ylabel "impact power per 5 deg (W/m)"
  unset xlabel
  set format x ""
  plot datafile using (mid(0)):"liner_impact_power_W_per_m" with boxes lc rgb '#555555' title "on the bare liner", \
       for [s = 0:nspecies-1] datafile using (mid(0)):(column(7 + 2 * s)) with histeps lw 2.5 lc rgb species_col(s) \
         title word(species_names, s + 1)
  unset label 3
  set format x "%g"
  set xlabel "impact angle (deg from 6 o'clock, + on the rising side)"
  set ylabel "impacts per s (slice)"
  plot for [s = 0:nspecies-1] datafile using (mid(0)):(column(6 + 2 * s)) with histeps lw 2.5 lc rgb species_col(s) \
         title word(species_names, s + 1)
  unset multiplot
  set output
}
