/* The integrator of a Model Exchange FMU behind an adapter (adapt.c describes the adapters).
 *
 * fmi3DoStep(t, h) integrates the FMU from t to t + h and stops early at an event: a state event
 * (an event indicator changes sign: CVode's root finding locates it; Euler stops at the first step
 * past the change), a step event (completedIntegratorStep asks for Event Mode, called after every
 * integrator step where the FMU needs it), or a request to terminate. It then returns with
 * eventHandlingNeeded (earlyReturn, lastSuccessfulTime = the event's time) and the master joins the
 * FMU's event iteration to the other FMUs'. Time events need nothing here: the FMU announces them
 * with nextEventTime in fmi3UpdateDiscreteStates, and the master's next communication point is
 * never after them. After Event Mode (fmi3EnterStepMode), an input set, or an FMU state restored,
 * the integrator starts afresh from the FMU's states.
 *
 * CVode is SUNDIALS' (the libraries fmpy ships, loaded at run time: the declarations below are the
 * few of its C API used here): BDF with Newton iterations and a dense linear solver, the relative
 * tolerance of the configuration and each state's absolute tolerance that times its nominal value
 * (as fmpy sets it up), one internal step at a time (CV_ONE_STEP), each completed step shown to the
 * FMU (completedIntegratorStep). CVode's steps do not stop at communication points (its step sizes
 * are its own, as under fmpy's CV_NORMAL): a step that ends past the communication point is
 * interpolated there (CVodeGetDky), and a root found past it waits for the step that reaches it.
 * Only a time event (nextEventTime) is CVode's stop time: the right-hand side may jump there. An
 * FMU without states integrates one dummy state. */

typedef int (*cv_rhs_fn)(double, void *, void *, void *);
typedef int (*cv_root_fn)(double, void *, double *, void *);
typedef void (*cv_error_fn)(int, const char *, const char *, const char *, int, void *, void *);

enum { CV_BDF = 2, CV_ONE_STEP = 2, CV_TSTOP_RETURN = 1, CV_ROOT_RETURN = 2 };

typedef struct {
    void *core, *cvode; /* dlopen's handles */
    int (*context_create)(int, void **);
    int (*context_free)(void **);
    int (*clear_errors)(void *);
    int (*push_error)(void *, cv_error_fn, void *);
    double *(*array)(void *);
    void (*destroy)(void *);
    void *(*new_serial)(int64_t, void *);
    void *(*dense_matrix)(int64_t, int64_t, void *);
    void *(*dense_solver)(void *, void *, void *);
    int (*solver_free)(void *);
    void (*matrix_free)(void *);
    void *(*create)(int, void *);
    int (*init)(void *, cv_rhs_fn, double, void *);
    int (*reinit)(void *, double, void *);
    int (*tolerances)(void *, double, void *);
    int (*root_init)(void *, int, cv_root_fn);
    int (*linear_solver)(void *, void *, void *);
    int (*user_data)(void *, void *);
    int (*stop_time)(void *, double);
    int (*max_steps)(void *, long);
    int (*no_root_warning)(void *);
    int (*step)(void *, double, void *, double *, int);
    int (*root_info)(void *, int *);
    int (*dky)(void *, double, int, void *);
    int (*clear_stop_time)(void *);
    void (*free_memory)(void **);
} rga_sundials;

struct rga_me {
    rga_sundials s;
    size_t nx, nz;          /* states (at least one: a dummy one without), event indicators */
    bool dummy;
    double *x, *dx, *z, *z_before, *nominal;
    int *roots;
    void *context, *memory, *y, *abstol, *matrix, *solver, *y_out;
    bool started;           /* CVodeInit was called */
    double tn;              /* CVode: where its solution has reached (the FMU is at or before it) */
    bool root_pending;      /*        a root found past the last communication point, at root_time */
    double root_time, *root_y;
    bool next_defined;      /* the FMU's next time event (fmi3UpdateDiscreteStates), CVode's stop time */
    double next;
    bool restart;           /* start afresh at the next step */
    double t0;              /* Euler: where it started afresh */
    long k;                 /*        the steps since */
    long steps, rhs, root_calls;
    fmi3Status failed;      /* an FMU call in one of CVode's callbacks failed */
    char error[512];        /* CVode's last error message */
};

