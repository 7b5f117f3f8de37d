/* The schema of the master's plan, and of the engine that runs it: the one definition of both.
 *
 * robogen.cosim.engine reads this file into cffi's declarations (so no preprocessor lines here)
 * and takes every enumeration below from it (robogen.cosim.engine.Kind, End, ...); the engine's C
 * files include it. A plan (rg_plan) is what assembling a system produces, flattened to indices:
 * the instances and the C functions that call them (an FMU's own, or an adapter's), the DoStep
 * order, the Get and Set batches per FMU and type, the clock routes and the clocked values they
 * carry, the record columns, the clock schedule. robogen.cosim.plan builds it, once per run; it
 * is not changed afterwards. An engine (rg_engine) is one run of a plan: its state, owned by C
 * (rg_engine_new, rg_engine_free), read by Python between calls of rg_engine_run. */

/* How a value is held in C: the C type of its FMI type (Enumerations as Int64). */
enum rg_kind { K_F64 = 0, K_F32, K_I64, K_U64, K_I32, K_U32, K_I16, K_U16, K_I8, K_U8, K_BOOL, K_STRING, K_BINARY };

/* How the engine stores the rows, by where the recorder sends them. */
enum rg_store {
    STORE_SLOTS = 0, /* 8-byte values (Python builds the rows): the rows are kept */
    STORE_TEXT,      /* the CSV lines: the rows go to a CSV file only */
    STORE_NONE       /* nothing: the rows go nowhere */
};

/* What a recorded column holds. */
enum rg_column { COL_VALUE = 0, COL_CLOCK, COL_CLOCKED };

/* Why rg_engine_run returned to Python. */
enum rg_end {
    END_PAUSE = 0,  /* a chunk of rows is stored, its deadline passed, or an event iteration ended
                     * whose rows are to be flushed: Python takes the rows and calls again */
    END_DONE,       /* the run reached its stop time, or an FMU asked to terminate */
    END_FAILED,     /* an FMI call failed (the call notes say which, status its status) */
    END_ZENO,       /* an event iteration did not settle (zeno_k instants) */
    END_NO_MEMORY,
    END_LOOP,       /* connected values did not settle in an instant (woke says where) */
    END_WRITE,      /* the results file or the events log cannot be written */
    END_PACE,       /* paced: a communication point was reached (t); Python waits for the wall clock */
    END_STEP,       /* Python steps the FMUs from t to step_to (they roll back with FMU state) and
                     * tells the engine with rg_engine_stepped */
    END_RANGE       /* a connected value does not fit its input's type (range_link says which link) */
};

/* The call that asked to terminate the run. */
enum rg_by { BY_DO_STEP = 0, BY_UPDATE };

/* fmi3IntervalQualifier, as fmi3GetIntervalDecimal reports it. */
enum rg_interval { INTERVAL_NOT_YET_KNOWN = 0, INTERVAL_UNCHANGED, INTERVAL_CHANGED };

/* The C functions an instance is called through: the FMU's own, or an adapter's (a Python
 * callback for an instance in a worker process or traced; the first argument is then the
 * adapter's handle). Their statuses are fmi3Status values. */
typedef int (*rg_do_step_fn)(void *, double, double, bool, bool *, bool *, bool *, double *);
typedef int (*rg_get_fn)(void *, const uint32_t *, size_t, void *, size_t);
typedef int (*rg_get_binary_fn)(void *, const uint32_t *, size_t, size_t *, const uint8_t **, size_t);
typedef int (*rg_set_fn)(void *, const uint32_t *, size_t, const void *, size_t);
typedef int (*rg_set_binary_fn)(void *, const uint32_t *, size_t, const size_t *, const uint8_t *const *, size_t);
typedef int (*rg_mode_fn)(void *);
typedef int (*rg_update_fn)(void *, bool *, bool *, bool *, bool *, bool *, double *);
typedef int (*rg_get_clock_fn)(void *, const uint32_t *, size_t, bool *);
typedef int (*rg_set_clock_fn)(void *, const uint32_t *, size_t, const bool *);
typedef int (*rg_get_interval_fn)(void *, const uint32_t *, size_t, double *, int *);
/* A String as a JSON string (Python's json.dumps of it decoded as UTF-8 with replacement), for
 * the events log: the text in *out (kept until the next call), its length in *size. */
