/*
 * kernel_correction: the kernel gradient correction of Bonet & Lok 1999,
 * shared by the divergence source of the pressure solve (pressureSource
 * gradientCorrection) and the velocity correction of particle shifting.
 *
 * Over the neighbours j of particle i (volumes V_j, g_ij = krn_gradf of
 * |r_ij|, r_ij = x_i - x_j, so grad W_ij = g_ij r_ij):
 *
 *   A_i = sum_j V_j grad W_ij (x_j - x_i)^T = -sum_j V_j g_ij r_ij r_ij^T,
 *   L_i = A_i^-1,
 *
 * so that L_i sum_j V_j (f_j - f_i) grad W_ij is exact for a linear f on
 * any packing.  Where det A_i <= 1/8 (a deficient neighbourhood) L_i is
 * the identity.  Static inline: the callers' neighbour loops gather (the
 * same bits for any thread count).
 */
#ifndef SL_KERNEL_CORRECTION_H
#define SL_KERNEL_CORRECTION_H

/* A (row-major 3 x 3) += the pair's share -vg r r^T (vg = V_j g_ij). */
static inline void krn_correction_add(double A[9], double vg, const double r[3])
{
    for (int a = 0; a < 3; a++)
        for (int c = 0; c < 3; c++) A[3 * a + c] -= vg * r[a] * r[c];
}

/* det A (row-major 3 x 3). */
static inline double krn_det3(const double A[9])
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) + A[1] * (A[5] * A[6] - A[3] * A[8]) +
        A[2] * (A[3] * A[7] - A[4] * A[6]);
}

/* L = A^-1 (row-major), the identity where det A <= 1/8; returns whether
 * it corrects. */
static inline int krn_correction_invert(const double A[9], double L[9])
{
    const double c00 = A[4] * A[8] - A[5] * A[7], c01 = A[5] * A[6] - A[3] * A[8],
                 c02 = A[3] * A[7] - A[4] * A[6];
    const double det = krn_det3(A);
    if (!(det > 0.125)) { /* a deficient neighbourhood: no correction */
        for (int a = 0; a < 9; a++) L[a] = (a % 4 == 0) ? 1.0 : 0.0;
        return 0;
    }
    const double id = 1.0 / det;
    L[0] = c00 * id;
    L[1] = (A[2] * A[7] - A[1] * A[8]) * id;
    L[2] = (A[1] * A[5] - A[2] * A[4]) * id;
    L[3] = c01 * id;
    L[4] = (A[0] * A[8] - A[2] * A[6]) * id;
    L[5] = (A[2] * A[3] - A[0] * A[5]) * id;
    L[6] = c02 * id;
    L[7] = (A[1] * A[6] - A[0] * A[7]) * id;
    L[8] = (A[0] * A[4] - A[1] * A[3]) * id;
    return 1;
}

/* How isotropic A is: det A / (tr A / 3)^3, 1 for a multiple of the
 * identity (a full neighbourhood on any isotropic packing), smaller the
 * more one direction lacks neighbours (a free surface of the cubic
 * lattice: 0.92-0.94 for the kernels and supports in use); 0 for
 * a singular or indefinite A. */
static inline double krn_correction_isotropy(const double A[9])
{
    const double det = krn_det3(A), t = (A[0] + A[4] + A[8]) / 3.0;
    return det > 0.0 && t > 0.0 ? det / (t * t * t) : 0.0;
}

#endif
