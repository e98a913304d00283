/* par: MPI behind one small interface, or one rank without it (see par.h). */
#include "parallel/par.h"

#include <stdlib.h>
#include <string.h>

#include "core/sl_log.h"

#ifdef SL_HAVE_MPI
#include <mpi.h>
#endif

static int rank_, size_ = 1;
static par_counts count_;
#ifdef SL_HAVE_MPI
static int started_, finished_;
#endif

int par_built(void)
{
#ifdef SL_HAVE_MPI
    return 1;
#else
    return 0;
#endif
}

int par_launcher_size(void)
{
    const char *names[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"};
    for (size_t k = 0; k < sizeof names / sizeof *names; k++) {
        const char *v = getenv(names[k]);
        if (v && *v) return atoi(v);
    }
    return 0;
}

#ifdef SL_HAVE_MPI
/* An exit before par_finalize (sl_fatal on one rank) must not leave the
 * other ranks waiting in a collective forever. */
static void abort_job(void)
{
    if (started_ && !finished_) MPI_Abort(MPI_COMM_WORLD, 1);
}
#endif

void par_init(int *argc, char ***argv, int want)
{
    (void)argc;
    (void)argv;
    if (!want) return;
#ifdef SL_HAVE_MPI
    int provided;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    started_ = 1;
    atexit(abort_job);
#else
    sl_fatal("-parallel: this Sluice was built without MPI (install libopenmpi-dev and "
             "openmpi-bin, then make clean && make)");
#endif
}

void par_finalize(void)
{
#ifdef SL_HAVE_MPI
    if (started_ && !finished_) {
        finished_ = 1;
        MPI_Finalize();
    }
#endif
}

int par_rank(void) { return rank_; }
int par_size(void) { return size_; }

par_counts par_counters(void) { return count_; }

void par_split_rows(size_t n, size_t block, size_t *off)
{
    const size_t nb = (n + block - 1) / block, p = (size_t)size_;
    for (size_t r = 0; r <= p; r++) {
        const size_t row = (nb * r / p) * block;
        off[r] = row < n ? row : n;
    }
}

#ifdef SL_HAVE_MPI
/* Timing and counting around one collective. */
#define COUNTED(msgs, nbytes, call)          \
    do {                                     \
        const double t0_ = MPI_Wtime();      \
        call;                                \
        count_.seconds += MPI_Wtime() - t0_; \
        count_.calls++;                      \
        count_.messages += (msgs);           \
        count_.bytes += (double)(nbytes);    \
    } while (0)

/* Counts and displacements of a gather (int, as MPI takes them); the
 * arrays are kept between calls (no allocation in the time loop after
 * the first). */
static int *counts_, *displs_;

static void gather_layout(const size_t *off)
{
    if (!counts_) {
        counts_ = malloc((size_t)size_ * sizeof *counts_);
        displs_ = malloc((size_t)size_ * sizeof *displs_);
        if (!counts_ || !displs_) sl_fatal("out of memory");
    }
    for (int r = 0; r < size_; r++) {
        const size_t c = off[r + 1] - off[r];
        if (c > (size_t)2147483647 || off[r] > (size_t)2147483647)
            sl_fatal("par_gather_rows: %zu rows at %zu exceed MPI's int counts", c, off[r]);
        counts_[r] = (int)c;
        displs_[r] = (int)off[r];
    }
}
#endif

void par_gather_rows(double *a, const size_t *off)
{
#ifdef SL_HAVE_MPI
    if (size_ == 1) return;
    gather_layout(off);
    const size_t mine = off[rank_ + 1] - off[rank_];
    const size_t got = off[size_] - off[0] - mine;
    COUNTED(size_ - 1, got * sizeof(double),
            MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, a, counts_, displs_, MPI_DOUBLE,
                           MPI_COMM_WORLD));
#else
    (void)a;
    (void)off;
#endif
}

void par_gather_one(double *v)
{
#ifdef SL_HAVE_MPI
    if (size_ == 1) return;
    COUNTED(size_ - 1, (size_t)(size_ - 1) * sizeof(double),
            MPI_Allgather(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, v, 1, MPI_DOUBLE, MPI_COMM_WORLD));
#else
    (void)v;
#endif
}

int par_max_int(int v)
{
#ifdef SL_HAVE_MPI
    if (size_ == 1) return v;
    int out;
    COUNTED(size_ - 1, (size_t)(size_ - 1) * sizeof v,
            MPI_Allreduce(&v, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD));
    return out;
#else
    return v;
#endif
}

