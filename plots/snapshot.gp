# snapshot.gp - one instant of the charge in the mill: disks drawn to scale, coloured by
# species, and the liner (shell and lifters) coloured by its local wear rate.
# Inputs (see common.gp for the shared variables):
#   design                      the design to draw (one figure per design)
#   cbmax                       optional upper end of the wear-rate colour scale, so that
#                               snapshots of several designs share one scale
#   OUT/snapshot_DESIGN.csv     columns x_m, y_m, radius_m, species (species: 0, 1, ...)
#   OUT/liner_DESIGN.csv        columns x1_m, y1_m, x2_m, y2_m, wear_rate_mm_per_1000h
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/snapshot_DESIGN).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("design")) { print "snapshot.gp: set design='NAME'"; exit status 1 }
if (!exists("outbase")) outbase = datadir . "/plots/snapshot_" . design
snapfile = datadir . "/snapshot_" . design . ".csv"
linerfile = datadir . "/liner_" . design . ".csv"

stats snapfile using "species" nooutput
nspecies = int(STATS_max) + 1
stats linerfile using "wear_rate_mm_per_1000h" nooutput
wmax = STATS_max > 0 ? STATS_max : 1
if (exists("cbmax")) { if (real(cbmax) > 0) { wmax = real(cbmax) } }

# Species colours (muted, so the wear colours stand out): grey rock, steel blue balls, ...
species_rgb(s) = (s == 0) ? 0x9a8f80 : (s == 1) ? 0x4f6d8f : (s == 2) ? 0xb07d48 : \
                 (s == 3) ? 0x6b8e5a : 0x7d7d7d
set palette defined (0 '#2c7bb6', 0.25 '#abd9e9', 0.5 '#ffffbf', 0.75 '#fdae61', 1 '#d7191c')
set cbrange [0 : wmax]
set cblabel "Liner wear rate (mm per 1000 h)"
set colorbox vertical default
set cblabel offset 1.5, 0
set size ratio -1
set offsets 0, 0, 0, 0
set autoscale fix
set style fill transparent solid 0.75 noborder
set xlabel "x (m)"
set ylabel "y (m)"
unset grid
set key at screen 0.45, screen 0.015 center bottom horizontal
set bmargin 6
set rmargin 14

do for [fmt in formats] {
  eval term_cmd(fmt, 900, 820)
  set output outbase . "." . fmt
  set title "Charge snapshot and liner wear rate: " . design font ",13"
  plot snapfile using "x_m":"y_m":"radius_m":(species_rgb(int(column("species")))) \
         with circles lc rgb variable notitle, \
       linerfile using "x1_m":"y1_m":(column("x2_m") - column("x1_m")):(column("y2_m") - column("y1_m")):"wear_rate_mm_per_1000h" \
         with vectors nohead lw 4 lc palette notitle, \
       for [s = 0:nspecies-1] keyentry with circles fs solid 0.75 lc rgb species_rgb(s) \
         title sprintf("species %d", s)
  set output
}
