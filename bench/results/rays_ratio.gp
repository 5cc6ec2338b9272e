set terminal pngcairo size 1100,420 font 'sans,10'
set output "rays_ratio.png"
set grid
set key outside right top
set title "Ray throughput relative to a raw Embree loop on the same rays"
set xlabel "scene triangles"
set ylabel "ratio"
set logscale x
unset logscale y
plot "rays_ratio.dat" index 0 using 1:2 with linespoints title "occluded: ours / raw rtcOccluded1 (1 thread)", "rays_ratio.dat" index 0 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle, "rays_ratio.dat" index 1 using 1:2 with linespoints title "occluded: ours / raw rtcOccluded1 (2 threads)", "rays_ratio.dat" index 1 using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle, "rays_ratio.dat" index 2 using 1:2 with linespoints title "candidate search: ours / raw rtcIntersect1 (2 threads)", "rays_ratio.dat" index 3 using 1:2 with linespoints title "raw rtcOccluded16 / rtcOccluded1 (2 threads)"