double par_max_double(double v)
{
#ifdef SL_HAVE_MPI
    if (size_ == 1) return v;
    double out;
    COUNTED(size_ - 1, (size_t)(size_ - 1) * sizeof v,
            MPI_Allreduce(&v, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD));
    return out;
#else
    return v;
#endif
}

double par_min_double(double v)
{
#ifdef SL_HAVE_MPI
    if (size_ == 1) return v;
    double out;
    COUNTED(size_ - 1, (size_t)(size_ - 1) * sizeof v,
            MPI_Allreduce(&v, &out, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD));
    return out;
#else
    return v;
#endif
}

void par_bcast(void *buf, size_t bytes)
{
#ifdef SL_HAVE_MPI
    if (size_ == 1) return;
    if (bytes > (size_t)2147483647) sl_fatal("par_bcast: %zu bytes exceed MPI's int counts", bytes);
    COUNTED(size_ - 1, rank_ ? bytes : 0, MPI_Bcast(buf, (int)bytes, MPI_BYTE, 0, MPI_COMM_WORLD));
#else
    (void)buf;
    (void)bytes;
#endif
}

void par_barrier(void)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

long par_sum_long(long v)
{
#ifdef SL_HAVE_MPI
    if (size_ == 1) return v;
    long out;
    COUNTED(size_ - 1, (size_t)(size_ - 1) * sizeof v,
            MPI_Allreduce(&v, &out, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD));
    return out;
#else
    return v;
#endif
}

void par_allgatherv(const double *mine, int n, double *all, const int *cnt, const int *dis)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1) {
        long got = 0;
        for (int r = 0; r < size_; r++) got += r == rank_ ? 0 : cnt[r];
        COUNTED(size_ - 1, (size_t)got * sizeof(double),
                MPI_Allgatherv(mine, n, MPI_DOUBLE, all, cnt, dis, MPI_DOUBLE, MPI_COMM_WORLD));
        return;
    }
#endif
    for (int k = 0; k < n; k++) all[dis[0] + k] = mine[k];
    (void)cnt;
}

void par_alltoall_int(const int *send, int *recv)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1) {
        COUNTED(size_ - 1, (size_t)(size_ - 1) * sizeof(int),
                MPI_Alltoall(send, 1, MPI_INT, recv, 1, MPI_INT, MPI_COMM_WORLD));
        return;
    }
#endif
    recv[0] = send[0];
}

#ifdef SL_HAVE_MPI
/* Messages of a personalised exchange: the ranks a rank receives from. */
static long senders(const int *rcnt)
{
    long m = 0;
    for (int r = 0; r < size_; r++) m += r != rank_ && rcnt[r] > 0;
    return m;
}

static long received(const int *rcnt)
{
    long got = 0;
    for (int r = 0; r < size_; r++) got += r == rank_ ? 0 : rcnt[r];
    return got;
}
#endif

void par_alltoallv_u32(const uint32_t *s, const int *scnt, const int *sdis, uint32_t *r,
                       const int *rcnt, const int *rdis)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1) {
        COUNTED(senders(rcnt), (size_t)received(rcnt) * sizeof *r,
                MPI_Alltoallv(s, scnt, sdis, MPI_UINT32_T, r, rcnt, rdis, MPI_UINT32_T,
                              MPI_COMM_WORLD));
        return;
    }
#endif
    (void)rcnt;
    for (int k = 0; k < scnt[0]; k++) r[rdis[0] + k] = s[sdis[0] + k];
}

void par_alltoallv_double(const double *s, const int *scnt, const int *sdis, double *r,
                          const int *rcnt, const int *rdis)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1) {
        COUNTED(
            senders(rcnt), (size_t)received(rcnt) * sizeof *r,
            MPI_Alltoallv(s, scnt, sdis, MPI_DOUBLE, r, rcnt, rdis, MPI_DOUBLE, MPI_COMM_WORLD));
        return;
    }
#endif
    (void)rcnt;
    for (int k = 0; k < scnt[0]; k++) r[rdis[0] + k] = s[sdis[0] + k];
}

#ifdef SL_HAVE_MPI
static MPI_Request *reqs_; /* 2 per rank, for par_exchange_start */
static int nreq_;          /* in flight (0: none) */
#endif

