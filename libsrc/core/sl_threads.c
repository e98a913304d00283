/* sl_threads: passive waiting of the OpenMP threads (see sl_threads.h). */
#include "core/sl_threads.h"

#include <stdlib.h>
#include <unistd.h>

void sl_threads_passive(char **argv)
{
    if (getenv("OMP_WAIT_POLICY") || getenv("GOMP_SPINCOUNT")) return;
    if (setenv("OMP_WAIT_POLICY", "passive", 1)) return;
    execv("/proc/self/exe", argv); /* returns only on failure */
}
