/* case_lock: flock on <case>/.sluice.lock (see case_lock.h). */
#include "case/case_lock.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/* What the holder wrote into the lock file, one line. */
static void holder(int fd, char *buf, size_t len)
{
    ssize_t n = pread(fd, buf, len - 1, 0);
    buf[n > 0 ? n : 0] = '\0';
    buf[strcspn(buf, "\n")] = '\0';
    if (!buf[0]) snprintf(buf, len, "a process that has not written its pid yet");
}

/* Whether fd is still the file at path (a releasing holder unlinks it). */
static int same_file(int fd, const char *path)
{
    struct stat a, b;
    return fstat(fd, &a) == 0 && stat(path, &b) == 0 && a.st_dev == b.st_dev &&
        a.st_ino == b.st_ino;
}

int case_lock_take(case_lock *l, const char *dir, sl_err *err)
{
    size_t n = strlen(dir) + 32;
    l->fd = -1;
    l->path = sl_malloc(n, "a path");
    snprintf(l->path, n, "%s/.sluice.lock", dir);
    for (int tries = 0; tries < 100; tries++) {
        int fd = open(l->path, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
        if (fd < 0) {
            sl_err_set(err, "cannot lock the case: cannot create '%s': %s", l->path,
                       strerror(errno));
            return 1;
        }
        if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
            char who[256];
            int e = errno;
            holder(fd, who, sizeof who);
            close(fd);
            if (e == EWOULDBLOCK)
                sl_err_set(err,
                           "case %s is being run by %s (lock %s): wait for it to end, or "
                           "stop it (kill -INT <pid>: it writes and stops)",
                           dir, who, l->path);
            else sl_err_set(err, "cannot lock the case '%s': %s", l->path, strerror(e));
            return 1;
        }
        if (!same_file(fd, l->path)) { /* unlinked by the holder we waited for: again */
            close(fd);
            continue;
        }
        char host[128] = "?", stamp[64], text[512];
        time_t now = time(NULL);
        gethostname(host, sizeof host - 1);
        strftime(stamp, sizeof stamp, "%Y-%m-%d %H:%M:%S", localtime(&now));
        int len = snprintf(text, sizeof text, "pcisph (pid %ld on host %s since %s)\n",
                           (long)getpid(), host, stamp);
        if (ftruncate(fd, 0) != 0 || pwrite(fd, text, (size_t)len, 0) != len) {
            sl_err_set(err, "cannot lock the case: cannot write '%s': %s", l->path,
                       strerror(errno));
            close(fd);
            return 1;
        }
        l->fd = fd;
        return 0;
    }
    sl_err_set(err, "cannot lock the case '%s': it keeps being replaced", l->path);
    return 1;
}

void case_lock_release(case_lock *l)
{
    if (l->fd >= 0) {
        unlink(l->path); /* while holding it: the next one sees a new file */
        close(l->fd);
        l->fd = -1;
    }
    free(l->path);
    l->path = NULL;
}
