/* Unity translation unit of the test FMU "counter" (the order robogen_runtime.h prescribes). */
#include "config.h"
#include "robogen_runtime.h"
#include "model.c"
#include "robogen_runtime.c"
