// Layering probe (CMakeLists.txt, test layering.numerics_below_pipeline): compiled with the
// numerics layer's include root only, this include must not be found.
#include "gridshell/pipeline/design.h"
