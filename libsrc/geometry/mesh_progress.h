/*
 * mesh_progress: "where is my run" for long mesh work -- reading, welding,
 * indexing and sampling a mesh of millions of triangles takes minutes --
 * through core/sl_progress: on a terminal one line rewritten in place, in a
 * log a plain "Progress: indexing glass.stl (2000000 triangles)  45.0 %
 * wall 12 s  ETA 14 s" line every 10 s (SLUICE_PROGRESS, _PERIOD).  Work
 * of fewer than MESH_PROGRESS_MIN units is not tracked, and the clock is
 * read once every MESH_PROGRESS_EVERY units, so that small meshes pay
 * nothing.  Only geometry/ uses it.
 */
#ifndef SL_MESH_PROGRESS_H
#define SL_MESH_PROGRESS_H

#include <stdarg.h>
#include <stdio.h>

#include "core/sl_progress.h"

#define MESH_PROGRESS_MIN   100000
#define MESH_PROGRESS_EVERY 4096

typedef struct mesh_progress {
    sl_progress p;
    int on;
    size_t next; /* the next count at which the clock is read */
    char what[192];
} mesh_progress;

static inline void mesh_progress_start(mesh_progress *mp, size_t total, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static inline void mesh_progress_start(mesh_progress *mp, size_t total, const char *fmt, ...)
{
    va_list ap;
    mp->on = total >= MESH_PROGRESS_MIN;
    mp->next = MESH_PROGRESS_EVERY;
    if (!mp->on) return;
    va_start(ap, fmt);
    vsnprintf(mp->what, sizeof mp->what, fmt, ap);
    va_end(ap);
    sl_progress_start(&mp->p, stderr, 0.0, (double)total, 10.0);
}

/* `done` units of the total so far. */
static inline void mesh_progress_at(mesh_progress *mp, size_t done)
{
    if (!mp->on || done < mp->next) return;
    mp->next = done + MESH_PROGRESS_EVERY;
    sl_progress_update(&mp->p, (double)done, mp->what);
}

static inline void mesh_progress_end(mesh_progress *mp)
{
    if (mp->on) sl_progress_end(&mp->p);
    mp->on = 0;
}

#endif
