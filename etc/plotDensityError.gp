# Sluice: plot the density error over time from a densityError.dat, as the
# densityError function object or the densityError utility write it:
#
#   gnuplot -c etc/plotDensityError.gp <case>/postProcessing/<name>/<startTime>/densityError.dat [out.png]
#
# Columns (see the file's header): 1 Time, 2 average, 3 maximum (compression
# max(rho - rho0, 0) / rho0 in percent), 4 averageSigned, 5 minimumSigned,
# 6 maximumSigned, then the percentiles.  The PNG defaults to the .dat name
# with .png; pngcairo is used when gnuplot has it, else png.
if (ARGC < 1) {
    print "usage: gnuplot -c plotDensityError.gp <densityError.dat> [out.png]"
    exit status 1
}
dat = ARG1
png = ARGC >= 2 ? ARG2 : (strstrt(dat, ".dat") > 0 ? dat[1:strstrt(dat, ".dat") - 1] . ".png" : dat . ".png")
if (strstrt(GPVAL_TERMINALS, "pngcairo") > 0) {
    set terminal pngcairo size 1000,600 noenhanced
} else {
    set terminal png size 1000,600 noenhanced
}
set output png
set title "Density error: compression max(rho - rho0, 0) / rho0 -- " . dat
set xlabel "time (s)"
set ylabel "density error (% of rho0)"
set grid
set key below
plot dat using 1:2 with linespoints pt 7 ps 0.5 title "average", \
     dat using 1:3 with linespoints pt 5 ps 0.5 title "maximum"
print png
