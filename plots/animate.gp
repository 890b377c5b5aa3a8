# animate.gp - the charge tumbling in the mill, liner coloured by wear rate (or by shear
# work), as an animated GIF for teaching. `millwear animate` writes the inputs and runs it.
# Inputs (gnuplot string variables, set with -e or by millwear):
#   datafile  whitespace-separated frames; frame i (0-based) is two data blocks:
#               index 2i     disks:  x_m y_m radius_m species        (world frame)
#               index 2i+1   liner:  x_m y_m value   (closed path of the mill boundary;
#                                    value of the edge starting at the vertex)
#             blocks separated by two blank lines
#   metafile  gnuplot commands setting: nframes, R (mill radius, m), cbmax, cblabel and
#             array ftitle[nframes] (one title per frame); nspecies and the arrays
#             sp_rgb[nspecies] (colours as numbers) and sp_name[nspecies]
#   outbase   output path without extension; writes outbase.gif
#   delay     frame delay in 1/100 s ["5"]
#   size      image size in pixels (square) ["640"]
#   frame     optional: draw only frame K (0-based) to outbase.png instead of the GIF
# By hand (after `millwear animate --keep-data`):
#   gnuplot -e "datafile='frames.dat'; metafile='frames_meta.gp'; outbase='mill'" plots/animate.gp
if (!exists("datafile") || !exists("metafile") || !exists("outbase")) {
  print "animate.gp: set datafile, metafile and outbase"; exit status 1
}
if (!exists("delay")) delay = "5"
if (!exists("size")) size = "640"
load metafile

# frame='K' draws only frame K (0-based) to outbase.png, to check a restyle quickly.
if (exists("frame")) {
  set terminal png size int(size), int(size) noenhanced font 'Sans,10'
  set output outbase . ".png"
  first = int(frame); last = int(frame)
} else {
  set terminal gif animate delay int(delay) size int(size), int(size) noenhanced font 'Sans,10'
  set output outbase . ".gif"
  first = 0; last = nframes - 1
}

# Species colours and names from the meta file (sp_rgb, sp_name: as the snapshot figures).
species_rgb(s) = (s >= 0 && s < nspecies) ? sp_rgb[s + 1] : 0x7d7d7d
set palette defined (0 '#2c7bb6', 0.25 '#abd9e9', 0.5 '#ffffbf', 0.75 '#fdae61', 1 '#d7191c')
set cbrange [0 : cbmax]
set cblabel cblabel
set colorbox vertical user origin screen 0.86, screen 0.15 size screen 0.03, screen 0.6
set size ratio -1
set lmargin at screen 0.11
set rmargin at screen 0.82
set xrange [-1.05 * R : 1.05 * R]
set yrange [-1.05 * R : 1.05 * R]
set xlabel "x (m)"
set ylabel "y (m)"
set style fill solid 1.0 noborder
set key at screen 0.46, screen 0.02 center bottom horizontal
unset grid

do for [i = first : last] {
  set title ftitle[i + 1]
  plot datafile index (2 * i) using 1:2:3:(species_rgb(int($4))) with circles lc rgb variable notitle, \
       datafile index (2 * i + 1) using 1:2:3 with lines lw 4 lc palette notitle, \
       for [s = 0:nspecies-1] keyentry with circles fs solid 1.0 lc rgb sprintf("#%06x", sp_rgb[s + 1]) title sp_name[s + 1]
}
set output
