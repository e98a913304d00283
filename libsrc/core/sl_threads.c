/* sl_threads: passive waiting of the OpenMP threads (see sl_threads.h). */
#include "core/sl_threads.h"

#include <limits.h>
#include <stdlib.h>
#include <unistd.h>

void sl_threads_passive(char **argv)
{
    if (getenv("OMP_WAIT_POLICY") || getenv("GOMP_SPINCOUNT")) return;
    if (setenv("OMP_WAIT_POLICY", "passive", 1)) return;
    /* the program's own path, so that it keeps its name (ps, pgrep, top,
     * kill by name): started as /proc/self/exe it would be called "exe" */
    char self[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n > 0) {
        self[n] = '\0';
        execv(self, argv); /* returns only on failure */
    }
    execv("/proc/self/exe", argv);
}