typedef int (*rg_json_string_fn)(const char *, size_t, const char **, size_t *);

/* A value last set to a connected input: reals as d (Float32 widened), signed integers as i,
 * unsigned ones and Booleans as u; Strings and Binaries in last_bytes/last_size. */
typedef union {
    double d;
    int64_t i;
    uint64_t u;
} rg_value;

/* A growable byte buffer (the arena of String and Binary copies, the CSV text, the events). */
typedef struct {
    char *data;
    size_t size, used;
} rg_bytes;

/* The rows of one call of rg_engine_run (Python reads them; the engine grows them as needed). */
typedef struct {
    long rows, capacity;
    double *times;
    int32_t *index;          /* the super-dense index */
    uint8_t *event;          /* a row of an event iteration (decimation keeps it) */
    uint64_t *slots;         /* STORE_SLOTS: by column, capacity slots each (column c, row i at c * capacity + i) */
    uint8_t *present;        /* STORE_SLOTS: the same layout; 0 is an empty cell */
} rg_rows;

typedef struct {
    /* -- the grid and the run ------------------------------------------------------------ */
    double start, step, stop, stop_limit;
    double time_tolerance;   /* robogen.fmu.fmi.TIME_TOLERANCE: times this close (relatively) are the same ... */
    double resolution;       /* ... but never a quarter of the run's time resolution or more (0: none) ... */
    int time_ulps;           /* ... and never fewer than this many units in the last place (robogen.fmu.fmi.TIME_ULPS) */
    int max_iterations;
    bool early;              /* an FMU may return early: every step a general one */
    bool rollback;           /* several may: Python steps them (END_STEP), rolling back with FMU state */
    bool paced;              /* return after every communication point (END_PACE) */
    bool pause_at_events;    /* return after each event iteration: its rows are to be flushed */
    int store;               /* enum rg_store */
    int fd;                  /* STORE_TEXT: the CSV file, written at the end of each event iteration (or -1) */
    int events_fd;           /* the events log, written at the end of each event iteration (or -1) */
    int32_t *note_call;      /* the master's call notes (robogen.cosim.fmi3.CallNotes) */
    double *note_time;
    /* -- instances, in dependency order ---------------------------------------------------- */
    int n_instances;
    void *const *instance;   /* what their functions take first */
    const bool *event_mode;  /* an event of an FMU without Event Mode does not stop the loop */
    const int *step_order;   /* the early returner first */
    rg_do_step_fn const *do_step;
    rg_mode_fn const *enter_event, *enter_step;
    rg_update_fn const *update;
    rg_get_clock_fn const *get_clock;
    rg_set_clock_fn const *set_clock;
    rg_get_interval_fn const *get_interval;
    const int32_t *step_note, *enter_event_note, *enter_step_note, *update_note, *get_clock_note, *set_clock_note,
        *get_interval_note;  /* per instance: the note of each call */
    int n_event;             /* the instances in Event Mode (indices, in instance order) */
    const int *event_instance;
    /* -- reads: one fmi3Get<Type> call of several outputs of one instance ----------------- */
    int n_reads;
    rg_get_fn const *get;    /* its fmi3Get<Type> (NULL for K_BINARY) */
    rg_get_binary_fn const *get_binary; /* fmi3GetBinary for K_BINARY, else NULL */
    void *const *read_instance;
    const uint32_t *const *vrs;
    const size_t *count;
    const size_t *n_values;  /* the values it reads (count, or more where arrays are read: their elements) */
    const int *kind;
    void *const *buffer;     /* where each fmi3Get writes (the master's Readers' buffers) */
    size_t *const *sizes;    /* fmi3GetBinary's valueSizes (K_BINARY only) */
    const int32_t *read_note;
    /* -- the exchange after a step: reads and Set groups, in dependency order ------------- */
    int n_ops;
    const int *op;           /* r >= 0 reads r, -1 - g sets group g */
    int n_exchange_ops;      /* op[0..n_exchange_ops): the connected instances'; then the recorded ones' reads */
    const int *op_first, *op_count; /* per instance: its own exchange operations */
    int n_sets;              /* groups: the changed inputs of one target FMU and type, from one source */
    rg_set_fn const *set;    /* NULL for K_BINARY */
    rg_set_binary_fn const *set_binary;
    void *const *set_instance;
    const int *set_kind;
    const int32_t *set_note;
    const int *set_first, *set_count; /* its links */
    const int *set_target, *set_edge; /* the target instance, the connection's edge */
    int n_links;
    const int *link_read;    /* per link: the read and the index in it of the source's value */
    const int *link_index;
    const uint32_t *link_vr; /* the target input */
    const bool *link_scaled; /* a real converted on its way: factor * value + offset (NULL: no link is) */
    const double *link_factor, *link_offset;
    bool connected;          /* any value link or clock route */
    int n_edges;             /* connections between two instances (for naming an algebraic loop) */
    /* -- clocks ---------------------------------------------------------------------------- */
    const int *clock_first;  /* per instance and one more: its clocks (sorted) from here */
    const int *clock_count;
    const uint32_t *clock_vr;
    const int *out_first;    /* per instance and one more: its watched output clocks, sorted */
    const int *out_count;
    const uint32_t *out_vr;
    const int *out_clock;    /* each one's clock index */
    const int *out_dep_first, *out_dep_count; /* its dependencies in dep_vr (count -1: every input) */
    const uint32_t *dep_vr;
    int n_periodic;          /* time-based periodic input clocks: tick k at start + shift + k interval */
    const int *p_instance, *p_clock;
    const double *p_start, *p_shift, *p_interval;
    int n_aperiodic;         /* changing and countdown input clocks: the FMU announces each next tick */
    const int *a_instance, *a_clock;
    const bool *a_countdown;
    const bool *on;          /* true, as often as the most clocks of one fmi3SetClock call */
    /* -- clocked variables read (recorded, carried by a clock route, shown in the events log) */
    int n_cells;
    const int *cell_instance;
    const uint32_t *cell_vr;
    const int *cell_kind;
    const int *cell_type;    /* the FMI type (one Get call per type) */
    rg_get_fn const *cell_get;
    rg_get_binary_fn const *cell_get_binary;
    const int32_t *cell_note;
    const bool *cell_output; /* an output: not read again in an instant */
    const int *cell_clock_first, *cell_clock_count, *cell_clock; /* the clocks it belongs to */
    const int *cell_dep_first, *cell_dep_count;
    /* -- clock routes: an active output clock sets its target clocks and the values they carry */
    const int *route_first, *route_count; /* per watched output clock */
    const int *croute_first, *croute_count; /* per clock: the routes between clock domains its ticks forward */
    const int *route_source_instance; /* per route: the instance whose cells it reads */
    const int *route_target, *route_clock, *route_edge; /* route_clock -1: an input that is not clocked */
    const int *route_source_first, *route_source_count, *route_source; /* the cells it carries */
    const int *route_batch_first, *route_batch_count; /* one Set call per target type */
    rg_set_fn const *batch_set;
    rg_set_binary_fn const *batch_set_binary;
    const int32_t *batch_note;
    const int *batch_kind, *batch_first, *batch_count;
    const int *batch_cell;   /* per value of a batch: the source cell, the target's value reference */
    const uint32_t *batch_vr;
    const bool *batch_scaled; /* per value of a batch, as link_scaled */
    const double *batch_factor, *batch_offset;
    /* -- record slots ---------------------------------------------------------------------- */
    int n_columns;           /* the recorded columns after time and superdense */
    const int *column_kind;  /* enum rg_column */
    const int *column_read;  /* COL_VALUE: its read and the index in it */
    const int *column_index;
    const int *column_ref;   /* COL_CLOCK: the clock's index (-1: never active); COL_CLOCKED: the cell */
    int n_groups;            /* the recorded cells of one instance, in the order the columns meet them */
    const int *group_first, *group_count, *group_cell;
    /* -- the events log -------------------------------------------------------------------- */
    const int *event_first, *event_count; /* per clock: the clocked variables its events show (cells) */
    const int *event_cell;
    const char *const *event_head; /* per clock: its event's fmu, clock and the opening of its values */
    const char *const *event_key;  /* per variable shown: its name and a colon, in JSON */
    rg_json_string_fn json_string;
} rg_plan;