void par_exchange_start(const double *s, const int *scnt, const int *sdis, double *r,
                        const int *rcnt, const int *rdis)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1) {
        if (nreq_) sl_fatal("par_exchange_start: an exchange is in flight (internal error)");
        if (!reqs_) {
            reqs_ = malloc(2 * (size_t)size_ * sizeof *reqs_);
            if (!reqs_) sl_fatal("out of memory");
        }
        const double t0 = MPI_Wtime();
        int nr = 0;
        long msgs = 0, got = 0;
        for (int q = 0; q < size_; q++)
            if (q != rank_ && rcnt[q] > 0) {
                MPI_Irecv(r + rdis[q], rcnt[q], MPI_DOUBLE, q, 17, MPI_COMM_WORLD, &reqs_[nr++]);
                msgs++;
                got += rcnt[q];
            }
        for (int q = 0; q < size_; q++)
            if (q != rank_ && scnt[q] > 0)
                MPI_Isend(s + sdis[q], scnt[q], MPI_DOUBLE, q, 17, MPI_COMM_WORLD, &reqs_[nr++]);
        nreq_ = nr;
        count_.seconds += MPI_Wtime() - t0;
        count_.calls++;
        count_.messages += msgs;
        count_.bytes += (double)got * (double)sizeof(double);
        return;
    }
#endif
    (void)s, (void)scnt, (void)sdis, (void)r, (void)rcnt, (void)rdis;
}

void par_exchange_wait(void)
{
#ifdef SL_HAVE_MPI
    if (nreq_) {
        const double t0 = MPI_Wtime();
        MPI_Waitall(nreq_, reqs_, MPI_STATUSES_IGNORE);
        nreq_ = 0;
        count_.seconds += MPI_Wtime() - t0;
    }
#endif
}

void par_exchange_double(const double *s, const int *scnt, const int *sdis, double *r,
                         const int *rcnt, const int *rdis)
{
    par_exchange_start(s, scnt, sdis, r, rcnt, rdis);
    par_exchange_wait();
}

size_t par_recv_bytes_upto(void *buf, size_t n, int from, int tag)
{
#ifdef SL_HAVE_MPI
    if (n > 2147483647u) n = 2147483647u;
    MPI_Status stt;
    int got = 0;
    const double t0 = MPI_Wtime();
    MPI_Recv(buf, (int)n, MPI_BYTE, from, tag, MPI_COMM_WORLD, &stt);
    MPI_Get_count(&stt, MPI_BYTE, &got);
    count_.seconds += MPI_Wtime() - t0;
    count_.calls++;
    count_.messages++;
    count_.bytes += (double)got;
    return (size_t)got;
#else
    (void)buf, (void)n, (void)from, (void)tag;
    return 0;
#endif
}

#ifdef SL_HAVE_MPI
static MPI_Request ireqs_[PAR_MAX_IRECV]; /* par_irecv_bytes's, in flight */
static int nireq_;
#endif

void par_irecv_bytes(void *buf, size_t n, int from, int tag)
{
#ifdef SL_HAVE_MPI
    if (n > 2147483647u) sl_fatal("-parallel: a message of %zu bytes exceeds MPI's int counts", n);
    if (nireq_ == PAR_MAX_IRECV)
        sl_fatal("par_irecv_bytes: %d receives in flight (internal error)", nireq_);
    const double t0 = MPI_Wtime();
    MPI_Irecv(buf, (int)n, MPI_BYTE, from, tag, MPI_COMM_WORLD, &ireqs_[nireq_++]);
    count_.seconds += MPI_Wtime() - t0;
    count_.calls++;
    count_.messages++;
    count_.bytes += (double)n;
#else
    (void)buf, (void)n, (void)from, (void)tag;
    sl_fatal("par_irecv_bytes: built without MPI (internal error)");
#endif
}

int par_irecv_test(void)
{
#ifdef SL_HAVE_MPI
    if (!nireq_) return 1;
    const double t0 = MPI_Wtime();
    int done = 0;
    MPI_Testall(nireq_, ireqs_, &done, MPI_STATUSES_IGNORE);
    if (done) nireq_ = 0;
    count_.seconds += MPI_Wtime() - t0;
    return done;
#else
    return 1;
#endif
}

