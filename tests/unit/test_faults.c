/* Fault tests: runs that are interrupted, killed or cannot write, and
 * hostile input.  bin/pcisph runs on copies of tests/cases/hydrostaticTank
 * under tests/output/faults_*; written files are read back with VTK by
 * tests/cases/check_run.py (which also checks fluid.pvd).
 *
 *   - SIGINT / SIGTERM / SIGUSR2 and a `stopNow` file: the step is
 *     finished, a time directory written, the exit status is 0 with a
 *     message, and `startFrom latestTime` goes on; a stopNow made before
 *     the run is removed with a warning;
 *   - a second signal stops at once (killed by it), SIGKILL at any moment:
 *     what was written stays readable, fluid.pvd stays valid, and a
 *     restart from latestTime works (also past a half-written "*.tmp.*");
 *   - SIGUSR1 and a `writeNow` file write a time directory and the run
 *     goes on to endTime;
 *   - a full disk (tmpfs) or a read-only case (bind mount) ends the run
 *     with a message naming the cause and a non-zero exit, earlier time
 *     directories and fluid.pvd intact.  Mounting needs `unshare -m` as
 *     root; where that is impossible these tests are skipped with a note;
 *   - hostile input: each stops with a message naming the file (and key)
 *     and writes nothing, within a time limit;
 *   - a second solver in a running case is refused, naming the first one's
 *     pid, and the lock dies with the first one (kill -9 included);
 *   - the per-step record reaches the disk within about a second, so that
 *     kill -9 loses at most that;
 *   - temporaries "*.tmp.<pid>" of dead runs are removed, with a message;
 *   - a damaged restart file is reported as damaged, naming the time
 *     directory and what to do; listTimes -check marks it;
 *   - a run stopped by a signal says how to resume, and Allrun -resume
 *     continues it.
 * Time directories are read back as check_run.py lines (time=... nan=...). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "hostile_table.h"

static const char *bin_dir(void)
{
    const char *b = getenv("SLUICE_BIN");
    return b ? b : "bin";
}

static int sh(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Run a shell command built like printf; returns its exit status (-1 if
 * it did not exit normally). */
static int sh(const char *fmt, ...)
{
    char cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    int rc = system(cmd);
    return rc != -1 && WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

static void sleep_s(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - floor(s)) * 1e9)};
    nanosleep(&ts, NULL);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Whole text file (at most 64 KiB) into a static buffer, valid until the
 * next call. */
static int read_int(const char *path)
{
    int v = -1;
    FILE *f = fopen(path, "r");
    if (f) {
        if (fscanf(f, "%d", &v) != 1) v = -1;
        fclose(f);
    }
    return v;
}

static const char *slurp(const char *path)
{
    static char buf[65536];
    FILE *f = fopen(path, "r");
    buf[0] = 0;
    if (!f) return buf;
    buf[fread(buf, 1, sizeof buf - 1, f)] = 0;
    fclose(f);
    return buf;
}

/* tests/output/<name>: a copy of the hydrostatic tank with `edit` applied
 * (shell commands run inside it). */
static void make_case(const char *name, const char *edit)
{
    assert_int_equal(
        sh("rm -rf tests/output/%s && mkdir -p tests/output && "
           "cp -r tests/cases/hydrostaticTank tests/output/%s && cd tests/output/%s && %s",
           name, name, name, edit ? edit : "true"),
        0);
}

static void set_key(const char *name, const char *file, const char *key, const char *value)
{
    assert_int_equal(sh("cd tests/output/%s && (grep -v '^%s ' %s; echo '%s %s;') > %s.new && "
                        "mv %s.new %s",
                        name, key, file, key, value, file, file, file),
                     0);
}

/* Start the solver on tests/output/<name> in the background, output to
 * tests/output/<name>.log. */
static pid_t spawn(const char *name)
{
    char exe[1024], dir[512], log[512];
    snprintf(exe, sizeof exe, "%s/pcisph", bin_dir());
    snprintf(dir, sizeof dir, "tests/output/%s", name);
    snprintf(log, sizeof log, "tests/output/%s.log", name);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0) _exit(126);
        dup2(fd, 1);
        dup2(fd, 2);
        close(fd);
        unsetenv("OMP_WAIT_POLICY"); /* the solver's own restart with it (sl_threads.h) */
        unsetenv("GOMP_SPINCOUNT");
        execl(exe, exe, "-case", dir, (char *)NULL);
        _exit(127);
    }
    return pid;
}

/* Wait for pid to end (at most `limit` s, then SIGKILL and fail). */
static int wait_end(pid_t pid, double limit)
{
    int status;
    double t0 = now();
    for (;;) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid) return status;
        assert_true(r == 0);
        if (now() - t0 > limit) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            fail_msg("the solver did not end within %g s", limit);
        }
        sleep_s(0.02);
    }
}

/* Wait until tests/output/<name>/<rel> exists while pid runs; 0 if pid
 * ended first or `limit` s passed. */
static int wait_file(pid_t pid, const char *name, const char *rel, double limit)
{
    char path[512];
    snprintf(path, sizeof path, "tests/output/%s/%s", name, rel);
    double t0 = now();
    while (now() - t0 < limit) {
        if (exists(path)) return 1;
        if (waitpid(pid, NULL, WNOHANG) == pid) return 0;
        sleep_s(0.02);
    }
    return 0;
}

/* Wait (at most 5 s) until signal sig is no longer pending for pid
 * (/proc/<pid>/status, SigPnd and ShdPnd). */
