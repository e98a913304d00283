/* atomic_file: temp file + fsync + rename (see atomic_file.h). */
#include "io/atomic_file.h"

#include "core/sl_mem.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void afile_release(afile *a)
{
    free(a->path);
    free(a->tmp);
    a->path = a->tmp = NULL;
    a->f = NULL;
}

FILE *afile_open(afile *a, const char *path, sl_err *err)
{
    size_t len = strlen(path) + 32;
    int fd;
    a->f = NULL;
    a->path = sl_strdup(path);
    a->tmp = sl_malloc(len, "a temp file name");
    snprintf(a->tmp, len, "%s.tmp.%ld", path, (long)getpid());
    fd = open(a->tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd >= 0) {
        a->f = fdopen(fd, "wb");
        if (!a->f) {
            int e = errno;
            close(fd);
            unlink(a->tmp);
            errno = e;
        }
    }
    if (!a->f) {
        sl_err_set(err, "cannot write '%s': %s", path, strerror(errno));
        afile_release(a);
        return NULL;
    }
    /* Large writes go straight through; small XML pieces are batched. */
    setvbuf(a->f, NULL, _IOFBF, 1 << 16);
    return a->f;
}

/* Make the rename durable; a failure here cannot un-write the file, and
 * some file systems refuse fsync on folders, so it is best effort. */
static void afile_sync_dir(const char *path)
{
    char *copy = sl_strdup(path);
    int fd = open(dirname(copy), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
    free(copy);
}

int afile_commit(afile *a, sl_err *err)
{
    int e = 0;
    if (!a->f) {
        sl_err_set(err, "cannot write '%s': file not open", a->path ? a->path : "?");
        return 1;
    }
    errno = 0;
    if (fflush(a->f) != 0 || ferror(a->f)) e = errno ? errno : EIO;
    if (!e && fsync(fileno(a->f)) != 0) e = errno;
    if (fclose(a->f) != 0 && !e) e = errno;
    a->f = NULL;
    if (!e && rename(a->tmp, a->path) != 0) e = errno;
    if (e) {
        unlink(a->tmp);
        sl_err_set(err, "cannot write '%s': %s", a->path, strerror(e));
        afile_release(a);
        return 1;
    }
    afile_sync_dir(a->path);
    afile_release(a);
    return 0;
}

void afile_abort(afile *a)
{
    if (a->f) {
        fclose(a->f);
        unlink(a->tmp);
    }
    afile_release(a);
}
