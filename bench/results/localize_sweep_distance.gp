set terminal pngcairo size 1100,840 font 'sans,10'
set output "localize_sweep_distance.png"
set grid
set key outside right top
set multiplot layout 2,1
set title "Median error of ok results vs tag distance from the path (m)"
set xlabel "tag distance from the path (m)"
set ylabel "median error (mm)"
unset logscale x
set logscale y
plot "localize_sweep_distance.dat" index 0 using 1:2 with linespoints title "hyperbolic", "localize_sweep_distance.dat" index 1 using 1:2 with linespoints title "nlls", "localize_sweep_distance.dat" index 2 using 1:2 with linespoints title "sar"
set title "Failure rate (status failed) vs tag distance from the path (m)"
set xlabel "tag distance from the path (m)"
set ylabel "failed fraction"
unset logscale x
unset logscale y
plot "localize_sweep_distance.dat" index 3 using 1:2 with linespoints title "hyperbolic", "localize_sweep_distance.dat" index 4 using 1:2 with linespoints title "nlls", "localize_sweep_distance.dat" index 5 using 1:2 with linespoints title "sar"
unset multiplot
