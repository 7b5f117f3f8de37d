/* Loading an FMU binary in the tests' C hosts (host.c, trace_host.c), on Linux (dlopen with
 * RTLD_LOCAL, as most C importers do) and on Windows (LoadLibrary):
 *
 *   void *library = fmi3_library_open(path);   NULL if it cannot be loaded
 *   fmi3_api_load(library, &api);              the Co-Simulation functions the hosts call; a
 *                                              missing one prints "missing NAME" and exits with 2
 *
 * An includer on Linux defines _POSIX_C_SOURCE before any header, for dlopen.
 */
#ifndef FMI3_LIBRARY_H
#define FMI3_LIBRARY_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"

#if defined(_WIN32)
#include <windows.h>
#else
#include <dlfcn.h>
#endif

static void *fmi3_library_open(const char *path)
{
#if defined(_WIN32)
    return (void *)LoadLibraryA(path);
#else
    void *library = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (library == NULL) printf("dlopen failed: %s\n", dlerror());
    return library;
#endif
}

static void *fmi3_library_symbol(void *library, const char *name)
{
#if defined(_WIN32)
    FARPROC found = GetProcAddress((HMODULE)library, name);
    void *symbol;
    memcpy(&symbol, &found, sizeof symbol);
#else
    void *symbol = dlsym(library, name);
#endif
    if (symbol == NULL) {
        printf("missing %s\n", name);
        fflush(stdout);
        exit(2);
    }
    return symbol;
}

typedef struct {
    fmi3InstantiateCoSimulationTYPE *instantiate;
    fmi3FreeInstanceTYPE *free_instance;
    fmi3EnterInitializationModeTYPE *enter_init;
    fmi3ExitInitializationModeTYPE *exit_init;
    fmi3EnterEventModeTYPE *enter_event_mode;
    fmi3EnterStepModeTYPE *enter_step_mode;
    fmi3TerminateTYPE *terminate;
    fmi3SetClockTYPE *set_clock;
    fmi3GetClockTYPE *get_clock;
    fmi3SetInt64TYPE *set_int64;
    fmi3GetInt64TYPE *get_int64;
    fmi3SetUInt64TYPE *set_uint64;
    fmi3GetUInt64TYPE *get_uint64;
    fmi3SetFloat64TYPE *set_float64;
    fmi3GetFloat64TYPE *get_float64;
    fmi3SetBooleanTYPE *set_boolean;
    fmi3GetBooleanTYPE *get_boolean;
    fmi3UpdateDiscreteStatesTYPE *update;
    fmi3DoStepTYPE *do_step;
} fmi3_api;

static void fmi3_api_load(void *library, fmi3_api *api)
{
    /* Object-to-function pointer conversion through memcpy keeps -Wpedantic quiet. */
#define FMI3_RESOLVE(field, name)                            \
    do {                                                     \
        void *fmi3_p_ = fmi3_library_symbol(library, name);  \
        memcpy(&api->field, &fmi3_p_, sizeof api->field);    \
    } while (0)
    FMI3_RESOLVE(instantiate, "fmi3InstantiateCoSimulation");
    FMI3_RESOLVE(free_instance, "fmi3FreeInstance");
    FMI3_RESOLVE(enter_init, "fmi3EnterInitializationMode");
    FMI3_RESOLVE(exit_init, "fmi3ExitInitializationMode");
    FMI3_RESOLVE(enter_event_mode, "fmi3EnterEventMode");
    FMI3_RESOLVE(enter_step_mode, "fmi3EnterStepMode");
    FMI3_RESOLVE(terminate, "fmi3Terminate");
    FMI3_RESOLVE(set_clock, "fmi3SetClock");
    FMI3_RESOLVE(get_clock, "fmi3GetClock");
    FMI3_RESOLVE(set_int64, "fmi3SetInt64");
    FMI3_RESOLVE(get_int64, "fmi3GetInt64");
    FMI3_RESOLVE(set_uint64, "fmi3SetUInt64");
    FMI3_RESOLVE(get_uint64, "fmi3GetUInt64");
    FMI3_RESOLVE(set_float64, "fmi3SetFloat64");
    FMI3_RESOLVE(get_float64, "fmi3GetFloat64");
    FMI3_RESOLVE(set_boolean, "fmi3SetBoolean");
    FMI3_RESOLVE(get_boolean, "fmi3GetBoolean");
    FMI3_RESOLVE(update, "fmi3UpdateDiscreteStates");
    FMI3_RESOLVE(do_step, "fmi3DoStep");
#undef FMI3_RESOLVE
}

#endif