static void wait_delivered(pid_t pid, int sig)
{
    char path[64], line[256];
    snprintf(path, sizeof path, "/proc/%ld/status", (long)pid);
    double t0 = now();
    while (now() - t0 < 5) {
        FILE *f = fopen(path, "r");
        unsigned long long pending = 0, mask;
        if (!f) return;
        while (fgets(line, sizeof line, f))
            if ((sscanf(line, "SigPnd: %llx", &mask) == 1 ||
                 sscanf(line, "ShdPnd: %llx", &mask) == 1))
                pending |= mask;
        fclose(f);
        if (!(pending & (1ull << (sig - 1)))) return;
        sleep_s(0.001);
    }
}

/* ---- what was written ---- */

typedef struct output {
    int ntimes, unreadable, nan, pvd_ok, pvd_n, pvd_missing, pvd_unlisted, tmp_left;
    double last; /* newest time with a fluid.vtu */
} output;

static output read_output(const char *dir)
{
    char cmd[1024], line[1024];
    output o = {0};
    o.last = -1;
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 tests/cases/check_run.py %s --pvd", dir);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    while (fgets(line, sizeof line, p)) {
        if (!strncmp(line, "time=", 5)) {
            o.ntimes++;
            o.last = strtod(line + 5, NULL);
            o.unreadable += strstr(line, "unreadable=1") != NULL;
            const char *n = strstr(line, " nan=");
            if (n) o.nan += atoi(n + 5);
        } else if (!strncmp(line, "pvd=", 4)) {
            o.pvd_ok = !strncmp(line, "pvd=OK", 6);
            sscanf(line, "pvd=%*s n=%d missing=%d unlisted=%d", &o.pvd_n, &o.pvd_missing,
                   &o.pvd_unlisted);
        }
    }
    assert_int_equal(pclose(p), 0);
    snprintf(cmd, sizeof cmd, "ls %s | grep -q '\\.tmp\\.'", dir);
    o.tmp_left = system(cmd) == 0;
    return o;
}

/* Everything written is readable and finite; the pvd is valid and lists
 * every complete time directory but at most `unlisted`. */
static void check_intact(const char *dir, int unlisted, output *out)
{
    output o = read_output(dir);
    print_message("%s: %d time directories (newest %g), pvd %s with %d, %d unlisted%s\n", dir,
                  o.ntimes, o.last, o.pvd_ok ? "valid" : "INVALID", o.pvd_n, o.pvd_unlisted,
                  o.tmp_left ? ", a *.tmp.* left behind" : "");
    assert_true(o.ntimes >= 1);
    assert_int_equal(o.unreadable, 0);
    assert_int_equal(o.nan, 0);
    assert_true(o.pvd_ok);
    assert_int_equal(o.pvd_missing, 0);
    assert_true(o.pvd_unlisted <= unlisted);
    if (out) *out = o;
}

enum { ANY_UNLISTED = 1000 }; /* for check_intact: leave the count to the caller */

/* Continue tests/output/<name> from its latest time to `end`; must exit 0,
 * reach `end`, and list every time directory in fluid.pvd. */
static void restart_to(const char *name, double end)
{
    char value[64], dir[256];
    snprintf(value, sizeof value, "%.9g", end);
    set_key(name, "system/controlDict", "startFrom", "latestTime");
    set_key(name, "system/controlDict", "endTime", value);
    assert_int_equal(sh("timeout -s KILL 600 %s/pcisph -case tests/output/%s -quiet > "
                        "tests/output/%s.restart.log 2>&1",
                        bin_dir(), name, name),
                     0);
    snprintf(dir, sizeof dir, "tests/output/%s.restart.log", name);
    assert_non_null(strstr(slurp(dir), "Restarting from"));
    snprintf(dir, sizeof dir, "tests/output/%s", name);
    output o;
    check_intact(dir, ANY_UNLISTED, &o);
    assert_true(fabs(o.last - end) < 1e-9);
    if (o.pvd_unlisted)
        fail_msg("after the restart %s/fluid.pvd lists %d of the %d time directories (the one "
                 "restarted from is left out: libsrc/case/case_output.c out_init keeps only "
                 "times before the start time)",
                 dir, o.pvd_n, o.ntimes);
}

/* ---- signals ---- */

/* A long run (endTime 5, writes every 0.02 s) stopped by `sig` after its
 * first write (sig 0: by a file stopNow in the case, and a stale stopNow
 * made before the run is removed, not obeyed); then continued to 0.02 s
 * past the stop. */
static void stop_by(int sig, const char *name)
{
    make_case(name, sig ? NULL : "touch stopNow");
    set_key(name, "system/controlDict", "endTime", "5");
    set_key(name, "system/controlDict", "writeInterval", "0.02");
    pid_t pid = spawn(name);
    assert_true(wait_file(pid, name, "0.02/fluid.vtu", 300));
    sleep_s(0.1);
    /* started again for passive OpenMP waits (sl_threads.h), it keeps its
     * name: ps, pgrep and killall find it */
    char comm_path[64], comm[64] = "";
    snprintf(comm_path, sizeof comm_path, "/proc/%d/comm", (int)pid);
    FILE *cf = fopen(comm_path, "r");
    assert_non_null(cf);
    assert_non_null(fgets(comm, sizeof comm, cf));
    fclose(cf);
    if (strcmp(comm, "pcisph\n")) fail_msg("the solver's process is called '%s', not pcisph", comm);
    if (sig) kill(pid, sig);
    else assert_int_equal(sh("touch tests/output/%s/stopNow", name), 0);
    int status = wait_end(pid, 120);
    char log[256];
    snprintf(log, sizeof log, "tests/output/%s.log", name);
    const char *text = slurp(log);
    const char *how = sig ? strsignal(sig) : "stopNow";
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        fail_msg("after %s the solver ended with status %#x:\n%s", how, status, text);
    const char *said = sig ? "Stopped by a signal at t = " : "Stopped by the file stopNow at t = ";
    const char *msg = strstr(text, said);
    if (!msg) fail_msg("no '%s' in the log:\n%s", said, text);
    assert_non_null(strstr(msg, "startFrom latestTime"));
    double t_stop = strtod(msg + strlen(said), NULL);
    if (!sig) {
        assert_non_null(strstr(text, "stopNow, left from before this run"));
        char path[256];
        snprintf(path, sizeof path, "tests/output/%s/stopNow", name);
        assert_false(exists(path)); /* the request is used up */
    }
    char dir[256];
    snprintf(dir, sizeof dir, "tests/output/%s", name);
    output o;
    check_intact(dir, 0, &o);
    print_message("%s: stopped at t = %g\n", how, t_stop);
    assert_true(t_stop > 0.02 - 1e-9 && t_stop < 5);
    assert_true(fabs(o.last - t_stop) < 1e-6); /* the stop time was written */
    restart_to(name, t_stop + 0.02);
}