typedef struct {
    const char *name;
    size_t offset;
    int library; /* 0: core, 1: cvode */
} rga_sundials_symbol;

#define SUN(field, name, library) {name, offsetof(rga_sundials, field), library}

static const rga_sundials_symbol SUNDIALS_SYMBOLS[] = {
    SUN(context_create, "SUNContext_Create", 0), SUN(context_free, "SUNContext_Free", 0),
    SUN(clear_errors, "SUNContext_ClearErrHandlers", 0), SUN(push_error, "SUNContext_PushErrHandler", 0),
    SUN(array, "N_VGetArrayPointer", 0), SUN(destroy, "N_VDestroy", 0), SUN(solver_free, "SUNLinSolFree", 0),
    SUN(matrix_free, "SUNMatDestroy", 0), SUN(new_serial, "N_VNew_Serial", 1), SUN(dense_matrix, "SUNDenseMatrix", 1),
    SUN(dense_solver, "SUNLinSol_Dense", 1), SUN(create, "CVodeCreate", 1), SUN(init, "CVodeInit", 1),
    SUN(reinit, "CVodeReInit", 1), SUN(tolerances, "CVodeSVtolerances", 1), SUN(root_init, "CVodeRootInit", 1),
    SUN(linear_solver, "CVodeSetLinearSolver", 1), SUN(user_data, "CVodeSetUserData", 1),
    SUN(stop_time, "CVodeSetStopTime", 1), SUN(max_steps, "CVodeSetMaxNumSteps", 1),
    SUN(no_root_warning, "CVodeSetNoInactiveRootWarn", 1), SUN(step, "CVode", 1), SUN(root_info, "CVodeGetRootInfo", 1),
    SUN(dky, "CVodeGetDky", 1), SUN(clear_stop_time, "CVodeClearStopTime", 1), SUN(free_memory, "CVodeFree", 1),
};

/* SUNDIALS' libraries, loaded once per process and kept (unloading and loading them again for
 * every instance costs milliseconds; they hold no state of their own between contexts). */
static void *sundials_core, *sundials_cvode;

