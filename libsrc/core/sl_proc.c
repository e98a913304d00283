/* sl_proc: starting and waiting for a child program (see sl_proc.h). */
#include "core/sl_proc.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

/* In the child: what failed and errno, to the parent through fd. */
static void sl_proc_child_fail(int fd, int what) __attribute__((noreturn));
static void sl_proc_child_fail(int fd, int what)
{
    int msg[2] = {what, errno};
    ssize_t n = write(fd, msg, sizeof msg);
    (void)n;
    _exit(127);
}

/* stdout and stderr into `path` (truncated), or stdin from it. */
static int sl_proc_redirect(const char *path, int out)
{
    int fd = out ? open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666)
                 : open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return -1;
    if (out) return dup2(fd, STDOUT_FILENO) < 0 || dup2(fd, STDERR_FILENO) < 0 ? -1 : 0;
    return dup2(fd, STDIN_FILENO) < 0 ? -1 : 0;
}

enum { SL_PROC_DIR = 1, SL_PROC_LOG, SL_PROC_INPUT, SL_PROC_EXEC };

static void sl_proc_child(const sl_proc *p, int report, int in)
{
    if (in >= 0 && dup2(in, STDIN_FILENO) < 0) sl_proc_child_fail(report, SL_PROC_INPUT);
    if (p->input && sl_proc_redirect(p->input, 0)) sl_proc_child_fail(report, SL_PROC_INPUT);
    if (p->log && sl_proc_redirect(p->log, 1)) sl_proc_child_fail(report, SL_PROC_LOG);
    if (p->dir && chdir(p->dir) != 0) sl_proc_child_fail(report, SL_PROC_DIR);
    if (p->env_name) setenv(p->env_name, p->env_value ? p->env_value : "", 1);
    signal(SIGPIPE, SIG_DFL);
    execvp(p->argv[0], (char *const *)p->argv);
    sl_proc_child_fail(report, SL_PROC_EXEC);
}

/* The parent's side: what the child reported before exec, if anything. */
static int sl_proc_check_start(const sl_proc *p, pid_t pid, int report, sl_err *err)
{
    int msg[2], st;
    ssize_t n;
    while ((n = read(report, msg, sizeof msg)) < 0 && errno == EINTR) continue;
    close(report);
    if (n != (ssize_t)sizeof msg) return 0; /* closed by exec: running */
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) continue;
    const char *what = msg[0] == SL_PROC_DIR ? "cannot enter"
        : msg[0] == SL_PROC_LOG              ? "cannot write its log"
        : msg[0] == SL_PROC_INPUT            ? "cannot read its input"
                                             : "cannot run";
    const char *obj = msg[0] == SL_PROC_DIR   ? p->dir
        : msg[0] == SL_PROC_LOG               ? p->log
        : msg[0] == SL_PROC_INPUT && p->input ? p->input
                                              : p->argv[0];
    if (msg[0] == SL_PROC_EXEC) sl_err_set(err, "cannot run %s: %s", obj, strerror(msg[1]));
    else sl_err_set(err, "%s: %s '%s': %s", p->argv[0], what, obj, strerror(msg[1]));
    return -1;
}

pid_t sl_proc_start(const sl_proc *p, FILE **to, sl_err *err)
{
    int report[2], in[2] = {-1, -1};
    if (pipe2(report, O_CLOEXEC) != 0 || (p->pipe_input && pipe2(in, O_CLOEXEC) != 0)) {
        sl_err_set(err, "cannot start %s: %s", p->argv[0], strerror(errno));
        return -1;
    }
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) {
        sl_err_set(err, "cannot start %s: %s", p->argv[0], strerror(errno));
        return -1;
    }
    if (pid == 0) {
        close(report[0]);
        sl_proc_child(p, report[1], in[0]);
    }
    close(report[1]);
    if (in[0] >= 0) close(in[0]);
    if (sl_proc_check_start(p, pid, report[0], err)) {
        if (in[1] >= 0) close(in[1]);
        return -1;
    }
    if (p->pipe_input && !(*to = fdopen(in[1], "w"))) {
        sl_err_set(err, "cannot write to %s: %s", p->argv[0], strerror(errno));
        close(in[1]);
        return -1;
    }
    return pid;
}

int sl_proc_wait(pid_t pid, int *status, int nohang, sl_err *err)
{
    pid_t r;
    while ((r = waitpid(pid, status, nohang ? WNOHANG : 0)) < 0 && errno == EINTR) continue;
    if (r < 0) {
        sl_err_set(err, "waiting for process %ld: %s", (long)pid, strerror(errno));
        return -1;
    }
    return r == pid;
}

int sl_proc_run(const sl_proc *p, int *status, sl_err *err)
{
    pid_t pid = sl_proc_start(p, NULL, err);
    if (pid < 0) return -1;
    return sl_proc_wait(pid, status, 0, err) < 0 ? -1 : 0;
}

int sl_proc_ok(int status) { return WIFEXITED(status) && WEXITSTATUS(status) == 0; }

void sl_proc_describe(int status, char *buf, size_t len)
{
    if (WIFSIGNALED(status)) snprintf(buf, len, "killed by signal %d", WTERMSIG(status));
    else snprintf(buf, len, "exit status %d", WEXITSTATUS(status));
}