static void test_sigint_writes_and_stops(void **state)
{
    (void)state;
    stop_by(SIGINT, "faults_sigint");
}

static void test_sigterm_writes_and_stops(void **state)
{
    (void)state;
    stop_by(SIGTERM, "faults_sigterm");
}

/* USR2 (what mpirun forwards at once, doc/parallel.md "Signals") and the
 * file stopNow stop the same way. */
static void test_sigusr2_and_stop_now_file(void **state)
{
    (void)state;
    stop_by(SIGUSR2, "faults_sigusr2");
    stop_by(0, "faults_stopnow");
}

/* The second of two signals stops at once; SIGKILL stops anywhere.  In
 * both cases what is on disk stays usable.  A half-written time directory
 * "<t>.tmp.<pid>" (as a kill during a write leaves) must not confuse the
 * restart. */
static void kill_midway(const char *name, int twice)
{
    int status = 0;
    double took = 0;
    for (int attempt = 1; attempt <= 3; attempt++) {
        make_case(name, NULL);
        set_key(name, "system/controlDict", "endTime", "5");
        set_key(name, "system/controlDict", "writeInterval", "0.01");
        pid_t pid = spawn(name);
        assert_true(wait_file(pid, name, "0.03/fluid.vtu", 300));
        if (twice) {
            /* two signals sent together may merge into one: send the second
             * once the first is no longer pending */
            kill(pid, SIGINT);
            wait_delivered(pid, SIGINT);
            kill(pid, SIGINT);
        } else {
            kill(pid, SIGKILL);
        }
        double t0 = now();
        status = wait_end(pid, 60);
        took = now() - t0;
        /* On a busy machine the run can finish its step, write and exit on
         * the first SIGINT before this process sends the second: that run
         * tells nothing about the second signal, so it is run again. */
        if (!(twice && WIFEXITED(status))) break;
        print_message("attempt %d: the run ended on the first SIGINT (status %#x) before the "
                      "second was sent: again\n",
                      attempt, status);
    }
    print_message("%s: ended after %.3f s, status %#x\n", twice ? "two SIGINTs" : "SIGKILL", took,
                  status);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(WTERMSIG(status), twice ? SIGINT : SIGKILL);
    assert_true(took < 5.0);
    char dir[256];
    output o;
    snprintf(dir, sizeof dir, "tests/output/%s", name);
    check_intact(dir, 1, &o); /* killed between a directory and its pvd entry */
    assert_int_equal(sh("cd tests/output/%s && mkdir -p 4.5.tmp.99999 && "
                        "echo garbage > 4.5.tmp.99999/fluid.vtu",
                        name),
                     0);
    restart_to(name, o.last + 0.02);
}

static void test_second_signal_stops_at_once(void **state)
{
    (void)state;
    kill_midway("faults_twice", 1);
}

static void test_sigkill_leaves_usable_output(void **state)
{
    (void)state;
    kill_midway("faults_kill", 0);
}

/* SIGUSR1 or a file `writeNow`: a time directory off the write interval,
 * and the run goes on to endTime (writeInterval 1, endTime 1). */
static void write_on_request(const char *name, int by_file)
{
    make_case(name, NULL);
    set_key(name, "system/controlDict", "endTime", "1");
    set_key(name, "system/controlDict", "writeInterval", "1");
    pid_t pid = spawn(name);
    assert_true(wait_file(pid, name, "0/fluid.vtu", 300));
    sleep_s(0.05); /* the run has at least 500 steps to go */
    char path[256];
    snprintf(path, sizeof path, "tests/output/%s/writeNow", name);
    if (by_file) {
        FILE *f = fopen(path, "w");
        assert_non_null(f);
        fclose(f);
    } else {
        kill(pid, SIGUSR1);
    }
    int status = wait_end(pid, 300);
    char log[256], dir[256];
    snprintf(log, sizeof log, "tests/output/%s.log", name);
    const char *text = slurp(log);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        fail_msg("the solver ended with status %#x:\n%s", status, text);
    const char *msg = strstr(text, "Writing at t = ");
    if (!msg) fail_msg("no 'Writing at t = ... on request' in the log:\n%s", text);
    double t_req = strtod(msg + strlen("Writing at t = "), NULL);
    snprintf(dir, sizeof dir, "tests/output/%s", name);
    output o;
    check_intact(dir, 0, &o);
    print_message("%s: written at t = %g\n", by_file ? "writeNow" : "SIGUSR1", t_req);
    assert_true(t_req > 0 && t_req < 1);
    assert_int_equal(o.ntimes, 3);        /* 0, the request, 1 */
    assert_true(fabs(o.last - 1) < 1e-9); /* and it went on to the end */
    assert_false(exists(path));           /* the request file is used up */
}