static bool load_sundials(rga_sundials *s, const rga_config *c, char *error, size_t error_size)
{
    size_t i;
    /* the core first: CVode's library needs it (by its soname, which the loaded core has) */
    if ((sundials_core == NULL && (sundials_core = dlopen(c->sundials_core, RTLD_NOW | RTLD_LOCAL)) == NULL)
        || (sundials_cvode == NULL && (sundials_cvode = dlopen(c->sundials_cvode, RTLD_NOW | RTLD_LOCAL)) == NULL)) {
        snprintf(error, error_size, "cannot load SUNDIALS (CVode) from fmpy: %s", dlerror());
        return false;
    }
    s->core = sundials_core;
    s->cvode = sundials_cvode;
    for (i = 0; i < sizeof SUNDIALS_SYMBOLS / sizeof SUNDIALS_SYMBOLS[0]; i++) {
        void *symbol = dlsym(SUNDIALS_SYMBOLS[i].library ? s->cvode : s->core, SUNDIALS_SYMBOLS[i].name);
        if (symbol == NULL) {
            snprintf(error, error_size, "SUNDIALS (fmpy's) lacks %s", SUNDIALS_SYMBOLS[i].name);
            return false;
        }
        memcpy((char *)s + SUNDIALS_SYMBOLS[i].offset, &symbol, sizeof symbol);
    }
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * The FMU's Model Exchange functions, FMI 2.0 or 3.0 alike */

static fmi3Status me_set_time(rga *a, double t)
{
    return a->cfg.kind == RGA_FMI2_ME ? (fmi3Status)a->f2.set_time(a->inner, t) : a->f3.set_time(a->inner, t);
}

static fmi3Status me_set_x(rga *a, const double *x)
{
    if (a->me->dummy) return fmi3OK;
    return a->cfg.kind == RGA_FMI2_ME ? (fmi3Status)a->f2.set_x(a->inner, x, a->me->nx) : a->f3.set_x(a->inner, x, a->me->nx);
}

static fmi3Status me_get_x(rga *a, double *x)
{
    if (a->me->dummy) {
        x[0] = 1.0;
        return fmi3OK;
    }
    return a->cfg.kind == RGA_FMI2_ME ? (fmi3Status)a->f2.get_x(a->inner, x, a->me->nx) : a->f3.get_x(a->inner, x, a->me->nx);
}

static fmi3Status me_get_dx(rga *a, double *dx)
{
    a->me->rhs++;
    if (a->me->dummy) {
        dx[0] = 0.0;
        return fmi3OK;
    }
    return a->cfg.kind == RGA_FMI2_ME ? (fmi3Status)a->f2.get_dx(a->inner, dx, a->me->nx) : a->f3.get_dx(a->inner, dx, a->me->nx);
}

static fmi3Status me_get_z(rga *a, double *z)
{
    if (a->me->nz == 0) return fmi3OK;
    return a->cfg.kind == RGA_FMI2_ME ? (fmi3Status)a->f2.get_z(a->inner, z, a->me->nz) : a->f3.get_z(a->inner, z, a->me->nz);
}

static fmi3Status me_get_nominals(rga *a, double *nominal)
{
    size_t i;
    if (a->me->dummy) {
        nominal[0] = 1.0;
        return fmi3OK;
    }
    if (a->cfg.kind == RGA_FMI2_ME) return (fmi3Status)a->f2.get_nominals(a->inner, nominal, a->me->nx);
    if (a->f3.get_nominals != NULL) return a->f3.get_nominals(a->inner, nominal, a->me->nx);
    for (i = 0; i < a->me->nx; i++) nominal[i] = 1.0;
    return fmi3OK;
}

/* completedIntegratorStep, where the FMU needs it: *enter (a step event), *terminate. */
static fmi3Status me_completed(rga *a, bool *enter, bool *terminate)
{
    fmi2Boolean enter2 = fmi2False, terminate2 = fmi2False;
    fmi3Status status;
    *enter = *terminate = false;
    if (!a->cfg.completed_step) return fmi3OK;
    if (a->cfg.kind == RGA_FMI3_ME) return a->f3.completed(a->inner, true, enter, terminate);
    status = (fmi3Status)a->f2.completed(a->inner, fmi2True, &enter2, &terminate2);
    *enter = enter2 != fmi2False;
    *terminate = terminate2 != fmi2False;
    return status;
}

/* ---------------------------------------------------------------------------------------------
 * CVode's callbacks: the FMU at (t, y) */

static int cv_rhs(double t, void *y, void *ydot, void *user)
{
    rga *a = (rga *)user;
    fmi3Status status;
    if ((status = me_set_time(a, t)) > fmi3Warning || (status = me_set_x(a, a->me->s.array(y))) > fmi3Warning
        || (status = me_get_dx(a, a->me->s.array(ydot))) > fmi3Warning) {
        a->me->failed = status;
        return -1;
    }
    return 0;
}

static int cv_root(double t, void *y, double *g, void *user)
{
    rga *a = (rga *)user;
    fmi3Status status;
    a->me->root_calls++;
    if ((status = me_set_time(a, t)) > fmi3Warning || (status = me_set_x(a, a->me->s.array(y))) > fmi3Warning
        || (status = me_get_z(a, g)) > fmi3Warning) {
        a->me->failed = status;
        return -1;
    }
    return 0;
}

static void cv_error(int line, const char *function, const char *file, const char *message, int code, void *user,
                     void *context)
{
    rga_me *me = (rga_me *)user;
    (void)line; (void)file; (void)context;
    snprintf(me->error, sizeof me->error, "%s (code %d): %s", function != NULL ? function : "CVode", code,
             message != NULL ? message : "");
}

/* ---------------------------------------------------------------------------------------------
 * The integrator */

static void *zeroed(size_t n, size_t size) { return calloc(n > 0 ? n : 1, size); }

static int cvode_new(rga *a, char *error, size_t error_size)
{
    rga_me *me = a->me;
    rga_sundials *s = &me->s;
    if (!load_sundials(s, &a->cfg, error, error_size)) return -1;
    if (s->context_create(0, &me->context) != 0) {
        snprintf(error, error_size, "SUNContext_Create failed");
        return -1;
    }
    s->clear_errors(me->context);
    s->push_error(me->context, cv_error, me);
    me->y = s->new_serial((int64_t)me->nx, me->context);
    me->y_out = s->new_serial((int64_t)me->nx, me->context);
    me->abstol = s->new_serial((int64_t)me->nx, me->context);
    me->memory = s->create(CV_BDF, me->context);
    me->matrix = s->dense_matrix((int64_t)me->nx, (int64_t)me->nx, me->context);
    me->solver = me->y != NULL && me->matrix != NULL ? s->dense_solver(me->y, me->matrix, me->context) : NULL;
    if (me->y == NULL || me->y_out == NULL || me->abstol == NULL || me->memory == NULL || me->solver == NULL) {
        snprintf(error, error_size, "CVode could not be set up: %s", me->error);
        return -1;
    }
    return 0;
}

static int me_new(rga *a, char *error, size_t error_size)
{
    rga_me *me = (rga_me *)calloc(1, sizeof(rga_me));
    if ((a->me = me) == NULL) {
        snprintf(error, error_size, "no memory left for the integrator");
        return -1;
    }
    me->dummy = a->cfg.n_states == 0;
    me->nx = me->dummy ? 1 : (size_t)a->cfg.n_states;
    me->nz = (size_t)a->cfg.n_indicators;
    me->x = (double *)zeroed(me->nx, sizeof(double));
    me->dx = (double *)zeroed(me->nx, sizeof(double));
    me->nominal = (double *)zeroed(me->nx, sizeof(double));
    me->z = (double *)zeroed(me->nz, sizeof(double));
    me->z_before = (double *)zeroed(me->nz, sizeof(double));
    me->roots = (int *)zeroed(me->nz, sizeof(int));
    me->root_y = (double *)zeroed(me->nx, sizeof(double));
    me->restart = true;
    if (!me->x || !me->dx || !me->nominal || !me->z || !me->z_before || !me->roots || !me->root_y) {
        snprintf(error, error_size, "no memory left for the integrator");
        return -1;
    }
    return a->cfg.solver == RGA_CVODE ? cvode_new(a, error, error_size) : 0;
}

static void me_free(rga *a)
{
    rga_me *me = a->me;
    if (me == NULL) return;
    if (me->memory != NULL) me->s.free_memory(&me->memory);
    if (me->solver != NULL) me->s.solver_free(me->solver);
    if (me->matrix != NULL) me->s.matrix_free(me->matrix);
    if (me->y != NULL) me->s.destroy(me->y);
    if (me->y_out != NULL) me->s.destroy(me->y_out);
    if (me->abstol != NULL) me->s.destroy(me->abstol);
    if (me->context != NULL) me->s.context_free(&me->context);
    free(me->x); free(me->dx); free(me->nominal); free(me->z); free(me->z_before); free(me->roots); free(me->root_y);
    free(me);
    a->me = NULL;
}

static void me_restart_later(rga *a)
{
    if (a->me != NULL) a->me->restart = true;
}

/* The FMU's next time event (from its update in Event Mode): CVode's stop time after the restart. */
static void me_next_event(rga *a, bool defined, double t)
{
    a->me->next_defined = defined;
    a->me->next = t;
}

static void me_statistics(const rga *a, long *steps, long *rhs, long *roots)
{
    *steps = a->me != NULL ? a->me->steps : 0;
    *rhs = a->me != NULL ? a->me->rhs : 0;
    *roots = a->me != NULL ? a->me->root_calls : 0;
}

static fmi3Status cvode_failed(rga *a, const char *what, int flag)
{
    say(a, fmi3Error, "CVode: %s failed (flag %d) at t=%.17g: %s", what, flag, a->time, a->me->error);
    return fmi3Error;
}

/* CVode's stop time: the FMU's next time event, if it announced one after its time. */
static fmi3Status cvode_stop_at_time_event(rga *a)
{
    rga_me *me = a->me;
    int flag = me->next_defined && me->next > a->time ? me->s.stop_time(me->memory, me->next) : me->s.clear_stop_time(me->memory);
    return flag != 0 ? cvode_failed(a, "CVodeSetStopTime", flag) : fmi3OK;
}

/* CVode started afresh at the FMU's time and states. */
static fmi3Status cvode_restart(rga *a)
{
    rga_me *me = a->me;
    rga_sundials *s = &me->s;
    double *abstol = s->array(me->abstol);
    size_t i;
    int flag;
    memcpy(s->array(me->y), me->x, me->nx * sizeof(double));
    for (i = 0; i < me->nx; i++) abstol[i] = a->cfg.tolerance * fabs(me->nominal[i]);
    me->tn = a->time;
    me->root_pending = false;
    if (me->started) {
        if ((flag = s->reinit(me->memory, a->time, me->y)) != 0) return cvode_failed(a, "CVodeReInit", flag);
        return cvode_stop_at_time_event(a);
    }
    me->started = true;
    if ((flag = s->init(me->memory, cv_rhs, a->time, me->y)) != 0) return cvode_failed(a, "CVodeInit", flag);
    if ((flag = s->tolerances(me->memory, a->cfg.tolerance, me->abstol)) != 0) return cvode_failed(a, "CVodeSVtolerances", flag);
    if ((flag = s->root_init(me->memory, (int)me->nz, me->nz > 0 ? cv_root : NULL)) != 0)
        return cvode_failed(a, "CVodeRootInit", flag);
    if ((flag = s->linear_solver(me->memory, me->solver, me->matrix)) != 0) return cvode_failed(a, "CVodeSetLinearSolver", flag);
    s->user_data(me->memory, a);
    s->max_steps(me->memory, 100000);
    s->no_root_warning(me->memory);
    return cvode_stop_at_time_event(a);
}

/* Start afresh from the FMU's states at its time (after Event Mode, a Set, a restored state). */
static fmi3Status me_restart(rga *a)
{
    rga_me *me = a->me;
    fmi3Status status;
    if ((status = me_get_x(a, me->x)) > fmi3Warning || (status = me_get_nominals(a, me->nominal)) > fmi3Warning
        || (status = me_get_z(a, me->z)) > fmi3Warning)
        return status;
    me->restart = false;
    me->t0 = a->time;
    me->k = 0;
    return a->cfg.solver == RGA_CVODE ? cvode_restart(a) : fmi3OK;
}

/* The FMU at (t, x) after a completed step: *event where it asks for Event Mode, *terminate. */
static fmi3Status show_step(rga *a, double t, const double *x, bool *event, bool *terminate)
{
    fmi3Status status;
    bool enter;
    if ((status = me_set_time(a, t)) > fmi3Warning || (status = me_set_x(a, x)) > fmi3Warning
        || (status = me_completed(a, &enter, terminate)) > fmi3Warning)
        return status;
    if (enter) *event = true;
    return fmi3OK;
}

/* CVode from the FMU's time to end, one internal step at a time (see the file's comment):
 * *reached, *event (a root or a step event), *terminate. */
static fmi3Status cvode_step(rga *a, double end, double *reached, bool *event, bool *terminate)
{
    rga_me *me = a->me;
    rga_sundials *s = &me->s;
    double t;
    int flag;
    for (;;) {
        if (me->root_pending && me->root_time <= end) { /* a root found in an earlier step is due */
            *reached = me->root_time;
            *event = true;
            return show_step(a, me->root_time, me->root_y, event, terminate);
        }
        if (me->tn >= end) { /* CVode is at or past end: the FMU there, interpolated */
            if ((flag = s->dky(me->memory, end, 0, me->y_out)) != 0) return cvode_failed(a, "CVodeGetDky", flag);
            *reached = end;
            return show_step(a, end, s->array(me->y_out), event, terminate);
        }
        me->failed = fmi3OK;
        flag = s->step(me->memory, end, me->y, &t, CV_ONE_STEP);
        if (me->failed > fmi3Warning) return me->failed;
        if (flag < 0) return cvode_failed(a, "CVode", flag);
        me->steps++;
        me->tn = t;
        if (flag == CV_ROOT_RETURN) {
            me->root_pending = true;
            me->root_time = t;
            memcpy(me->root_y, s->array(me->y), me->nx * sizeof(double));
            continue;
        }
        if (t < end) {
            fmi3Status status = show_step(a, t, s->array(me->y), event, terminate);
            *reached = t;
            if (flag == CV_TSTOP_RETURN) *event = true; /* a time event before end: CVode stops there */
            if (status > fmi3Warning || *event || *terminate) return status;
        }
    }
}

/* Whether an event indicator changed sign from z_before to z (as fmpy's Euler decides it). */
static bool crossed(const rga_me *me)
{
    size_t i;
    for (i = 0; i < me->nz; i++)
        if ((me->z_before[i] < 0 && me->z[i] >= 0) || (me->z_before[i] > 0 && me->z[i] <= 0)) return true;
    return false;
}

/* Explicit Euler from the FMU's time to end at the fixed step (the last one shorter if need be):
 * *reached, *event (a sign change or a step event). */
static fmi3Status euler_step(rga *a, double end, double *reached, bool *event, bool *terminate)
{
    rga_me *me = a->me;
    fmi3Status status;
    double t = a->time, next;
    size_t i;
    bool enter;
    while (t < end) {
        double grid = me->t0 + (double)(me->k + 1) * a->cfg.euler_step, tiny = 1e-12 * (fabs(end) > 1.0 ? fabs(end) : 1.0);
        next = grid < end - tiny ? grid : end;
        if ((status = me_get_dx(a, me->dx)) > fmi3Warning) return status;
        for (i = 0; i < me->nx; i++) me->x[i] += (next - t) * me->dx[i];
        memcpy(me->z_before, me->z, me->nz * sizeof(double));
        if ((status = me_set_time(a, next)) > fmi3Warning || (status = me_set_x(a, me->x)) > fmi3Warning
            || (status = me_get_z(a, me->z)) > fmi3Warning || (status = me_completed(a, &enter, terminate)) > fmi3Warning)
            return status;
        me->steps++;
        if (next == end && fabs(grid - end) > tiny) { /* the step ended off the Euler grid: it starts again here */
            me->t0 = end;
            me->k = 0;
        } else {
            me->k++;
        }
        t = *reached = next;
        if (crossed(me) || enter) *event = true;
        if (*event || *terminate) return fmi3OK;
    }
    return fmi3OK;
}

static fmi3Status me_step(rga *a, double t, double h, bool *event, bool *terminate, bool *early, double *last)
{
    double end = t + h, reached = t;
    fmi3Status status;
    if (t != a->time) { /* the master moved the FMU (a restored state): start afresh there */
        a->time = t;
        a->me->restart = true;
    }
    if (a->me->restart && (status = me_restart(a)) > fmi3Warning) return status;
    status = a->cfg.solver == RGA_CVODE ? cvode_step(a, end, &reached, event, terminate)
                                        : euler_step(a, end, &reached, event, terminate);
    if (status > fmi3Warning) return status;
    *last = reached >= end ? end : reached;
    *early = reached < end;
    return fmi3OK;
}
