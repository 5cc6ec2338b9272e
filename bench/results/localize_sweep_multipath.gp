set terminal pngcairo size 1100,840 font 'sans,10'
set output "localize_sweep_multipath.png"
set grid
set key outside right top
set multiplot layout 2,1
set title "Median error of ok results vs metal wall behind the tag, distance (m)"
set xlabel "metal wall behind the tag, distance (m)"
set ylabel "median error (mm)"
set logscale x
set logscale y
plot "localize_sweep_multipath.dat" index 0 using 1:2 with linespoints title "hyperbolic", "localize_sweep_multipath.dat" index 1 using 1:2 with linespoints title "nlls", "localize_sweep_multipath.dat" index 2 using 1:2 with linespoints title "sar"
set title "Failure rate (status failed) vs metal wall behind the tag, distance (m)"
set xlabel "metal wall behind the tag, distance (m)"
set ylabel "failed fraction"
set logscale x
unset logscale y
plot "localize_sweep_multipath.dat" index 3 using 1:2 with linespoints title "hyperbolic", "localize_sweep_multipath.dat" index 4 using 1:2 with linespoints title "nlls", "localize_sweep_multipath.dat" index 5 using 1:2 with linespoints title "sar"
unset multiplot
