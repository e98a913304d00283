/*
 * bnd_methods: the boundary methods a case can choose, the one table.
 * Adding a method: write boundary/<name>.{h,c} after the contract in
 * bnd_method.h, include its header here and add X(<name>) to the list.
 */
#ifndef SL_BND_METHODS_H
#define SL_BND_METHODS_H

#include "boundary/becker2009.h"
#include "boundary/harada2007.h"
#include "boundary/ihmsen2010.h"

/* The default (first) is this paper's method. */
#define BND_METHODS(X) X(ihmsen2010) X(becker2009) X(harada2007)

#endif
