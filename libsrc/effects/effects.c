/* effects: names of the effects (see effects.h). */
#include "effects/effects.h"

const char *eff_name(eff_kind k)
{
    static const char *const names[EFF_COUNT] = {
        "gravity", "viscosity", "surfaceTension", "surfaceDensityCorrection", "movingBoundary",
        "emitter"};
    return (unsigned)k < EFF_COUNT ? names[k] : "?";
}
