# trajectories.gp - the trajectory envelope (`millwear charge`): the flight paths of the disks
# the lifters threw in the window's last half revolution, coloured by species, each landed
# path ending in a dot at its first impact, over the charge and the liner at the window's end
# (the snapshot; paths still in the air end at their disk). Toe and shoulder marked, the sense
# of rotation drawn (docs/trajectories.md).
# Inputs (see common.gp for the shared variables):
#   design                          the scene's name
#   species_names, species_colours  one word per species index: its name and colour "#rrggbb"
#                                   [species_0, ...; grey]
#   toe_deg, shoulder_deg, centrifuged, turning   as snapshot.gp takes them [none]
#   OUT/trajectories_DESIGN.csv     path, disk, species, landed, end, x_m, y_m: one block of
#                                   rows per path, a blank line between blocks
#   OUT/snapshot_DESIGN.csv         x_m, y_m, radius_m, species
#   OUT/liner_DESIGN.csv            x1_m, y1_m, x2_m, y2_m
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/trajectories_DESIGN).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("design")) { print "trajectories.gp: set design='NAME'"; exit status 1 }
if (!exists("outbase")) outbase = datadir . "/plots/trajectories_" . design
pathfile = datadir . "/trajectories_" . design . ".csv"
snapfile = datadir . "/snapshot_" . design . ".csv"
linerfile = datadir . "/liner_" . design . ".csv"

if (exists("species_names")) { nspecies = words(species_names) } else { stats snapfile using "species" nooutput; nspecies = int(STATS_max) + 1 }
if (!exists("species_names")) { species_names = ""; do for [s = 0:nspecies-1] { species_names = species_names . sprintf(" species_%d", s) } }
if (!exists("species_colours")) { species_colours = ""; do for [s = 0:nspecies-1] { species_colours = species_colours . " #8f8f7a" } }
hexdigit(c) = strstrt("0123456789abcdef", c) - 1
hexnum(c) = sum [i = 2:7] hexdigit(c[i:i]) * 16**(7 - i)
species_col(s) = word(species_colours, s + 1)
array species_rgb[nspecies]
do for [s = 0:nspecies-1] { species_rgb[s + 1] = hexnum(species_col(s)) }
# The paths in a darker shade of the species' colour, so they stand out over the charge.
darker(c) = (int(((c >> 16) & 255) * 0.6) << 16) + (int(((c >> 8) & 255) * 0.6) << 8) + int((c & 255) * 0.6)
path_rgb(s) = darker(species_rgb[int(s) + 1])

stats linerfile using (sqrt(column("x1_m")**2 + column("y1_m")**2)) nooutput
R = STATS_max

set size ratio -1
set offsets 0, 0, 0, 0
set xrange [-1.12 * R : 1.12 * R]
set yrange [-1.12 * R : 1.12 * R]
set xlabel "x (m)"
set ylabel "y (m)"
unset grid
set key at screen 0.5, screen 0.015 center bottom horizontal
set bmargin 6

have_marks = exists("turning") ? 1 : 0
sense = have_marks ? (real(turning) < 0 ? -1 : 1) : 1
mark_x(a, r) = r * sin(sense * a * pi / 180)
mark_y(a, r) = -r * cos(sense * a * pi / 180)
if (have_marks) {
  if (int(real(centrifuged)) == 1) {
    set label 11 "centrifuged: no toe or shoulder" at 0, 1.06 * R center front font ",11"
  } else {
    set arrow 11 from mark_x(real(toe_deg), 1.10 * R), mark_y(real(toe_deg), 1.10 * R) \
              to mark_x(real(toe_deg), 0.96 * R), mark_y(real(toe_deg), 0.96 * R) head filled lw 2 lc rgb '#000000' front
    set label 11 "toe" at mark_x(real(toe_deg), 1.13 * R), mark_y(real(toe_deg), 1.13 * R) center front
    set arrow 12 from mark_x(real(shoulder_deg), 1.10 * R), mark_y(real(shoulder_deg), 1.10 * R) \
              to mark_x(real(shoulder_deg), 0.96 * R), mark_y(real(shoulder_deg), 0.96 * R) head filled lw 2 lc rgb '#000000' front
    set label 12 "shoulder" at mark_x(real(shoulder_deg), 1.13 * R), mark_y(real(shoulder_deg), 1.13 * R) center front
  }
  if (int(real(turning)) != 0) {
    a0 = 60; a1 = 120
    set object 15 circle at 0, 0 size 1.06 * R arc [a0 : a1] nowedge fs empty border lc rgb '#333333' front lw 2
    if (int(real(turning)) > 0) {
      set arrow 16 from 1.06 * R * cos(a1 * pi / 180 - 0.12), 1.06 * R * sin(a1 * pi / 180 - 0.12) \
                to 1.06 * R * cos(a1 * pi / 180), 1.06 * R * sin(a1 * pi / 180) head filled size screen 0.025, 25 lc rgb '#333333' front
    } else {
      set arrow 16 from 1.06 * R * cos(a0 * pi / 180 + 0.12), 1.06 * R * sin(a0 * pi / 180 + 0.12) \
                to 1.06 * R * cos(a0 * pi / 180), 1.06 * R * sin(a0 * pi / 180) head filled size screen 0.025, 25 lc rgb '#333333' front
    }
    set label 17 (int(real(turning)) > 0 ? "turning counter-clockwise" : "turning clockwise") at 0, 1.09 * R center front font ",10"
  }
}

do for [fmt in formats] {
  eval term_cmd(fmt, 900, 880)
  set output outbase . "." . fmt
  set title "Flight paths from the lifters, last half revolution: " . design font ",13"
  plot snapfile using "x_m":"y_m":"radius_m":(species_rgb[int(column("species")) + 1]) \
         with circles fs transparent solid 0.3 noborder lc rgb variable notitle, \
       linerfile using "x1_m":"y1_m":(column("x2_m") - column("x1_m")):(column("y2_m") - column("y1_m")) \
         with vectors nohead lw 2.5 lc rgb '#222222' notitle, \
       pathfile using "x_m":"y_m":(path_rgb(column("species"))) with lines lw 1 lc rgb variable notitle, \
       pathfile using "x_m":(column("end") > 0 ? column("y_m") : NaN):(path_rgb(column("species"))) \
         with points pt 7 ps 0.5 lc rgb variable notitle, \
       for [s = 0:nspecies-1] keyentry with lines lw 3 lc rgb path_rgb(s) title word(species_names, s + 1)
  set output
}
