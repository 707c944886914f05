# The plots of the fieldcast-latency report, drawn from its plot data. fieldcast-latency runs
#   gnuplot -e "dir='REPORT/plots'; out='REPORT'; flights='a b c'; warps='hold rotation …'; e2e='stick host'; e2ePixels='stick host'" plots.gnuplot
# rates.dat and fields.dat hold one block per flight and warp (flight-major, warps in the order
# of `warps`); cost.dat one block per flight.

nf = words(flights)
nw = words(warps)
block(f, w) = (f - 1) * nw + (w - 1)
panelWidth = 420
# One colour per warp, in the order fieldcast-latency lists them (hold, rotation, quadratic,
# homography, mesh, range3d); grey for any further warp
colours = '#7f7f7f #e377c2 #1f77b4 #ff7f0e #2ca02c #d62728'
colour(w) = w <= words(colours) ? word(colours, w) : '#444444'

set terminal pngcairo size nf * panelWidth, 400 font ',9' linewidth 1.3 noenhanced
set grid lc rgb '#dddddd'
set key below horizontal font ',8' samplen 2

# PSNR against IG rate, one panel per flight
set output out . '/psnr_vs_rate.png'
set multiplot layout 1, nf title 'PSNR of the warped fields against the truth'
do for [f = 1:nf] {
  set title word(flights, f)
  set xlabel 'IG rate (Hz)'
  set ylabel 'PSNR (dB)'
  set logscale x
  set xtics (5, 10, 15, 20, 30, 60)
  plot for [w = 1:nw] dir . '/rates.dat' index block(f, w) using 1:3 with linespoints pt 7 ps 0.6 lc rgb colour(w) title word(warps, w)
}
unset multiplot
unset logscale x
set xtics autofreq

# Geometric error against frame age: every field of every rate, one panel per flight
set output out . '/error_vs_age.png'
set multiplot layout 1, nf title 'Mean geometric error of each field against the age of its frame'
do for [f = 1:nf] {
  set title word(flights, f)
  set xlabel 'frame age at display (ms)'
  set ylabel 'mean error (px)'
  set logscale y
  set yrange [0.001:*]
  plot for [w = 1:nw] dir . '/fields.dat' index block(f, w) using 1:($2 > 0.001 ? $2 : 0.001) with points pt 7 ps 0.25 lc rgb colour(w) title word(warps, w)
}
unset multiplot
unset yrange

# Cost against fidelity: one point per warp, one panel per flight
set output out . '/cost_vs_fidelity.png'
set multiplot layout 1, nf title 'Cost and fidelity per warp (IG at 10 Hz, or the slowest rate evaluated)'
do for [f = 1:nf] {
  set title word(flights, f)
  set xlabel 'warp cost per field, one core (ms)'
  set ylabel 'mean error (px)'
  set logscale xy
  set offsets graph 0.1, graph 0.25, graph 0.1, graph 0.1
  plot for [w = 1:nw] dir . '/cost.dat' index (f - 1) using (strcol(4) eq word(warps, w) ? $1 : NaN):($2 > 0.001 ? $2 : 0.001) \
         with points pt 7 ps 0.9 lc rgb colour(w) title word(warps, w), \
       '' index (f - 1) using 1:($2 > 0.001 ? $2 : 0.001):4 with labels offset char 0.8, char 0.6 left font ',8' notitle
}
unset multiplot

# Input → field latency in the running service: per input measured (`e2e`, e2e_INPUT.dat) a
# panel of histograms, the pose's and (when `e2ePixels` names the input) the pixels'
ne = words(e2e)
if (ne > 0) {
  set terminal pngcairo size ne * 480, 360 font ',9' linewidth 1.3 noenhanced
  set output out . '/e2e_latency.png'
  set multiplot layout 1, ne title 'Step input → first emitted field that shows it'
  unset logscale
  set offsets 0, 0, 0, 0
  set xlabel 'latency (ms)'
  set ylabel 'steps'
  set xrange [0:*]
  set yrange [0:*]
  set key top right
  set style fill solid 0.5 border
  binWidth = 1.0
  bin(x) = binWidth * floor(x / binWidth) + binWidth / 2
  set boxwidth binWidth absolute
  do for [i = 1:ne] {
    input = word(e2e, i)
    set title input
    data = dir . '/e2e_' . input . '.dat'
    if (strstrt(' ' . e2ePixels . ' ', ' ' . input . ' ') > 0) {
      plot data index 0 using (bin($1)):(1.0) smooth frequency with boxes lc rgb '#1f77b4' title 'pose', \
           '' index 1 using (bin($1)):(1.0) smooth frequency with boxes lc rgb '#d62728' fs transparent solid 0.4 title 'pixels'
    } else {
      plot data index 0 using (bin($1)):(1.0) smooth frequency with boxes lc rgb '#1f77b4' title 'pose'
    }
  }
  unset multiplot
}
