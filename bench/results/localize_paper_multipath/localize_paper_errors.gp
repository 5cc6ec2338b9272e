set terminal pngcairo size 1100,420 font 'sans,10'
set output "localize_paper_errors.png"
set grid
set key outside right top
set title "Estimation error per tag, seed 1 (truth-side prior)"
set xlabel "tag"
set ylabel "error (mm)"
unset logscale x
unset logscale y
plot "localize_paper_errors.dat" index 0 using 1:2 with linespoints title "hyperbolic", "localize_paper_errors.dat" index 1 using 1:2 with linespoints title "nlls", "localize_paper_errors.dat" index 2 using 1:2 with linespoints title "sar", "localize_paper_errors.dat" index 3 using 1:2 with lines title "paper mean (15 mm)"
