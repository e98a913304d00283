/*
 * sl_threads: how the OpenMP threads of a program wait.
 *
 * At every barrier a thread that is done waits for the others.  libgomp's
 * default spins first, which on a machine busy with other work takes the
 * core from the very thread it waits for: with one CPU-bound process
 * beside it, 2 threads of bin/pcisph ran 3x slower than 1 (README,
 * Performance).  Passive waiting (the thread sleeps until the barrier
 * opens) keeps 2 threads at least as fast as 1 there, at the price of a
 * wake-up per barrier on an idle machine.
 */
#ifndef SL_THREADS_H
#define SL_THREADS_H

/* First thing in main: unless OMP_WAIT_POLICY or GOMP_SPINCOUNT is set,
 * set OMP_WAIT_POLICY=passive and start the program again from its own
 * path, keeping its pid and its name (libgomp reads its environment once,
 * when it is loaded).  If that fails the program goes on with the default
 * policy. */
void sl_threads_passive(char **argv);

#endif
