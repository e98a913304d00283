/*
 * sl_morton: Morton (Z-order) codes, the spatial order that keeps
 * particles close in space close in memory (neighbours/, geometry/).
 */
#ifndef SL_MORTON_H
#define SL_MORTON_H

#include <stdint.h>

/* The low 21 bits of v spread to every third bit (bit k to bit 3k):
 * spread(x) | spread(y) << 1 | spread(z) << 2 is the 3D Morton code. */
static inline uint64_t sl_morton_spread3(uint64_t v)
{
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

#endif