static void test_sigusr1_writes_and_goes_on(void **state)
{
    (void)state;
    write_on_request("faults_usr1", 0);
}

static void test_write_now_file(void **state)
{
    (void)state;
    write_on_request("faults_writenow", 1);
}

/* ---- write failures ---- */

static int can_mount(void)
{
    return sh("mkdir -p tests/output/faults_mnt && unshare -m sh -c "
              "'mount -t tmpfs -o size=64k tmpfs tests/output/faults_mnt' > /dev/null 2>&1") == 0;
}

/* Bytes used by folder tests/output/<name>/<sub>. */
static long du_bytes(const char *name, const char *sub)
{
    char cmd[512];
    long n = -1;
    snprintf(cmd, sizeof cmd, "du -sb tests/output/%s/%s | cut -f1", name, sub);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    assert_int_equal(fscanf(p, "%ld", &n), 1);
    pclose(p);
    return n;
}

/* The case runs on a tmpfs with room for about three time directories;
 * it must stop with "No space left on device", earlier times intact. */
static void test_disk_full(void **state)
{
    (void)state;
    if (!can_mount()) {
        print_message("SKIPPED: cannot mount a tmpfs here (needs root and unshare -m)\n");
        skip();
    }
    /* the size of one time directory, from a short run */
    make_case("faults_size", NULL);
    set_key("faults_size", "system/controlDict", "endTime", "0.01");
    set_key("faults_size", "system/controlDict", "writeInterval", "0.01");
    assert_int_equal(
        sh("%s/pcisph -case tests/output/faults_size -quiet > /dev/null 2>&1", bin_dir()), 0);
    long one = du_bytes("faults_size", "0.01"), base = du_bytes("faults_size", ".");
    long size = (base + 2 * one + 4095) / 4096 * 4096;
    make_case("faults_full_src", NULL);
    set_key("faults_full_src", "system/controlDict", "endTime", "1");
    set_key("faults_full_src", "system/controlDict", "writeInterval", "0.01");
    int rc = sh("rm -rf tests/output/faults_full tests/output/faults_full_result && "
                "mkdir -p tests/output/faults_full && unshare -m sh -c '"
                "mount -t tmpfs -o size=%ld tmpfs tests/output/faults_full && "
                "cp -r tests/output/faults_full_src/. tests/output/faults_full/ && "
                "{ timeout -s KILL 600 %s/pcisph -case tests/output/faults_full -quiet "
                "> tests/output/faults_full.log 2>&1; echo $? > tests/output/faults_full.rc; "
                "cp -r tests/output/faults_full tests/output/faults_full_result; }'",
                size, bin_dir());
    assert_int_equal(rc, 0);
    int solver_rc = read_int("tests/output/faults_full.rc");
    const char *text = slurp("tests/output/faults_full.log");
    print_message("disk full (tmpfs %ld bytes, a time directory %ld): exit %d, %s", size, one,
                  solver_rc, strstr(text, "Error:") ? strstr(text, "Error:") : "no message\n");
    assert_true(solver_rc != 0 && solver_rc != 137);
    assert_non_null(strstr(text, "Error:"));
    assert_non_null(strstr(text, "No space left on device"));
    assert_null(strstr(text, "Sanitizer"));
    output o;
    check_intact("tests/output/faults_full_result", 0, &o);
    assert_true(o.ntimes >= 2);
    assert_false(o.tmp_left); /* no half-written file or folder left on the full disk */
    /* the earlier output is good to restart from, once there is room */
    assert_int_equal(sh("rm -rf tests/output/faults_full && "
                        "mv tests/output/faults_full_result tests/output/faults_full"),
                     0);
    restart_to("faults_full", o.last + 0.02);
}

/* A case made read-only (bind mount) after a first run: continuing it must
 * fail with a message naming the cause, and change nothing. */
static void test_read_only_case(void **state)
{
    (void)state;
    if (!can_mount()) {
        print_message("SKIPPED: cannot bind-mount here (needs root and unshare -m)\n");
        skip();
    }
    const char *name = "faults_ro";
    make_case(name, NULL);
    set_key(name, "system/controlDict", "endTime", "0.04");
    set_key(name, "system/controlDict", "writeInterval", "0.02");
    assert_int_equal(sh("%s/pcisph -case tests/output/%s -quiet > /dev/null 2>&1", bin_dir(), name),
                     0);
    set_key(name, "system/controlDict", "startFrom", "latestTime");
    set_key(name, "system/controlDict", "endTime", "0.1");
    assert_int_equal(
        sh("cd tests/output && find %s -type f | sort | xargs md5sum > %s.before", name, name), 0);
    int rc = sh("d=tests/output/%s && unshare -m sh -c \"mount --bind $d $d && "
                "mount -o remount,bind,ro $d && { timeout -s KILL 600 %s/pcisph -case $d -quiet "
                "> $d.log 2>&1; echo \\$? > $d.rc; }\"",
                name, bin_dir());
    assert_int_equal(rc, 0);
    char path[256];
    snprintf(path, sizeof path, "tests/output/%s.log", name);
    const char *text = slurp(path);
    snprintf(path, sizeof path, "tests/output/%s.rc", name);
    int solver_rc = read_int(path);
    print_message("read-only case: exit %d, %s", solver_rc,
                  strstr(text, "Error:") ? strstr(text, "Error:") : "no message\n");
    assert_true(solver_rc != 0 && solver_rc != 137);
    assert_non_null(strstr(text, "Error:"));
    assert_non_null(strstr(text, "Read-only file system"));
    assert_int_equal(
        sh("cd tests/output && find %s -type f | sort | xargs md5sum | cmp -s - %s.before", name,
           name),
        0);
    check_intact("tests/output/faults_ro", 0, NULL);
}

