/*
 * par: the one interface of Sluice to MPI (issue 17), as OpenFOAM's
 * UPstream is to its Pstream libraries: nothing above this layer includes
 * mpi.h.  Built with mpicc (the Makefile finds it; `make MPI=no` builds
 * without), par_ is a thin wrapper over MPI_COMM_WORLD; built without MPI,
 * par_ is one rank and every exchange is a no-op, so a serial build and a
 * parallel build share every line above it.
 *
 * What the solver exchanges (phase 1, replicated state): every rank holds
 * every particle; a pass computes a contiguous range of rows per rank and
 * par_gather_rows makes the array whole again on every rank (an in-place
 * MPI_Allgatherv).  Every exchange is counted (messages, bytes, seconds)
 * for the End summary and doc/parallel.md.
 */
#ifndef SL_PAR_H
#define SL_PAR_H

#include <stddef.h>
#include <stdint.h>

/* 1 when this build has MPI. */
int par_built(void);
/* Start MPI (when `want` and the build has it); the rank count is then the
 * job's.  Without `want`, or without MPI, one rank.  An exit before
 * par_finalize (sl_fatal on any rank) aborts the whole job. */
void par_init(int *argc, char ***argv, int want);
void par_finalize(void);
/* The number of ranks of a job started by mpirun (its environment), 0
 * when not started by mpirun: an mpirun without -parallel is refused. */
int par_launcher_size(void);

int par_rank(void);
int par_size(void);
static inline int par_root(void) { return par_rank() == 0; }

/* Rows [off[r], off[r+1]) of a are rank r's (off: par_size() + 1 entries,
 * in units of doubles); afterwards every rank holds every rank's rows. */
void par_gather_rows(double *a, const size_t *off);
/* The same for one value per rank: v[par_rank()] in, v[0..size) out. */
void par_gather_one(double *v);
/* Largest of an int / a double over the ranks (an exact reduction). */
int par_max_int(int v);
double par_max_double(double v);
double par_min_double(double v);
/* Sum of a count over the ranks (exact). */
long par_sum_long(long v);
/* Every rank's n[r] values of `mine` to every rank, in rank order, into
 * all (counts cnt, displacements dis, in doubles). */
void par_allgatherv(const double *mine, int n, double *all, const int *cnt, const int *dis);
/* Personalised exchange: send[r] ints to rank r, recv[r] from it. */
void par_alltoall_int(const int *send, int *recv);
/* Personalised exchange of uint32 / doubles by counts and displacements
 * (in elements) per rank. */
void par_alltoallv_u32(const uint32_t *s, const int *scnt, const int *sdis, uint32_t *r,
                       const int *rcnt, const int *rdis);
void par_alltoallv_double(const double *s, const int *scnt, const int *sdis, double *r,
                          const int *rcnt, const int *rdis);

/* Phase 2 (domain mode, solver/pcs_domain.h): point-to-point exchange,
 * scnt[r] doubles from s + sdis[r] to rank r and rcnt[r] from rank r into
 * r + rdis[r]; only the pairs with a count exchange a message (neighbour
 * ranks), so the cost does not grow with the job's size.  The counts of
 * this rank to itself must be 0.  Both sides must know the counts (a
 * par_alltoall_int of them first, when they change). */
void par_exchange_double(const double *s, const int *scnt, const int *sdis, double *r,
                         const int *rcnt, const int *rdis);
/* The same in two halves, to compute while the messages travel: the
 * messages started (returns at once), then completed (a no-op when none
 * is in flight); s and r must not be touched in between.  One exchange in
 * flight at a time. */
void par_exchange_start(const double *s, const int *scnt, const int *sdis, double *r,
                        const int *rcnt, const int *rdis);
void par_exchange_wait(void);
/* One double to / from one rank (blocking; a chain of running sums). */
void par_send_double(double v, int to);
double par_recv_double(int from);
/* Bytes to / from one rank (blocking; rank 0's streamed output asks the
 * other ranks for their parts piece by piece, solver/pcs_domain.h).  The
 * tag keeps requests and replies apart; the receiver knows the size. */
void par_send_bytes(const void *buf, size_t n, int to, int tag);
void par_recv_bytes(void *buf, size_t n, int from, int tag);
/* The same for a message of at most n bytes; returns its size. */
size_t par_recv_bytes_upto(void *buf, size_t n, int from, int tag);
/* Receives posted now and completed later (rank 0's streamed output asks
 * for the next window while it compresses the current one): par_irecv_bytes
 * posts one (at most PAR_MAX_IRECV in flight; buf must not be touched until
 * the wait), par_irecv_test lets them progress (MPI moves a large message
 * only inside its calls; returns 1 when all are complete), par_irecv_wait
 * completes them all (a no-op when none is posted).  Messages of one
 * sender and tag match the receives in the order they were posted. */
#define PAR_MAX_IRECV 64
void par_irecv_bytes(void *buf, size_t n, int from, int tag);
int par_irecv_test(void);
void par_irecv_wait(void);
/* One long per rank to every rank: all[r] is rank r's v. */
void par_allgather_long(long v, long *all);
/* Every rank's v[0..n) summed (exact) / maximised, in place, on every rank. */
void par_sum_longs(long *v, size_t n);
void par_max_longs(long *v, size_t n);
/* Every rank's v[0..n) summed on rank 0, in place (the other ranks' v is
 * left as it was).  Used where one rank alone holds a non-zero value of
 * each entry, so that the sum is that value exactly. */
void par_sum_doubles_root(double *v, size_t n);
/* Rank r's n doubles (cnt[r] == n) into all + dis[r] on rank 0 (all is
 * read on rank 0 only). */
void par_gatherv_root(const double *mine, int n, double *all, const int *cnt, const int *dis);

/* Rank 0's bytes to every rank. */
void par_bcast(void *buf, size_t bytes);
void par_barrier(void);

/* The exchanges so far on this rank: calls, messages (point-to-point
 * equivalents: a gather over P ranks is P - 1 messages received), bytes
 * received and seconds spent inside MPI. */
typedef struct par_counts {
    long calls, messages;
    double bytes, seconds;
} par_counts;
par_counts par_counters(void);

/* Split nblocks blocks of `block` rows (n rows in all) over the ranks by
 * count: rank r gets blocks [nb r / P, nb (r + 1) / P), off[r] its first
 * row (off: P + 1 entries).  Block boundaries are kept so that per-block
 * partial sums are those of the serial code. */
void par_split_rows(size_t n, size_t block, size_t *off);

#endif
