/*
 * time_dir: OpenFOAM-style time directories of a case ("0", "0.05", "1e-05").
 *
 * A time directory is named by tdir_name of its time.  Writers fill
 * "<name>.tmp*" folders or write their files atomically, so a directory
 * whose name parses as a number and that holds the marker file is complete.
 */
#ifndef TIME_DIR_H
#define TIME_DIR_H

#include <stddef.h>

#include "core/sl_log.h"

/* OpenFOAM's time name: "%.*g" with `precision` significant digits (<= 0
 * means 6, at most 17), so without trailing zeros: 0 -> "0", 0.05 -> "0.05",
 * 1e-05 -> "1e-05", 0.30000000000000004 -> "0.3"; -0 gives "0".  The name is
 * truncated if it does not fit in len bytes (32 always suffice). */
void tdir_name(double t, int precision, char *buf, size_t len);

/* The smallest precision p >= `precision` (at most 17) whose name of t
 * reads back within `resolution` of t (a name that is true: 0.016 is not
 * "0.02"); the name goes to buf and p is returned. */
int tdir_name_within(double t, int precision, double resolution, char *buf, size_t len);

/* Time directories of a case, sorted by time ascending (ties by name). */
typedef struct tdir_list {
    size_t n;
    double *time;
    char **name;
} tdir_list;

/* List the directories of case_dir whose whole name is a finite number
 * ("0", "0.05", "1e-05"), skipping hidden ones and "*.tmp*" ones still being
 * written; with complete_marker != NULL only those holding a regular file of
 * that name.  Returns 0, or nonzero with err filled and *out empty.  Free the
 * list with tdir_list_free. */
int tdir_list_read(const char *case_dir, const char *complete_marker, tdir_list *out, sl_err *err);
void tdir_list_free(tdir_list *l);

/* OpenFOAM's time selection (timeSelector): keep in l the times that spec
 * selects -- a comma-separated list of times and inclusive ranges, "0.5",
 * "0.5:1", ":0.2" (up to), "0.8:" (from), e.g. "0,0.5:1"; a time matches
 * within 1e-9 (1 + |t|); NULL selects all -- or, with latest, only the
 * latest of them.  The first time (the initial state) is left out first
 * unless with_first.  Returns 0, or nonzero with err filled ("-time '...':
 * expected ...") and l unchanged on a malformed spec. */
int tdir_select(tdir_list *l, const char *spec, int latest, int with_first, sl_err *err);

/* rm -r of a file or folder (symbolic links are removed, never followed). */
void tdir_remove_tree(const char *path);

/* Temporaries "<name>.tmp.<pid>" (folders and files) in case_dir whose
 * writer, process <pid> of this machine, no longer runs: a run killed while
 * writing leaves them.  Removes them, lists their names (space-separated,
 * cut to fit) in `names` and returns how many there were. */
size_t tdir_remove_stale(const char *case_dir, char *names, size_t len);

/* mkdir -p (mode 0777 before umask); returns 0, or nonzero with err filled
 * ("cannot create '<path>': <reason>"). */
int tdir_mkdirs(const char *path, sl_err *err);

#endif
