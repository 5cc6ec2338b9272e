set terminal pngcairo size 1100,420 font 'sans,10'
set output "links_vs_tags.png.tmp-31442.png"
set grid
set key outside right top
set title "Links/s vs tags per antenna pose (1 M-triangle warehouse, 2 threads)"
set xlabel "tags"
set ylabel "links / s"
set logscale x
set logscale y
plot "links_vs_tags.dat" index 0 using 1:2 with linespoints title "los", "links_vs_tags.dat" index 1 using 1:2 with linespoints title "los packets", "links_vs_tags.dat" index 2 using 1:2 with linespoints title "los+blocked", "links_vs_tags.dat" index 3 using 1:2 with linespoints title "single-bounce", "links_vs_tags.dat" index 4 using 1:2 with linespoints title "single-bounce rays=4096"