typedef struct {
    const rg_plan *p;
    int n_links, n_reads;    /* the plan's, kept: rg_engine_free reads nothing of the plan, which
                              * its owner may have freed first */
    /* -- where the run is, between calls ------------------------------------------------ */
    int phase;               /* 0: the start's row or event iteration is due */
    int stage;
    bool step_event;         /* after END_PACE or END_STEP: the step asked for Event Mode */
    bool step_in_stretch;
    double t, limit, next_time, step_to;
    long n;
    double *time;            /* per instance: the communication point of its last step */
    bool *has_next;          /* per instance: nextEventTime of its last update */
    double *next_event;
    bool *needs;             /* per instance: asked for another instant in the last update */
    int64_t *p_k;            /* per periodic clock: the index of its next tick */
    double *a_next;          /* per aperiodic clock: its next tick (INFINITY: not known) */
    bool *a_ticked;          /* per aperiodic clock: active in an instant of this event iteration */
    /* statistics, and the end */
    long steps, event_iterations, instants, early_returns;
    int term_who, term_by;
    double term_t;
    int zeno_k;
    int range_link;          /* END_RANGE: a value did not fit its input (else -1): the input (instance, */
    int range_target;        /* value reference), the value as the source's kind holds it */
    uint32_t range_vr;
    int range_kind;
    rg_value range_value;
    bool *ticked;            /* per clock: active in the instant before the last allowed (Zeno) */
    long *woke;              /* per edge: how often its source set its target's inputs (algebraic loops) */
    bool event_ended;        /* an event iteration (or the start) ended since Python last looked */
    long written;            /* the rows this call wrote to fd */
    long text_rows;          /* the rows in text */
    rg_rows rows;
    rg_bytes arena;          /* String and Binary copies: of a chunk (STORE_SLOTS) or of a row */
    rg_bytes text;           /* the CSV lines of a chunk (STORE_TEXT) */
    rg_bytes events;         /* the events log's JSON lines not written yet */
    /* the values last set to the connected inputs (per link) */
    rg_value *last;
    bool *last_valid;        /* false until the input is first set */
    char **last_bytes;       /* Strings (NUL-terminated) and Binaries: malloc'd copies */
    size_t *last_size;
    /* scratch */
    bool *flags;             /* 4 per FMU: eventHandlingNeeded, terminateSimulation, earlyReturn, stepped */
    double *last_time;       /* 1 per FMU: lastSuccessfulTime */
    uint64_t **copies;       /* per read of Strings or Binaries: the arena offsets of its values' copies */
    uint32_t *set_vrs;       /* one Set call: as many as the largest group */
    rg_value *set_values;
    const uint8_t **set_pointers;
    size_t *set_sizes;
    bool *active;            /* per clock: active in this instant */
    bool *out_on;            /* per watched output clock: what fmi3GetClock said in this instant */
    bool *out_fresh;         /* read in this instant, unchanged since */
    bool *forwarded;         /* forwarded in this instant */
    bool *clock_forwarded;   /* per clock: its routes between clock domains forwarded in this instant */
    uint32_t *clock_scratch; /* one fmi3SetClock call's value references */
    uint64_t *cell_raw;      /* the value as its C type, at the start of 8 bytes (Strings and
                              * Binaries: the offset of a copy in the arena) */
    bool *cell_fresh, *cell_live, *cell_need;
    uint32_t *get_vrs;       /* one Get call's value references, values and cells */
    uint64_t *get_buffer;
    size_t *get_sizes;
    int *get_cells;
    int *route_scratch;
    uint64_t *set_scratch;
    bool *queued, *woken;    /* per instance: the worklist of an instant, the targets of one instance */
    int *woken_edge;
} rg_engine;

rg_engine *rg_engine_new(const rg_plan *p);
void rg_engine_free(rg_engine *e);
int rg_engine_run(rg_engine *e, long max_rows, double deadline, int *status);
void rg_engine_stepped(rg_engine *e, double t, bool event);
int rg_keep_last(rg_engine *e, int link, const char *data, size_t size);
size_t rg_format_double(char *out, double x);
