set terminal pngcairo size 1200,2080 font 'sans,10'
set output "accuracy_pareto.png.tmp-28324.png"
set grid
set key outside right top
set multiplot layout 4,1
set title "paper: p95 round-trip phase error (links readable in both) vs time per link; reference: single-bounce exhaustive, all paths; front: settings with <= 5 % flips"
set xlabel "time per link (us, all threads)"
set ylabel "p95 phase error (rad)"
set logscale x
set logscale y
plot "accuracy_pareto.dat" index 0 using 1:2 with points pt 7 ps 1.2 title "settings", "accuracy_pareto.dat" index 0 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle, "accuracy_pareto.dat" index 1 using 1:2 with linespoints lw 2 title "Pareto front"
set title "paper: the same against full (double reflections + UTD diffraction, all paths), 4000 links (200 tags x 20 poses); flips: links readable in one only; front: settings with <= 5 % flips"
set xlabel "time per link (us, all threads)"
set ylabel "p95 phase error (rad)"
set logscale x
set logscale y
plot "accuracy_pareto.dat" index 2 using 1:2 with points pt 7 ps 1.2 title "settings", "accuracy_pareto.dat" index 2 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle, "accuracy_pareto.dat" index 3 using 1:2 with linespoints lw 2 title "Pareto front"
set title "w1m: p95 round-trip phase error (links readable in both) vs time per link; reference: single-bounce exhaustive, all paths; front: settings with <= 5 % flips"
set xlabel "time per link (us, all threads)"
set ylabel "p95 phase error (rad)"
set logscale x
set logscale y
plot "accuracy_pareto.dat" index 4 using 1:2 with points pt 7 ps 1.2 title "settings", "accuracy_pareto.dat" index 4 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle, "accuracy_pareto.dat" index 5 using 1:2 with linespoints lw 2 title "Pareto front"
set title "w1m: the same against full (double reflections + UTD diffraction, all paths), 200 links (50 tags x 4 poses); flips: links readable in one only; front: settings with <= 5 % flips"
set xlabel "time per link (us, all threads)"
set ylabel "p95 phase error (rad)"
set logscale x
set logscale y
plot "accuracy_pareto.dat" index 6 using 1:2 with points pt 7 ps 1.2 title "settings", "accuracy_pareto.dat" index 6 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle, "accuracy_pareto.dat" index 7 using 1:2 with linespoints lw 2 title "Pareto front"
unset multiplot
