/* The FMI version a mex_core.h model is built for: FMI 2.0 where FMI2 is defined, else FMI 3.0. */
#ifdef FMI2
#include "mex2.h"
#else
#include "mex3.h"
#endif