/* ---- hostile input ---- */

typedef struct hostile {
    const char *what;
    const char *edit;    /* shell commands run in the minimal case */
    const char *expect1; /* substrings the error must contain */
    const char *expect2;
    int hungry; /* might take unbounded memory: run only with a memory limit */
} hostile;

/* Beyond the 25 bad inputs of test_case.c.  Where the solver should stop
 * but does not (or not clearly), the entry states the message wanted. */
static const hostile hostile_inputs[] = {
    {"unclosed brace", "echo 'viscosity { alpha 0.1; soundSpeed 20;' >> constant/fluidProperties",
     "fluidProperties:4", "not closed", 0},
    {"extra brace", "echo '}' >> constant/fluidProperties", "fluidProperties:4", "unbalanced", 0},
    {"unterminated string", "echo 'application \"pcisph;' >> system/controlDict", "controlDict:3",
     "unterminated string", 0},
    {"#include itself", "echo '#include \"controlDict\"' >> system/controlDict", "controlDict:3",
     "#include loop", 0},
    {"#include loop of two files",
     "echo '#include \"../constant/x\"' >> system/controlDict && "
     "echo '#include \"../system/controlDict\"' > constant/x",
     "constant/x:1", "#include loop", 0},
    {"#include a folder", "echo '#include \"../constant\"' >> system/controlDict", "controlDict:3",
     "Is a directory", 0},
    {"#include a device", "echo '#include \"/dev/zero\"' >> system/controlDict", "controlDict:3",
     "/dev/zero", 1},
    {"empty controlDict", ": > system/controlDict", "controlDict", "'endTime'", 0},
    {"binary fluidProperties", "head -c 3000 /bin/sh > constant/fluidProperties",
     "fluidProperties:", "invalid character", 0},
    {"no timeStepDict", "rm system/timeStepDict", "timeStepDict", "No such file", 0},
    {"no constant folder", "rm -r constant", "fluidProperties", "No such file", 0},
    {"controlDict is a folder", "rm system/controlDict && mkdir system/controlDict", "controlDict",
     "Is a directory", 0},
    {"no case at all", "rm -r system constant", "controlDict", "No such file", 0},
    {"spacing -0", "echo 'particleSpacing -0;' >> constant/fluidProperties", "fluidProperties:4",
     "particleSpacing", 0},
    {"spacing 1e-300", "echo 'particleSpacing 1e-300;' >> constant/fluidProperties",
     "particleSpacing", "too many", 0},
    {"spacing 25 times too small", "echo 'particleSpacing 0.0008;' >> constant/fluidProperties",
     "particleSpacing", "too many", 1},
    {"huge density", "echo 'rho0 1e308;' >> constant/fluidProperties", "fluidProperties:4", "rho0",
     0},
    {"NaN gravity", "echo 'gravity (0 0 nan);' >> constant/fluidProperties", "fluidProperties:4",
     "gravity", 0},
    {"infinite velocity",
     "echo 'fluidRegions { c { type box; min (0 0 0); max (0.4 0.6 0.6); velocity (inf 0 0); } }' "
     ">> constant/fluidProperties",
     "fluidProperties:4", "velocity", 0},
    {"endTime 1e400", "echo 'endTime 1e400;' >> system/controlDict", "controlDict:3", "endTime", 0},
    {"NaN deltaT", "echo 'deltaT nan;' >> system/timeStepDict", "timeStepDict:3", "deltaT", 0},
    {"fluid inside an obstacle",
     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
     "b { type box; min (0 0 0); max (0.5 0.6 0.7); } }' >> constant/boundaryProperties",
     "fluid region 'column'", "no particle", 0},
    {"fluid regions as a list", "echo 'fluidRegions ( a b );' >> constant/fluidProperties",
     "fluidProperties:4", "fluidRegions", 0},
    {"sphere of radius 1e200",
     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
     "s { type sphere; centre (0 0 0); radius 1e200; } }' >> constant/boundaryProperties",
     "'s'", "too many", 1},
    {"mesh file missing",
     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
     "m { type mesh; file \"nowhere.stl\"; } }' >> constant/boundaryProperties",
     "nowhere.stl", "No such file", 0},
    {"mesh file garbage",
     "cp ../../data/mesh/bad/garbage.stl constant/ && "
     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
     "m { type mesh; file \"garbage.stl\"; } }' >> constant/boundaryProperties",
     "garbage.stl", "not an STL file", 0},
    {"mesh file truncated",
     "cp ../../data/mesh/bad/truncated.stl constant/ && "
     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
     "m { type mesh; file \"truncated.stl\"; } }' >> constant/boundaryProperties",
     "truncated.stl", "truncated", 0},
    {"mesh file is a folder",
     "mkdir constant/d.obj && echo 'geometry { tank { type container; min (0 0 0); "
     "max (1.6 0.6 0.8); } m { type mesh; file \"d.obj\"; } }' >> constant/boundaryProperties",
     "d.obj", "directory", 0},
    {"mesh unreadable (NaN vertex)",
     "cp ../../data/mesh/bad/nan.obj constant/ && "
     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
     "m { type mesh; file \"nan.obj\"; } }' >> constant/boundaryProperties",
     "nan.obj", "finite", 0},
    {"open mesh as a fluid region",
     "cp ../../data/mesh/bad/open.obj constant/ && "
     "echo 'fluidRegions { m { type mesh; file \"open.obj\"; } }' >> constant/fluidProperties",
     "open.obj", "not closed", 0},
    {"mesh far below the spacing (scale 1e-9)",
     "cp ../../data/mesh/cube_ascii.stl constant/ && "
     "echo 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } "
     "m { type mesh; file \"cube_ascii.stl\"; scale 1e-9; } }' >> constant/boundaryProperties",
     "'m'", "too small", 0},
};

