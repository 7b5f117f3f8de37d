/* Starting the interpreter of a Python-implemented FMU (see bridge.h, fmi3.md §9).
 *
 * In a C host nothing has started Python. Left to itself, cffi would call Py_InitializeEx(),
 * which derives sys.prefix from the host executable (a C program: the standard library may not
 * be found) and knows nothing of the virtual environment the FMU was built in (so neither
 * _cffi_backend nor the model's imports are found). Instead Python is initialised here with the
 * build interpreter's home (unless PYTHONHOME says otherwise), the build environment's
 * site-packages are added with site.addsitedir (which also runs their .pth files), and the GIL
 * is released as cffi expects. In a host that already runs Python (fmpy, robogen's master) the
 * interpreter is only checked: it must be the Python minor version the FMU was built for.
 *
 * pyfmu_config.h (written by build.py) defines PYFMU_PYTHON_HOME, PYFMU_PYTHON_VERSION ("3.11")
 * and PYFMU_SITE_DIRS (a brace-enclosed list of string literals ending with NULL).
 */
#include <Python.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bridge.h"
#include "pyfmu_config.h"

static const char *const site_dirs[] = PYFMU_SITE_DIRS;

static int add_site_dirs(char *message, size_t size)
{
    PyObject *site = PyImport_ImportModule("site");
    size_t i;
    if (site == NULL) {
        PyErr_Clear();
        snprintf(message, size, "Python started but its 'site' module cannot be imported");
        return -1;
    }
    for (i = 0; site_dirs[i] != NULL; i++) {
        PyObject *result = PyObject_CallMethod(site, "addsitedir", "s", site_dirs[i]);
        if (result == NULL) {
            PyErr_Clear();
            Py_DECREF(site);
            snprintf(message, size, "site.addsitedir('%s') failed", site_dirs[i]);
            return -1;
        }
        Py_DECREF(result);
    }
    Py_DECREF(site);
    return 0;
}

static int initialize(char *message, size_t size)
{
    PyConfig config;
    PyStatus status;
    int result;
    PyConfig_InitPythonConfig(&config);
    config.install_signal_handlers = 0; /* the host owns the signals */
    config.parse_argv = 0;
    config.site_import = 0; /* like the build venv: no system or user site-packages, only ours */
    if (getenv("PYTHONHOME") == NULL) {
        status = PyConfig_SetBytesString(&config, &config.home, PYFMU_PYTHON_HOME);
        if (PyStatus_Exception(status)) {
            PyConfig_Clear(&config);
            snprintf(message, size, "cannot configure Python: %s", status.err_msg ? status.err_msg : "?");
            return -1;
        }
    }
    status = Py_InitializeFromConfig(&config);
    PyConfig_Clear(&config);
    if (PyStatus_Exception(status)) {
        snprintf(message, size, "Python %s (home %s) failed to start: %s", PYFMU_PYTHON_VERSION, PYFMU_PYTHON_HOME,
                 status.err_msg ? status.err_msg : "?");
        return -1;
    }
    result = add_site_dirs(message, size);
    (void)PyEval_SaveThread(); /* cffi takes the GIL with PyGILState_Ensure on every call */
    return result;
}

int pyfmu_start_python(char *message, size_t size)
{
    if (!Py_IsInitialized()) {
        if (initialize(message, size) != 0) {
            return -1;
        }
    } else {
        const char *running = Py_GetVersion();
        size_t n = strlen(PYFMU_PYTHON_VERSION);
        if (strncmp(running, PYFMU_PYTHON_VERSION, n) != 0 || running[n] != '.') {
            snprintf(message, size, "this FMU was built for Python %s; the host runs Python %.*s",
                     PYFMU_PYTHON_VERSION, (int)strcspn(running, " "), running);
            return -1;
        }
    }
    if (pyfmu_cffi_start() != 0) {
        snprintf(message, size, "the FMU's Python part failed to start (cffi printed the reason on stderr)");
        return -1;
    }
    return 0;
}
