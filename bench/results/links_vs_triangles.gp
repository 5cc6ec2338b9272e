set terminal pngcairo size 1100,420 font 'sans,10'
set output "links_vs_triangles.png.tmp-22492.png"
set grid
set key outside right top
set title "Links/s vs scene size (2 threads; tags on every row, antenna poses along the middle aisle)"
set xlabel "triangles"
set ylabel "links / s"
set logscale x
set logscale y
plot "links_vs_triangles.dat" index 0 using 1:2 with linespoints title "los", "links_vs_triangles.dat" index 1 using 1:2 with linespoints title "los packets", "links_vs_triangles.dat" index 2 using 1:2 with linespoints title "los+blocked", "links_vs_triangles.dat" index 3 using 1:2 with linespoints title "single-bounce", "links_vs_triangles.dat" index 4 using 1:2 with linespoints title "single-bounce rays=4096"
