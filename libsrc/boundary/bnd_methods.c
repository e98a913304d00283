/* bnd_methods: look-up in the table of boundary methods (bnd_methods.h). */
#include "boundary/bnd_methods.h"

#include <string.h>

#define BND_TYPE_ADDRESS(m) &m##_method,
#define BND_TYPE_NAME(m)    #m,
static const bnd_method_type *const all[] = {BND_METHODS(BND_TYPE_ADDRESS) NULL};
static const char *const names[] = {BND_METHODS(BND_TYPE_NAME) NULL};

const bnd_method_type *bnd_method_find(const char *name)
{
    for (size_t i = 0; all[i]; i++)
        if (strcmp(all[i]->name, name) == 0) return all[i];
    return NULL;
}

const char *const *bnd_method_names(void) { return names; }