/* 1 if the solver was built with AddressSanitizer (a memory limit would
 * break its shadow memory, so memory-hungry inputs are left out). */
static int sanitized(void)
{
    return sh("ldd %s/pcisph 2>/dev/null | grep -q libasan", bin_dir()) == 0;
}

static void test_hostile_input(void **state)
{
    (void)state;
    const char *dir = "tests/output/faults_hostile";
    int asan = sanitized(), failures = 0, ran = 0;
    for (size_t k = 0; k < sizeof hostile_inputs / sizeof *hostile_inputs; k++) {
        const hostile *h = &hostile_inputs[k];
        if (h->hungry && asan) continue;
        ran++;
        assert_int_equal(
            sh("rm -rf %s && mkdir -p %s/system %s/constant && cd %s && "
               "printf 'endTime 0.01;\\nwriteInterval 0.005;\\n' > system/controlDict && "
               "printf 'mode constant;\\ndeltaT 0.001;\\n' > system/timeStepDict && "
               "printf 'rho0 1000;\\nparticleSpacing 0.02;\\n"
               "fluidRegions { column { type box; min (0 0 0); max (0.4 0.6 0.6); } }\\n' "
               "> constant/fluidProperties && "
               "printf 'geometry { tank { type container; min (0 0 0); max (1.6 0.6 0.8); } }\\n' "
               "> constant/boundaryProperties && %s",
               dir, dir, dir, dir, h->edit),
            0);
        /* 60 s and (when safe) 2 GB of address space at most; SIGKILL,
         * since the solver only looks at SIGTERM inside its time loop */
        double t0 = now();
        int rc = sh("%s timeout -s KILL 60 %s/pcisph -case %s -quiet > %s.out 2> %s.err",
                    h->hungry ? "ulimit -v 2000000;" : "", bin_dir(), dir, dir, dir);
        double took = now() - t0;
        char path[512];
        snprintf(path, sizeof path, "%s.err", dir);
        const char *msg = slurp(path);
        int wrote =
            sh("test -e %s/0 -o -e %s/fluid.pvd -o -e %s/postProcessing", dir, dir, dir) == 0;
        int ok = rc > 0 && rc != 137 && strstr(msg, "Error:") && strstr(msg, h->expect1) &&
            strstr(msg, h->expect2) && !strstr(msg, "Sanitizer") && !strstr(msg, "runtime error") &&
            !wrote;
        if (!ok) {
            failures++;
            print_error("hostile input '%s': exit %d after %.1f s%s; wanted an error naming '%s' "
                        "and '%s'; got: %.400s\n",
                        h->what, rc, took, wrote ? ", output written" : "", h->expect1, h->expect2,
                        msg[0] ? msg : "(nothing)\n");
        } else {
            char cls[128];
            hostile_record(hostile_class_of(msg, dir, cls, sizeof cls), h->what, msg);
        }
    }
    print_message("%d hostile inputs, %d not handled%s\n", ran, failures,
                  asan ? " (memory-hungry ones left out under ASan)" : "");
    assert_int_equal(failures, 0);
}


/* ---- one solver per case, the record, temporaries, damaged restarts ---- */

/* Item 3: a second solver in a running case stops at once, naming the
 * first one's pid; once the first is killed (even with SIGKILL), the lock
 * is gone and the case runs again. */
static void test_second_solver_refused(void **state)
{
    (void)state;
    const char *name = "faults_lock";
    make_case(name, NULL);
    set_key(name, "system/controlDict", "endTime", "5");
    set_key(name, "system/controlDict", "writeInterval", "0.02");
    pid_t pid = spawn(name);
    assert_true(wait_file(pid, name, "0/fluid.vtu", 300));
    double t0 = now();
    int rc =
        sh("timeout -s KILL 60 %s/pcisph -case tests/output/%s -quiet > tests/output/%s.second "
           "2>&1",
           bin_dir(), name, name);
    double took = now() - t0;
    char path[256], want[64];
    snprintf(path, sizeof path, "tests/output/%s.second", name);
    const char *text = slurp(path);
    snprintf(want, sizeof want, "pid %ld ", (long)pid);
    print_message("second solver: exit %d after %.2f s: %s", rc, took, text);
    assert_true(rc != 0 && rc != 137);
    assert_non_null(strstr(text, "Error:"));
    assert_non_null(strstr(text, want));
    assert_true(took < 30);
    assert_int_equal(waitpid(pid, NULL, WNOHANG), 0); /* the first one runs on */
    hostile_record("second solver in a running case", "pcisph -case <case> while one runs there",
                   text);
    kill(pid, SIGKILL);
    wait_end(pid, 60);
    set_key(name, "system/controlDict", "endTime", "0.04");
    assert_int_equal(sh("timeout -s KILL 300 %s/pcisph -case tests/output/%s -quiet > /dev/null "
                        "2>&1",
                        bin_dir(), name),
                     0);
}

/* Rows of a record file (lines not starting with '#'). */
static int record_rows(const char *path)
{
    char line[4096];
    int n = 0;
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    while (fgets(line, sizeof line, f)) n += line[0] != '#' && line[0] != '\n';
    fclose(f);
    return n;
}

/* Rows of a record, and the bytes they take (the header's excluded). */
static int record_rows_bytes(const char *path, long *bytes)
{
    char line[4096];
    int n = 0;
    *bytes = 0;
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    while (fgets(line, sizeof line, f))
        if (line[0] != '#' && line[0] != '\n') {
            n++;
            *bytes += (long)strlen(line);
        }
    fclose(f);
    return n;
}

