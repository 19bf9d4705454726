// Layering probe (CMakeLists.txt, test layering.pipeline_below_presentation): compiled with the
// include roots of the pipeline and numerics layers, this include must not be found.
#include "gridshell/report/report_html.h"