void par_irecv_wait(void)
{
#ifdef SL_HAVE_MPI
    if (!nireq_) return;
    const double t0 = MPI_Wtime();
    MPI_Waitall(nireq_, ireqs_, MPI_STATUSES_IGNORE);
    nireq_ = 0;
    count_.seconds += MPI_Wtime() - t0;
#endif
}

void par_allgather_long(long v, long *all)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1) {
        COUNTED(size_ - 1, (size_t)(size_ - 1) * sizeof v,
                MPI_Allgather(&v, 1, MPI_LONG, all, 1, MPI_LONG, MPI_COMM_WORLD));
        return;
    }
#endif
    all[0] = v;
}

void par_sum_longs(long *v, size_t n)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1 && n) {
        if (n > (size_t)2147483647)
            sl_fatal("par_sum_longs: %zu values exceed MPI's int counts", n);
        COUNTED(size_ - 1, (size_t)(size_ - 1) * n * sizeof *v,
                MPI_Allreduce(MPI_IN_PLACE, v, (int)n, MPI_LONG, MPI_SUM, MPI_COMM_WORLD));
    }
#else
    (void)v, (void)n;
#endif
}

void par_max_longs(long *v, size_t n)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1 && n) {
        if (n > (size_t)2147483647)
            sl_fatal("par_max_longs: %zu values exceed MPI's int counts", n);
        COUNTED(size_ - 1, (size_t)(size_ - 1) * n * sizeof *v,
                MPI_Allreduce(MPI_IN_PLACE, v, (int)n, MPI_LONG, MPI_MAX, MPI_COMM_WORLD));
    }
#else
    (void)v, (void)n;
#endif
}

void par_sum_doubles_root(double *v, size_t n)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1 && n) {
        if (n > (size_t)2147483647)
            sl_fatal("par_sum_doubles_root: %zu values exceed MPI's int counts", n);
        COUNTED(rank_ ? 0 : size_ - 1, rank_ ? 0 : (size_t)(size_ - 1) * n * sizeof *v,
                MPI_Reduce(rank_ ? v : MPI_IN_PLACE, v, (int)n, MPI_DOUBLE, MPI_SUM, 0,
                           MPI_COMM_WORLD));
    }
#else
    (void)v, (void)n;
#endif
}

void par_gatherv_root(const double *mine, int n, double *all, const int *cnt, const int *dis)
{
#ifdef SL_HAVE_MPI
    if (size_ > 1) {
        long got = 0;
        for (int q = 0; q < size_; q++) got += q == rank_ ? 0 : cnt[q];
        COUNTED(rank_ ? 0 : size_ - 1, rank_ ? 0 : (size_t)got * sizeof(double),
                MPI_Gatherv(mine, n, MPI_DOUBLE, all, cnt, dis, MPI_DOUBLE, 0, MPI_COMM_WORLD));
        return;
    }
#endif
    (void)cnt;
    for (int k = 0; k < n; k++) all[dis[0] + k] = mine[k];
}

void par_send_double(double v, int to)
{
#ifdef SL_HAVE_MPI
    COUNTED(0, 0, MPI_Send(&v, 1, MPI_DOUBLE, to, 18, MPI_COMM_WORLD));
#else
    (void)v, (void)to;
#endif
}

double par_recv_double(int from)
{
    double v = 0.0;
#ifdef SL_HAVE_MPI
    COUNTED(1, sizeof v, MPI_Recv(&v, 1, MPI_DOUBLE, from, 18, MPI_COMM_WORLD, MPI_STATUS_IGNORE));
#else
    (void)from;
#endif
    return v;
}

void par_send_bytes(const void *buf, size_t n, int to, int tag)
{
#ifdef SL_HAVE_MPI
    if (n > 2147483647u) sl_fatal("-parallel: a message of %zu bytes exceeds MPI's int counts", n);
    COUNTED(0, 0, MPI_Send(buf, (int)n, MPI_BYTE, to, tag, MPI_COMM_WORLD));
#else
    (void)buf, (void)n, (void)to, (void)tag;
#endif
}

void par_recv_bytes(void *buf, size_t n, int from, int tag)
{
#ifdef SL_HAVE_MPI
    if (n > 2147483647u) sl_fatal("-parallel: a message of %zu bytes exceeds MPI's int counts", n);
    COUNTED(1, n, MPI_Recv(buf, (int)n, MPI_BYTE, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE));
#else
    (void)buf, (void)n, (void)from, (void)tag;
#endif
}
