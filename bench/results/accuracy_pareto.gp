set terminal pngcairo size 1200,1120 font 'sans,10'
set output "accuracy_pareto.png"
set grid
set key outside right top
set multiplot layout 2,1
set title "paper: p95 round-trip phase error (links readable in both) vs time per link; reference: exhaustive, all paths"
set xlabel "time per link (us, all threads)"
set ylabel "p95 phase error (rad)"
set logscale x
set logscale y
plot "accuracy_pareto.dat" index 0 using 1:2 with points pt 7 ps 1.2 title "settings", "accuracy_pareto.dat" index 0 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle, "accuracy_pareto.dat" index 1 using 1:2 with linespoints lw 2 title "Pareto front"
set title "w1m: p95 round-trip phase error (links readable in both) vs time per link; reference: exhaustive, all paths"
set xlabel "time per link (us, all threads)"
set ylabel "p95 phase error (rad)"
set logscale x
set logscale y
plot "accuracy_pareto.dat" index 2 using 1:2 with points pt 7 ps 1.2 title "settings", "accuracy_pareto.dat" index 2 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle, "accuracy_pareto.dat" index 3 using 1:2 with linespoints lw 2 title "Pareto front"
unset multiplot
