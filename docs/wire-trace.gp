# Plot the beads of samples/wire.fl from a --trace CSV:
#   build/src/flitter run --frames 300 --trace-file wire.csv samples/wire.fl
#   gnuplot docs/wire-trace.gp        (writes wire-trace.png)
set terminal pngcairo size 800,360
set output 'wire-trace.png'
set datafile separator ','
set xlabel 'time (s)'
set ylabel 'position x'
set key outside right title 'bead'
# one line per particle id (column 4); column 2 is time, 6 is x
plot for [i=0:9] sprintf("< awk -F, '$4 == \"%d\"' wire.csv", i) using 2:6 with lines lw 1.5 title sprintf('%d', i)
