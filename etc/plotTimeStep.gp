# The time step over time (the paper's Fig. 4) and the density error, from
# a case's per-step record (every session, joined by monitorCase), as a PNG:
#   monitorCase -case <case> -script etc/plotTimeStep.gp -png <file.png>
# (etc/plotTimeStep <case> does this).  monitorCase runs it as
#   gnuplot -c plotTimeStep.gp <table> <png> <title>
# with <table> the record as `monitorCase -print` writes it: columns Time
# deltaT iterations rhoErrAvg rhoErrMax vMax FMax shock wallTime
# controllerDeltaT ...
if (ARGC < 3) { print "usage: gnuplot -c plotTimeStep.gp <table> <png> <title>"; exit status 1 }
dat = ARG1
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
    set terminal pngcairo size 900,700 noenhanced
} else {
    set terminal png size 900,700 noenhanced
}
set output ARG2
# the case's name: the title up to its ':' (monitorCase adds the record's folders)
name = strstrt(ARG3, ":") > 0 ? ARG3[1:strstrt(ARG3, ":") - 1] : ARG3
set multiplot layout 2,1 title name.": time step and density error (Ihmsen et al. 2010, Fig. 4)"
set xlabel "t [s]"
set ylabel "deltaT [s]"
set format x "%g"
set format y "%g"
set grid
set key below
set lmargin 12
set rmargin 4
# at most ~7 x ticks, of 1, 2 or 5 times a power of ten, so labels never run together
stats dat using 1 nooutput
r = STATS_max - STATS_min
if (r > 0) { p = 10**floor(log10(r/7.0)); m = r/7.0/p; k = (m <= 1 ? 1 : (m <= 2 ? 2 : (m <= 5 ? 5 : 10))); tic = k*p; set xtics tic }
plot dat using 1:($8 == 0 ? $10 : 1/0) with lines lw 2 title "deltaT (controller)", \
     dat using 1:($8 != 0 ? $2 : 1/0) with points pt 7 ps 1.2 lc rgb "red" title "step discarded (shock)"
set ylabel "rho_err [%]"
plot dat using 1:4 with lines title "average", dat using 1:5 with lines title "maximum"
unset multiplot
