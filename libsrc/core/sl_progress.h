/*
 * sl_progress: one form of "where is my run" for everything long (the
 * solver, sweepCase, long mesh work): done of total, the rate smoothed over
 * the last ~10 s of wall time, and the time left at that rate.
 *
 * On a terminal the status is one line rewritten in place ("\r"), at most
 * a few times a second; elsewhere (a log file, a pipe) it is a plain line
 * every `period` seconds, so that `tail log.pcisph` answers the question
 * without flooding the log.  SLUICE_PROGRESS=off|line|plain overrides the
 * choice (tests use plain), SLUICE_PROGRESS_PERIOD=<s> the period.
 *
 * Debian has no C library for this (progress bars are packaged for Go,
 * Perl, Rust and Haskell only), hence this small module.
 */
#ifndef SL_PROGRESS_H
#define SL_PROGRESS_H

#include <stddef.h>
#include <stdio.h>

typedef enum { SL_PROGRESS_OFF, SL_PROGRESS_LINE, SL_PROGRESS_PLAIN } sl_progress_mode;

typedef struct sl_progress {
    FILE *out;
    sl_progress_mode mode;
    double period;            /* plain lines: seconds between them */
    double done0, total;      /* work at the start, and when finished */
    double wall0, last_print; /* wall clock (s) at the start and last print */
    double sample_wall, sample_done;
    double rate;  /* smoothed work per wall second; 0 until known */
    size_t shown; /* length of the line on the terminal */
} sl_progress;

/* Start: `done0` of `total` is done; plain lines every `period` s. */
void sl_progress_start(sl_progress *p, FILE *out, double done0, double total, double period);
/* Work `done` so far; prints when due, `what` (e.g. "t = 0.31 of 1 s") first. */
void sl_progress_update(sl_progress *p, double done, const char *what);
/* The last status, ended by a newline on a terminal (nothing in plain mode). */
void sl_progress_end(sl_progress *p);
/* Seconds left at the smoothed rate; < 0 while it is not known. */
double sl_progress_eta(const sl_progress *p, double done);
/* Seconds of wall time since sl_progress_start. */
double sl_progress_elapsed(const sl_progress *p);
/* "45 s", "3 min 05 s", "2 h 07 min"; "?" for a negative or huge time. */
void sl_progress_duration(double seconds, char *buf, size_t len);
/* The status text: "<what>  31.0 %  2.1 units/s  ETA 1 min 05 s". */
void sl_progress_text(const sl_progress *p, double done, const char *what, char *buf, size_t len);

#endif
