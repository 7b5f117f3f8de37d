/* The types the run loop shares with Python (robogen.cosim.runloop reads this file into cffi's
 * declarations; the C unit includes it after stepper.h): no preprocessor lines here. */

typedef int (*rg_mode_fn)(void *);
typedef int (*rg_update_fn)(void *, bool *, bool *, bool *, bool *, bool *, double *);
typedef int (*rg_get_clock_fn)(void *, const uint32_t *, size_t, bool *);
typedef int (*rg_set_clock_fn)(void *, const uint32_t *, size_t, const bool *);

typedef struct {
    rg_stretch *s;           /* the instances' steps, the exchange, the reads, the CSV text */
    double start, step, stop, stop_limit;
    int max_iterations;
    bool early;              /* an FMU may return early: no quiet stretch, every step a general one */
    int n_event;             /* the instances in Event Mode (indices, in instance order) */
    const int *event_instance;
    const int *step_order;   /* the early returner first */
    const bool *may_return_early;
    rg_mode_fn *enter_event, *enter_step;  /* per instance */
    rg_update_fn *update;
    rg_get_clock_fn *get_clock;
    rg_set_clock_fn *set_clock;
    const int32_t *enter_event_note, *enter_step_note, *update_note, *get_clock_note, *set_clock_note;
    double *time;            /* per instance: the communication point of its last step */
    bool *has_next;          /* per instance: nextEventTime of its last update */
    double *next_event;
    bool *needs;             /* per instance: asked for another instant in the last update */
    const int *clock_first;  /* per instance and one more: its clocks (sorted, at most 64) from here */
    const int *clock_count;
    const uint32_t *clock_vr;
    bool *active;            /* per clock: active in this instant */
    bool *ticked;            /* per clock: active in the instant before the last allowed (Zeno) */
    const int *out_first;    /* per instance: its watched output clocks, sorted: one fmi3GetClock */
    const int *out_count;
    const uint32_t *out_vr;
    const int *out_clock;    /* each one's clock index */
    bool *out_on;            /* what fmi3GetClock said in this instant */
    bool *out_fresh;         /* per watched output clock: read in this instant, unchanged since */
    const int *out_dep_first, *out_dep_count; /* its dependencies in dep_vr (count -1: every input) */
    int n_periodic;          /* time-based periodic input clocks: tick k at start + shift + k interval */
    const int *p_instance, *p_clock;
    const double *p_start, *p_shift, *p_interval;
    int64_t *p_k;
    uint32_t *clock_scratch; /* one fmi3SetClock call's value references */
    const bool *on;          /* and its values (all true) */
    int n_columns;           /* the recorded columns (as the stretch's) */
    const int *column_kind;
    const int *column_ref;   /* COL_CLOCK: the clock's index (-1: never active); COL_CLOCKED: the cell */
    int n_cells;             /* clocked variables read: recorded, or carried by a clock connection */
    const int *cell_instance;
    const uint32_t *cell_vr;
    const int *cell_kind;
    const int *cell_type;    /* the FMI type (one Get call per type) */
    rg_get_fn *cell_get;
    rg_get_binary_fn *cell_get_binary; /* K_BINARY cells */
    const int32_t *cell_note;
    const bool *cell_output; /* an output: not read again in an instant */
    const uint64_t *cell_mask; /* the clocks (bits of the instance's clock indices) it belongs to */
    uint64_t *cell_raw;      /* the value as its C type, at the start of 8 bytes (Strings and
                              * Binaries: the offset of a copy in the stretch's arena) */
    bool *cell_fresh, *cell_live, *cell_need;
    const int *cell_dep_first, *cell_dep_count;
    const uint32_t *dep_vr;
    int n_groups;            /* the recorded cells of one instance, in the order the columns meet them */
    const int *group_first, *group_count, *group_cell;
    uint32_t *get_vrs;       /* one Get call's value references, values and cells */
    uint64_t *get_buffer;
    size_t *get_sizes;       /* fmi3GetBinary's, and fmi3SetBinary's */
    int *get_cells;
    /* connections: value links (the stretch's operations) and clock routes */
    bool connected;
    int n_exchange_ops;      /* s->op[0..n_exchange_ops): the connected instances' reads and Set groups */
    const int *op_first, *op_count; /* per instance: its own */
    const int *set_target, *set_edge; /* per Set group: the target instance, the connection's edge */
    const int *route_first, *route_count; /* per watched output clock: its routes */
    const int *route_target, *route_clock, *route_edge;
    const int *route_source_first, *route_source_count, *route_source; /* the cells it carries */
    const int *route_batch_first, *route_batch_count; /* one Set call per target type */
    rg_set_fn *batch_set;
    const int32_t *batch_note;
    const int *batch_kind, *batch_first, *batch_count;
    const int *batch_cell;   /* per value of a batch: the source cell, the target's value reference */
    const uint32_t *batch_vr;
    rg_set_binary_fn *batch_set_binary;
    uint64_t *set_scratch;
    bool *forwarded;         /* per watched output clock: forwarded in this instant */
    bool *queued, *woken;    /* per instance: the worklist of an instant, the targets of one instance */
    int *woken_edge;
    int *route_scratch;      /* one clocked_values call's cells */
    long *woke;              /* per edge: how often its source set its target's inputs (algebraic loops) */
    int n_edges;
    /* where the run is, between calls */
    int phase;               /* 0: the start's row or event iteration is due */
    int stage;
    double t, limit, next_time;
    long n;
    /* statistics, and the end */
    long steps, event_iterations, instants, early_returns;
    int term_who, term_by;
    double term_t;
    int zeno_k;
    bool pause_at_events;    /* return after each event iteration: its rows are to be flushed */
    bool event_ended;        /* an event iteration (or the start) ended since Python last looked */
    int fd;                  /* MODE_TEXT: the CSV file, written at the end of each event iteration (or -1) */
    long text_rows;          /* the rows in s->text */
    long written;            /* the rows this call wrote to fd */
    int events_fd;           /* the events log, written at the end of each event iteration (or -1) */
    rg_bytes events;         /* its JSON lines not written yet */
    const int *event_first, *event_count; /* per clock: the clocked variables its events show (cells) */
    const int *event_cell;
    const char *const *event_head; /* per clock: its event's fmu, clock and the opening of its values */
    const char *const *event_key;  /* per variable shown: its name and a colon, in JSON */
} rg_run;

/* Where one call of rg_run_system stores its rows (Python reads them). */
typedef struct {
    long rows;
    double *times;
    int32_t *index;          /* the super-dense index */
    uint8_t *event;          /* a row of an event iteration (decimation keeps it) */
    uint64_t *slots;         /* MODE_SLOTS: n_columns per row */
    uint8_t *present;        /* MODE_SLOTS: n_columns per row; 0 is an empty cell */
} rg_rows;
