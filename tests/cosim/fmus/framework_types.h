#ifndef ROBOGEN_TEST_FRAMEWORK_TYPES_H
#define ROBOGEN_TEST_FRAMEWORK_TYPES_H
/* framework_types.h + framework.h: a minimal FMI 3.0 Co-Simulation runtime for robogen's own test FMUs.
 *
 * A model file defines `Model` (String and Binary variables as the Text and Bytes of
 * framework_values.h), includes framework_types.h, defines the table `VARS` (one row per
 * variable, value references included) and the hooks below, then includes framework.h.
 * MODEL_TOKEN comes from the build (-D), the same string as in modelDescription.xml. The runtime exports the
 * 75 fmi3* functions, checks the state machine and the clocked-access rules of FMI 3.0 §2.4
 * (so a master that breaks them gets fmi3Error), refuses a Float value that is not finite, and
 * deactivates every clock in fmi3UpdateDiscreteStates.
 *
 * Hooks:
 *   model_defaults(m)                         start values
 *   model_step(c, t, h, &event, &terminate)   advance from t towards t+h, return the time reached
 *   model_clock_set(c, vr)                    an input clock was set active (Event Mode)
 *   model_update(c, &needUpdate, &terminate, &nextDefined, &next)   clocks still active
 *   model_new_instant(c)                      after clocks were deactivated: raise clocks of the new instant
 *   model_exit_init(c)                        leaving Initialization Mode (parameters are final)
 *   model_changed(c)                          after any successful Set* or SetClock (Event Mode reactions)
 */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "framework_values.h"

/* Value types (an Enumeration is stored and accessed as T_I64). */
enum { T_F64, T_I64, T_BOOL, T_CLOCK, T_F32, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_U64, T_STRING, T_BINARY };
enum { C_PARAM, C_INPUT, C_OUTPUT, C_LOCAL };
enum { S_INSTANTIATED = 1, S_INIT = 2, S_EVENT = 4, S_STEP = 8, S_TERMINATED = 16 };

typedef struct {
    unsigned vr;
    int type;
    size_t offset;
    int causality;
    int clock; /* value reference of the variable's clock, or -1 */
    double interval, shift; /* periodic input clocks */
} VarInfo;

typedef struct {
    char name[64];
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
    int state;
    bool eventModeUsed, earlyReturnAllowed;
    double time;
    Model m;
} Instance;

typedef struct {
    Model m;
    double time;
    int state;
} SavedState;

static double model_step(Instance *c, double t, double h, bool *event, bool *terminate);
static void model_clock_set(Instance *c, unsigned vr);
static fmi3Status model_update(Instance *c, bool *needUpdate, bool *terminate, bool *nextDefined, double *next);
static void model_new_instant(Instance *c);
static void model_defaults(Model *m);
static void model_exit_init(Instance *c);
static void model_changed(Instance *c);

#define NVARS (sizeof(VARS) / sizeof(VARS[0]))

#endif
