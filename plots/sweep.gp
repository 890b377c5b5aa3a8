# sweep.gp - `millwear sweep`: the charge's figures against the varied scene key, with error
# bars of one standard error (batch means over each point's measured window).
# Inputs (see common.gp for the shared variables):
#   OUT/sweep.csv   columns used: value, power_kW, specific_power_kW_per_t, toe_deg,
#                   shoulder_deg, collision_power_kW, liner_shear_power_kW, their *_sem, lost_disks,
#                   centrifuged (toe and shoulder read "centrifuged" there: marked at 0 deg)
#   figure          which figure: power | toe_shoulder | collision_shear      [power]
#   key             the varied key, for the x label                            [value]
# Output: outbase.png, outbase.svg (default outbase = OUT/plots/sweep_FIGURE).
# A point that lost a disk is left out (its figures are suspect; sweep.csv names it).
if (!exists("scriptdir")) { scriptdir = "."; do for [i = strlen(ARG0):1:-1] { if (ARG0[i:i] eq "/") { scriptdir = ARG0[1:i-1]; break } } }
load scriptdir . "/common.gp"
if (!exists("figure")) figure = "power"
if (!exists("key")) key = "value"
if (!exists("outbase")) outbase = datadir . "/plots/sweep_" . figure
table = datadir . "/sweep.csv"

xlabel = (key eq "mill.speed") ? "Mill speed (fraction of critical)" : \
         (key eq "mill.speed_rpm") ? "Mill speed (rpm)" : \
         (key eq "charge.filling") ? "Filling (fraction of the mill area)" : \
         (key eq "charge.ball_filling") ? "Ball filling (fraction of the mill area)" : key
ok(c) = (column("lost_disks") > 0) ? NaN : column(c)

do for [fmt in formats] {
  if (figure eq "power") {
    eval term_cmd(fmt, 900, 900)
    set output outbase . "." . fmt
    set multiplot layout 2,1 title "Power draw against " . key . " (error bars: one standard error)" font ",13"
    set xlabel xlabel
    set ylabel "Power per mill (kW)"
    set key top left
    plot table using "value":(ok("power_kW")):"power_kW_sem" with yerrorlines ls 1 title "drive power"
    set ylabel "Specific power (kW per t of charge)"
    plot table using "value":(ok("specific_power_kW_per_t")):"specific_power_kW_per_t_sem" \
         with yerrorlines ls 2 title "power / charge mass"
    unset multiplot
  }
  if (figure eq "toe_shoulder") {
    eval term_cmd(fmt, 900, 600)
    set output outbase . "." . fmt
    set title "Toe and shoulder against " . key . " (error bars: one standard error)" font ",13"
    set xlabel xlabel
    set ylabel "Angle from 6 o'clock (deg, + on the rising side)"
    set key bottom center
    set yrange [-190:190]
    set ytics 45
    plot table using "value":(ok("shoulder_deg")):"shoulder_deg_sem" with yerrorlines ls 1 title "shoulder", \
         table using "value":(ok("toe_deg")):"toe_deg_sem" with yerrorlines ls 2 title "toe", \
         table using "value":(column("centrifuged") > 0 ? 0 : NaN) with points pt 4 ps 2.5 lc rgb '#000000' \
           title "centrifuged: the charge covers the shell, no toe or shoulder"
    unset yrange
  }
  if (figure eq "collision_shear") {
    eval term_cmd(fmt, 900, 600)
    set output outbase . "." . fmt
    set title "Collision and liner shear power against " . key . " (error bars: one standard error)" font ",13"
    set xlabel xlabel
    set ylabel "Power per mill (kW)"
    set key top left
    plot table using "value":(ok("collision_power_kW")):"collision_power_kW_sem" with yerrorlines ls 1 \
           title "particle-particle collisions", \
         table using "value":(ok("liner_shear_power_kW")):"liner_shear_power_kW_sem" with yerrorlines ls 2 \
           title "shear on the liner (Archard work rate)"
  }
  set output
}