/* Lines of the log that are steps ("Time = "). */
static int step_lines(const char *path)
{
    const char *text = slurp(path);
    int n = 0;
    for (const char *at = text; (at = strstr(at, "\nTime = ")); at++) n++;
    return n;
}

/* Item 4: slow steps (300 iterations each): the record holds rows within
 * about a second, long before its buffer fills, and kill -9 keeps them.
 * No clock and no step rate is asserted (a loaded machine stretches any
 * second; a sanitizer build or a faster machine changes the steps per
 * second): after the second logged step the test waits for the first row
 * on disk (at most 30 s) and asserts that the rows then on disk are fewer
 * bytes than the stream's buffer (st_blksize, what glibc's stdio holds
 * before it writes by itself), so they came by the flush, not by a full
 * buffer. */
static void test_record_flushed(void **state)
{
    (void)state;
    const char *name = "faults_flush";
    char edit[512];
    int iterations = sanitized() ? 100 : 300; /* the sanitizers slow every step anyway */
    snprintf(edit, sizeof edit,
             "sed -i 's/^minIterations .*//; s/^maxIterations .*//' "
             "constant/fluidProperties && printf 'minIterations %d;\\nmaxIterations %d;\\n' >> "
             "constant/fluidProperties",
             iterations, iterations);
    make_case(name, edit);
    set_key(name, "system/controlDict", "numberOfThreads", "1");
    set_key(name, "system/controlDict", "endTime", "5");
    set_key(name, "system/controlDict", "writeInterval", "5");
    pid_t pid = spawn(name);
    char log[256], rec[256];
    snprintf(log, sizeof log, "tests/output/%s.log", name);
    snprintf(rec, sizeof rec, "tests/output/%s/postProcessing/timeStep/0/timeStep.dat", name);
    double t0 = now();
    while (step_lines(log) < 2 && now() - t0 < 600) sleep_s(0.05);
    const double t1 = now();
    int rows = 0;
    long bytes = 0;
    while ((rows = record_rows_bytes(rec, &bytes)) < 1 && now() - t1 < 30) sleep_s(0.05);
    int steps = step_lines(log);
    struct stat st;
    long buffer = stat(rec, &st) == 0 && st.st_blksize > 0 ? (long)st.st_blksize : BUFSIZ;
    kill(pid, SIGKILL);
    wait_end(pid, 60);
    int after = record_rows(rec);
    print_message("the first row on disk %.1f s after the second logged step, at %d logged steps "
                  "(%d rows, %ld bytes of rows; the stream's buffer holds %ld); %d rows after "
                  "kill -9\n",
                  now() - t1, steps, rows, bytes, buffer, after);
    assert_true(steps >= 2);
    assert_true(rows >= 1 && after >= rows);
    assert_true(bytes < buffer); /* flushed by time, not by a full buffer */
}

/* Item 5: temporaries of dead runs go, with a message; one of a live
 * process stays. */
static void test_stale_temporaries_removed(void **state)
{
    (void)state;
    const char *name = "faults_stale";
    char live[64];
    snprintf(live, sizeof live, "0.5.tmp.%ld", (long)getpid());
    make_case(name, NULL);
    set_key(name, "system/controlDict", "endTime", "0.01");
    set_key(name, "system/controlDict", "writeInterval", "0.01");
    assert_int_equal(sh("cd tests/output/%s && mkdir -p 0.04.tmp.999999999/uniform %s && "
                        "echo x > 0.04.tmp.999999999/fluid.vtu && echo y > fluid.pvd.tmp.999999998",
                        name, live),
                     0);
    assert_int_equal(sh("%s/pcisph -case tests/output/%s -quiet > tests/output/%s.log 2>&1",
                        bin_dir(), name, name),
                     0);
    char log[256];
    snprintf(log, sizeof log, "tests/output/%s.log", name);
    const char *text = slurp(log);
    print_message("%s", strstr(text, "Warning:") ? strstr(text, "Warning:") : "no warning\n");
    assert_non_null(strstr(text, "0.04.tmp.999999999"));
    assert_non_null(strstr(text, "fluid.pvd.tmp.999999998"));
    assert_int_equal(sh("cd tests/output/%s && test ! -e 0.04.tmp.999999999 && "
                        "test ! -e fluid.pvd.tmp.999999998 && test -d %s",
                        name, live),
                     0);
}

/* Item 12: a restart file with 100 bytes flipped is "damaged", and the
 * message names the time directory and what to do; listTimes -check
 * marks it. */
static void test_damaged_restart(void **state)
{
    (void)state;
    const char *name = "faults_damaged";
    make_case(name, NULL);
    set_key(name, "system/controlDict", "endTime", "0.04");
    set_key(name, "system/controlDict", "writeInterval", "0.02");
    assert_int_equal(sh("%s/pcisph -case tests/output/%s -quiet > /dev/null 2>&1", bin_dir(), name),
                     0);
    /* 100 bytes from the middle of the file, each inverted */
    char path[256];
    snprintf(path, sizeof path, "tests/output/%s/0.04/uniform/restart", name);
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f), at = size / 2;
    unsigned char buf[100];
    fseek(f, at, SEEK_SET);
    assert_int_equal(fread(buf, 1, 100, f), 100);
    for (int i = 0; i < 100; i++) buf[i] = (unsigned char)~buf[i];
    fseek(f, at, SEEK_SET);
    assert_int_equal(fwrite(buf, 1, 100, f), 100);
    fclose(f);
    set_key(name, "system/controlDict", "startFrom", "latestTime");
    set_key(name, "system/controlDict", "endTime", "0.06");
    int rc = sh("%s/pcisph -case tests/output/%s -quiet > tests/output/%s.log 2>&1", bin_dir(),
                name, name);
    char log[256];
    snprintf(log, sizeof log, "tests/output/%s.log", name);
    const char *text = slurp(log);
    print_message("damaged restart: exit %d, %s", rc, text);
    assert_true(rc != 0);
    assert_non_null(strstr(text, "damaged"));
    assert_non_null(strstr(text, "time directory 0.04"));
    assert_non_null(strstr(text, "restart from 0.02"));
    assert_null(strstr(text, "not a restart file"));
    hostile_record("restart file", "uniform/restart with 100 bytes flipped (startFrom latestTime)",
                   text);
    rc = sh("%s/listTimes -case tests/output/%s -check > tests/output/%s.list 2>&1", bin_dir(),
            name, name);
    snprintf(log, sizeof log, "tests/output/%s.list", name);
    text = slurp(log);
    print_message("listTimes -check: exit %d\n%s", rc, text);
    assert_true(rc != 0);
    assert_non_null(strstr(text, "0.02\n"));
    assert_non_null(strstr(text, "0.04  damaged"));
}

