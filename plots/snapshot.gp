# snapshot.gp - one instant of the charge in the mill: disks drawn to scale, coloured by
# species, the liner (shell and lifters) coloured by its local wear rate (a run) or shear
# power (a charge), the toe, shoulder and centre of mass marked, the sense of rotation drawn.
# Inputs (see common.gp for the shared variables):
#   design                      the design to draw (one figure per design)
#   cbmax                       optional upper end of the colour scale (the caller sets it to
#                               the 95th percentile of every design's edges, so snapshots of
#                               several designs share one scale; edges above it take the top
#                               colour)
#   lvalue, cblabel             the liner column to colour by and its label
#                               [wear_rate_mm_per_1000h, "Liner wear rate (mm per 1000 h)"]
#   species_names, species_colours  one word per species index: its name ("-" for none) and
#                               its colour "#rrggbb" [species_0, ...; grey]
#   toe_deg, shoulder_deg, centrifuged, com_x_m, com_y_m, turning
#                               optional marks: angles from 6 o'clock, + toward the rising
#                               side; turning +1 counter-clockwise, -1 clockwise, 0 at rest
#   OUT/snapshot_DESIGN.csv     columns x_m, y_m, radius_m, species (0, 1, ...)
#   OUT/liner_DESIGN.csv        columns x1_m, y1_m, x2_m, y2_m and the lvalue column
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/snapshot_DESIGN).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("design")) { print "snapshot.gp: set design='NAME'"; exit status 1 }
if (!exists("outbase")) outbase = datadir . "/plots/snapshot_" . design
if (!exists("lvalue")) lvalue = "wear_rate_mm_per_1000h"
if (!exists("cblabel")) cblabel = "Liner wear rate (mm per 1000 h)"
snapfile = datadir . "/snapshot_" . design . ".csv"
linerfile = datadir . "/liner_" . design . ".csv"

stats snapfile using "species" nooutput
nspecies = int(STATS_max) + 1
if (!exists("species_names")) { species_names = ""; do for [s = 0:nspecies-1] { species_names = species_names . sprintf(" species_%d", s) } }
if (!exists("species_colours")) { species_colours = ""; do for [s = 0:nspecies-1] { species_colours = species_colours . " #8f8f7a" } }
stats linerfile using lvalue nooutput
wmax = STATS_max > 0 ? STATS_max : 1
if (exists("cbmax")) { if (real(cbmax) > 0) { wmax = real(cbmax) } }
stats linerfile using (sqrt(column("x1_m")**2 + column("y1_m")**2)) nooutput
R = STATS_max

# Species colours as numbers for `lc rgb variable`, one per species index.
hexdigit(c) = strstrt("0123456789abcdef", c) - 1
hexnum(c) = sum [i = 2:7] hexdigit(c[i:i]) * 16**(7 - i)
species_col(s) = word(species_colours, s + 1)
array species_rgb[nspecies]
do for [s = 0:nspecies-1] { species_rgb[s + 1] = hexnum(species_col(s)) }

set palette defined (0 '#2c7bb6', 0.25 '#abd9e9', 0.5 '#ffffbf', 0.75 '#fdae61', 1 '#d7191c')
set cbrange [0 : wmax]
set cblabel cblabel . "; scale to the 95th percentile" offset 1.5, 0
set colorbox vertical default
set size ratio -1
set offsets 0, 0, 0, 0
set xrange [-1.12 * R : 1.12 * R]
set yrange [-1.12 * R : 1.12 * R]
set style fill transparent solid 0.75 noborder
set xlabel "x (m)"
set ylabel "y (m)"
unset grid
set key at screen 0.45, screen 0.015 center bottom horizontal
set bmargin 6
set rmargin 16

# Marks: a point at angle a (deg from 6 o'clock, + toward the rising side) just outside
# the shell. The rising side is counter-clockwise for a mill turning counter-clockwise.
have_marks = exists("turning") ? 1 : 0
sense = have_marks ? (real(turning) < 0 ? -1 : 1) : 1
mark_x(a, r) = r * sin(sense * a * pi / 180)
mark_y(a, r) = -r * cos(sense * a * pi / 180)
if (have_marks) {
  if (int(real(centrifuged)) == 1) {
    set label 11 "centrifuged: no toe or shoulder" at 0, 1.06 * R center front font ",11"
  } else {
    # NaN (no disk reached the shell band) is not equal to itself: then no toe or shoulder.
    if (real(toe_deg) == real(toe_deg) && real(shoulder_deg) == real(shoulder_deg)) {
      set arrow 11 from mark_x(real(toe_deg), 1.10 * R), mark_y(real(toe_deg), 1.10 * R) \
                to mark_x(real(toe_deg), 0.96 * R), mark_y(real(toe_deg), 0.96 * R) head filled lw 2 lc rgb '#000000' front
      set label 11 "toe" at mark_x(real(toe_deg), 1.13 * R), mark_y(real(toe_deg), 1.13 * R) center front
      set arrow 12 from mark_x(real(shoulder_deg), 1.10 * R), mark_y(real(shoulder_deg), 1.10 * R) \
                to mark_x(real(shoulder_deg), 0.96 * R), mark_y(real(shoulder_deg), 0.96 * R) head filled lw 2 lc rgb '#000000' front
      set label 12 "shoulder" at mark_x(real(shoulder_deg), 1.13 * R), mark_y(real(shoulder_deg), 1.13 * R) center front
    }
  }
  set label 13 "+" at real(com_x_m), real(com_y_m) center front font ",16" tc rgb '#000000'
  set label 14 "centre of mass" at real(com_x_m), real(com_y_m) offset 0, -1 center front font ",9"
  # The sense of rotation: an arc over the top of the mill with its head where it turns to.
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
  eval term_cmd(fmt, 900, 860)
  set output outbase . "." . fmt
  set title "Charge snapshot: " . design font ",13"
  plot snapfile using "x_m":"y_m":"radius_m":(species_rgb[int(column("species")) + 1]) \
         with circles lc rgb variable notitle, \
       linerfile using "x1_m":"y1_m":(column("x2_m") - column("x1_m")):(column("y2_m") - column("y1_m")):(column(lvalue)) \
         with vectors nohead lw 4 lc palette notitle, \
       for [s = 0:nspecies-1] keyentry with circles fs solid 0.75 lc rgb species_col(s) \
         title (word(species_names, s + 1) eq "-" ? "" : word(species_names, s + 1))
  set output
}
