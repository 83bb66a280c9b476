#pragma once
// Checks of a skeleton's radii shared by the stages that take them as given.
#include "mesohex/core/skeleton.h"

namespace mesohex {

// Checks that every radius is finite and > 0: Error(InvalidInput) naming the first vertex that is not. (An empty
// radius list passes: no radius known.)
void check_radii(const Skeleton& s);

}  // namespace mesohex
