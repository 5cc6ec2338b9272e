set terminal pngcairo size 1000,500
set output "/work/sp/test_out/real_vs_sim.png"
set title "AdaRF D1 test: mean localization error of ok results, real vs simulated"
set ylabel "mean error (mm)"
set style data histograms
set style fill solid 0.8
set key outside below horizontal
set logscale y
set grid ytics
plot "/work/sp/test_out/real_vs_sim.dat" using 2:xtic(1) title columnheader(2), "/work/sp/test_out/real_vs_sim.dat" using 3:xtic(1) title columnheader(3), "/work/sp/test_out/real_vs_sim.dat" using 4:xtic(1) title columnheader(4), "/work/sp/test_out/real_vs_sim.dat" using 5:xtic(1) title columnheader(5), "/work/sp/test_out/real_vs_sim.dat" using 6:xtic(1) title columnheader(6)
