/*
 * sl_log: the one error path of Sluice.
 *
 * sl_info() prints progress to stdout, sl_warning() to stderr, sl_fatal()
 * prints "Error: ..." to stderr and exits with status 1.  Library code that
 * must report an error to a caller which may recover (the dictionary parser,
 * tests) returns a status and fills an sl_err buffer instead; applications
 * turn that into sl_fatal().  The macros carry the source location in debug
 * builds so that a developer can find where an error was raised.
 */
#ifndef SL_LOG_H
#define SL_LOG_H

#include <stddef.h>

#define SL_ERR_LEN 1024

/* A message buffer for recoverable errors: "file:line:col: message". */
typedef struct sl_err {
    char msg[SL_ERR_LEN];
} sl_err;

void sl_err_set(sl_err *e, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

void sl_info(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void sl_warning(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void sl_fatal_at(const char *src, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4), noreturn));

/* Quiet mode (for tests): sl_info prints nothing. */
void sl_log_set_quiet(int quiet);

/* A rank other than 0 of a parallel run (rank > 0): sl_info and
 * sl_warning print nothing (rank 0 prints the one log), sl_fatal prints
 * its message prefixed with "rank <rank>: ". */
void sl_log_set_secondary(int rank);

/* A hook run by sl_fatal before exit (e.g. to write the last good state).
 * It is run at most once. */
void sl_log_set_fatal_hook(void (*hook)(void));

#define sl_fatal(...) sl_fatal_at(__FILE__, __LINE__, __VA_ARGS__)

#endif
