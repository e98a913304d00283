/*
 * cf_tree: paths, copying and removing folder trees (see caseFolder.h).
 * Symlinks are copied and removed as links, never followed, so that a
 * link to a shared mesh or to "/" cannot make a tool copy or delete what
 * lies outside the case.
 */
#include "caseFolder/caseFolder.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/sl_mem.h"

char *cf_join(const char *a, const char *b)
{
    size_t n = strlen(a) + strlen(b) + 2;
    char *s = sl_malloc(n, "a path");
    if (!*a || !strcmp(a, ".")) snprintf(s, n, "%s", b);
    else snprintf(s, n, "%s%s%s", a, a[strlen(a) - 1] == '/' ? "" : "/", b);
    return s;
}

int cf_is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

int cf_is_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int cf_exists(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0;
}

int cf_is_case(const char *dir)
{
    char *p = cf_join(dir, "system/controlDict");
    int ok = cf_is_file(p);
    free(p);
    return ok;
}

static int cf_copy_link(const char *src, const char *dst, sl_err *err)
{
    char target[PATH_MAX];
    ssize_t n = readlink(src, target, sizeof target - 1);
    if (n < 0) {
        sl_err_set(err, "cannot read link '%s': %s", src, strerror(errno));
        return 1;
    }
    target[n] = '\0';
    if (symlink(target, dst) != 0) {
        sl_err_set(err, "cannot create link '%s': %s", dst, strerror(errno));
        return 1;
    }
    return 0;
}

static int cf_copy_data(int in, int out)
{
    char buf[1 << 16];
    ssize_t got;
    while ((got = read(in, buf, sizeof buf)) > 0)
        for (ssize_t done = 0; done < got;) {
            ssize_t w = write(out, buf + done, (size_t)(got - done));
            if (w < 0) return -1;
            done += w;
        }
    return got < 0 ? -1 : 0;
}

int cf_copy_file(const char *src, const char *dst, sl_err *err)
{
    struct stat st;
    int in, out, rc, e;
    if (lstat(src, &st) != 0) {
        sl_err_set(err, "cannot copy '%s': %s", src, strerror(errno));
        return 1;
    }
    if (S_ISLNK(st.st_mode)) return cf_copy_link(src, dst, err);
    if ((in = open(src, O_RDONLY | O_CLOEXEC)) < 0) {
        sl_err_set(err, "cannot read '%s': %s", src, strerror(errno));
        return 1;
    }
    out = open(dst, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, st.st_mode & 07777);
    if (out < 0) {
        sl_err_set(err, "cannot write '%s': %s", dst, strerror(errno));
        close(in);
        return 1;
    }
    rc = cf_copy_data(in, out);
    e = errno;
    if (fchmod(out, st.st_mode & 07777) != 0 && !rc) rc = -1, e = errno;
    if (close(out) != 0 && !rc) rc = -1, e = errno;
    close(in);
    if (rc) sl_err_set(err, "cannot copy '%s' to '%s': %s", src, dst, strerror(e));
    return rc ? 1 : 0;
}

int cf_copy_tree(const char *src, const char *dst, sl_err *err)
{
    struct stat st;
    struct dirent *de;
    DIR *d;
    int rc = 0;
    if (lstat(src, &st) != 0) {
        sl_err_set(err, "cannot copy '%s': %s", src, strerror(errno));
        return 1;
    }
    if (!S_ISDIR(st.st_mode)) return cf_copy_file(src, dst, err);
    if (mkdir(dst, (st.st_mode & 07777) | 0700) != 0 && errno != EEXIST) {
        sl_err_set(err, "cannot create '%s': %s", dst, strerror(errno));
        return 1;
    }
    if (!(d = opendir(src))) {
        sl_err_set(err, "cannot read folder '%s': %s", src, strerror(errno));
        return 1;
    }
    while (!rc && (de = readdir(d))) {
        if (!strcmp(de->d_name, ".") || !strcmp(de->d_name, "..")) continue;
        char *s = cf_join(src, de->d_name), *t = cf_join(dst, de->d_name);
        rc = cf_copy_tree(s, t, err);
        free(s);
        free(t);
    }
    closedir(d);
    return rc;
}

int cf_remove_tree(const char *path, sl_err *err)
{
    struct stat st;
    struct dirent *de;
    DIR *d;
    int rc = 0;
    if (lstat(path, &st) != 0) return 0;
    if (S_ISDIR(st.st_mode)) {
        if (!(d = opendir(path))) {
            sl_err_set(err, "cannot read folder '%s': %s", path, strerror(errno));
            return 1;
        }
        while (!rc && (de = readdir(d))) {
            if (!strcmp(de->d_name, ".") || !strcmp(de->d_name, "..")) continue;
            char *p = cf_join(path, de->d_name);
            rc = cf_remove_tree(p, err);
            free(p);
        }
        closedir(d);
        if (!rc && rmdir(path) != 0) {
            sl_err_set(err, "cannot remove '%s': %s", path, strerror(errno));
            rc = 1;
        }
    } else if (unlink(path) != 0) {
        sl_err_set(err, "cannot remove '%s': %s", path, strerror(errno));
        rc = 1;
    }
    return rc;
}

char *cf_self_dir(sl_err *err)
{
    char buf[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    char *slash;
    if (n < 0) {
        sl_err_set(err, "cannot find the program's folder (/proc/self/exe): %s", strerror(errno));
        return NULL;
    }
    buf[n] = '\0';
    slash = strrchr(buf, '/');
    if (slash) *slash = '\0';
    return sl_strdup(buf);
}
