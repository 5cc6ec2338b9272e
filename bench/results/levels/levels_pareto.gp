set terminal pngcairo size 1100,840 font 'sans,10'
set output "levels_pareto.png.tmp-10222.png"
set grid
set key outside right top
set multiplot layout 2,1
set title "Round-trip phase error vs cost, against full (exhaustive); links readable in both"
set xlabel "µs per link (1 thread)"
set ylabel "phase p95 (rad)"
set logscale x
set logscale y
plot "levels_pareto.dat" index 0 using 1:2 with linespoints title "paper phase p95 (rad)", "levels_pareto.dat" index 0 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle
set title "RSSI error vs cost, against full (exhaustive)"
set xlabel "µs per link (1 thread)"
set ylabel "RSSI p95 (dB)"
set logscale x
set logscale y
plot "levels_pareto.dat" index 1 using 1:2 with linespoints title "paper RSSI p95 (dB)", "levels_pareto.dat" index 1 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle
unset multiplot
