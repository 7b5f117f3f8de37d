/* Unity translation unit of the test FMU "plain". */
#include "config.h"
#include "robogen_runtime.h"
#include "model.c"
#include "robogen_runtime.c"
