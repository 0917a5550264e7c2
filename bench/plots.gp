# Plots in docs/images (run by scripts/plots; the README shows one): worst-error maps over (x, y) slices of ref6's `paper` workspace and the
# worst error along config/trajectory_example.yaml with its certified bounds. Data from <build>/bench/plot_data.
# Usage: gnuplot -e "datadir='DIR'; outdir='docs/images'" bench/plots.gp
if (!exists("datadir")) datadir = "."
if (!exists("outdir")) outdir = "."
load datadir."/bounds.gp"

set terminal pngcairo size 1360,560 enhanced font "Sans,11"
set palette defined (0 "#000080", 1 "#0050ff", 2 "#00c0c0", 3 "#60d040", 4 "#ffe000", 5 "#ff7000", 6 "#c00000")
set xlabel "x [mm]"
set ylabel "y [mm]"
set xrange [-150:150]
set yrange [-150:150]
set size ratio -1
set tics out nomirror
set cbtics out
set key off

# One heat map per component: left z = mid, angles 0; right z = max, all angles +15 deg.
do for [c in "3 8"] {
  col = int(c)
  name = (col == 3) ? "dx" : "rz"
  what = (col == 3) ? "worst position error dx" : "worst yaw error rz"
  unit = (col == 3) ? "{/Symbol m}m" : "mrad"
  set output outdir."/error_map_".name.".png"
  set multiplot layout 1,2 title sprintf("Reference robot ref6, workspace 'paper': %s [%s] at points of (x, y) slices", what, unit) font "Sans,13"
  set cblabel sprintf("%s [%s]", name, unit) offset 1.2,0
  set title slice_mid
  plot datadir."/map_mid.dat" using 1:2:col with image
  set title slice_tilt
  plot datadir."/map_tilt.dat" using 1:2:col with image
  unset multiplot
  unset output
}

# Worst error along the trajectory (points, 2000 samples) and the certified bounds of its maximum (dashed).
reset
set terminal pngcairo size 1100,800 enhanced font "Sans,11"
set output outdir."/trajectory_error.png"
set tics out nomirror
set grid lc rgb "#dddddd"
set key outside right top Left reverse samplen 2
set xlabel "t [s]"
set lmargin at screen 0.08
set rmargin at screen 0.76
# waypoint times (segment boundaries) as dotted vertical lines
do for [w in waypoint_times] { set arrow from w+0, graph 0 to w+0, graph 1 nohead dt 3 lc rgb "#888888" }
set multiplot layout 2,1 title "Worst error along ".trajectory_name."\nlines: f_k at 2000 points; dotted: waypoints; dashed: certified max over the whole trajectory (".certified.")" font "Sans,12"
set ylabel "position error [{/Symbol m}m]"
set yrange [0:*]
plot datadir."/trajectory.dat" using 1:2 with lines lw 2 lc 1 title "dx", \
     "" using 1:3 with lines lw 2 lc 2 title "dy", \
     "" using 1:4 with lines lw 2 lc 3 title "dz", \
     up1 with lines dt 2 lw 1.5 lc 1 title sprintf("max dx <= %.2f", up1), \
     up2 with lines dt 2 lw 1.5 lc 2 title sprintf("max dy <= %.2f", up2), \
     up3 with lines dt 2 lw 1.5 lc 3 title sprintf("max dz <= %.2f", up3)
set ylabel "rotation error [mrad]"
plot datadir."/trajectory.dat" using 1:5 with lines lw 2 lc 4 title "rx", \
     "" using 1:6 with lines lw 2 lc 6 title "ry", \
     "" using 1:7 with lines lw 2 lc 7 title "rz", \
     up4 with lines dt 2 lw 1.5 lc 4 title sprintf("max rx <= %.3f", up4), \
     up5 with lines dt 2 lw 1.5 lc 6 title sprintf("max ry <= %.3f", up5), \
     up6 with lines dt 2 lw 1.5 lc 7 title sprintf("max rz <= %.3f", up6)
unset multiplot
unset output