/* Item 19: a run stopped by a signal names the command that resumes it,
 * and a tutorial's Allrun -resume continues it (a plain Allrun refuses,
 * naming -resume). */
static void test_resume_after_stop(void **state)
{
    (void)state;
    const char *name = "faults_resume";
    assert_int_equal(
        sh("rm -rf tests/output/%s && cp -r tutorials/hydrostaticTank tests/output/%s && "
           "cd tests/output/%s && sed -i 's/^endTime .*/endTime 5;/; "
           "s/^writeInterval .*/writeInterval 0.02;/' system/controlDict",
           name, name, name),
        0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        char dir[256], top[4096];
        snprintf(dir, sizeof dir, "tests/output/%s/Allrun", name);
        if (getcwd(top, sizeof top)) setenv("SLUICE_DIR", top, 1);
        int fd = open("/dev/null", O_WRONLY);
        if (fd >= 0) dup2(fd, 1);
        execl("/bin/sh", "sh", dir, (char *)NULL);
        _exit(127);
    }
    assert_true(wait_file(pid, name, "0.02/fluid.vtu", 300));
    /* the solver is the Allrun's child: Ctrl-C reaches it */
    char kids[256];
    snprintf(kids, sizeof kids, "/proc/%ld/task/%ld/children", (long)pid, (long)pid);
    long child = atol(slurp(kids));
    assert_true(child > 0);
    kill((pid_t)child, SIGINT);
    int status = wait_end(pid, 120);
    char log[256];
    snprintf(log, sizeof log, "tests/output/%s/log.pcisph", name);
    const char *text = slurp(log);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    const char *msg = strstr(text, "Stopped by a signal");
    assert_non_null(msg);
    assert_non_null(strstr(msg, "Allrun -resume"));
    assert_non_null(strstr(msg, "-resume"));
    /* a plain Allrun refuses and names -resume */
    int rc = sh("cd tests/output/%s && SLUICE_DIR=$OLDPWD ./Allrun > ../%s.again 2>&1", name, name);
    snprintf(log, sizeof log, "tests/output/%s.again", name);
    assert_true(rc != 0);
    assert_non_null(strstr(slurp(log), "-resume"));
    /* Allrun -resume continues to the (shortened) end */
    assert_int_equal(
        sh("cd tests/output/%s && sed -i 's/^endTime .*/endTime 0.06;/' "
           "system/controlDict && SLUICE_DIR=$OLDPWD ./Allrun -resume > /dev/null 2>&1",
           name),
        0);
    snprintf(log, sizeof log, "tests/output/%s/log.pcisph", name);
    text = slurp(log);
    assert_non_null(strstr(text, "Stopped by a signal")); /* appended to, not replaced */
    assert_non_null(strstr(text, "Restarting from"));
    char dir[256];
    snprintf(dir, sizeof dir, "tests/output/%s/0.06/fluid.vtu", name);
    assert_true(exists(dir));
}

/* Usable input in unusual encodings: a UTF-8 byte-order mark and Windows
 * line ends are accepted. */
static void test_bom_and_crlf_accepted(void **state)
{
    (void)state;
    make_case("faults_crlf",
              "sed -i 's/$/\\r/' system/controlDict constant/fluidProperties && "
              "printf '\\357\\273\\277' > x && cat constant/boundaryProperties >> x && "
              "mv x constant/boundaryProperties");
    set_key("faults_crlf", "system/controlDict", "endTime", "0.01");
    set_key("faults_crlf", "system/controlDict", "writeInterval", "0.01");
    assert_int_equal(
        sh("%s/pcisph -case tests/output/faults_crlf -quiet > tests/output/faults_crlf.log "
           "2>&1",
           bin_dir()),
        0);
    check_intact("tests/output/faults_crlf", 0, NULL);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sigint_writes_and_stops),
        cmocka_unit_test(test_sigterm_writes_and_stops),
        cmocka_unit_test(test_sigusr2_and_stop_now_file),
        cmocka_unit_test(test_second_signal_stops_at_once),
        cmocka_unit_test(test_sigkill_leaves_usable_output),
        cmocka_unit_test(test_sigusr1_writes_and_goes_on),
        cmocka_unit_test(test_write_now_file),
        cmocka_unit_test(test_disk_full),
        cmocka_unit_test(test_read_only_case),
        cmocka_unit_test(test_hostile_input),
        cmocka_unit_test(test_second_solver_refused),
        cmocka_unit_test(test_record_flushed),
        cmocka_unit_test(test_stale_temporaries_removed),
        cmocka_unit_test(test_damaged_restart),
        cmocka_unit_test(test_resume_after_stop),
        cmocka_unit_test(test_bom_and_crlf_accepted),
    };
    return cmocka_run_group_tests_name("faults", tests, NULL, NULL);
}
