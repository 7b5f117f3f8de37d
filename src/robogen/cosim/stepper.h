/* The types the stretch shares with Python (robogen.cosim.stepper reads this file into cffi's
 * declarations; the C unit includes it): no preprocessor lines here. */

typedef int (*rg_do_step_fn)(void *, double, double, bool, bool *, bool *, bool *, double *);
typedef int (*rg_get_fn)(void *, const uint32_t *, size_t, void *, size_t);
typedef int (*rg_get_binary_fn)(void *, const uint32_t *, size_t, size_t *, const uint8_t **, size_t);
typedef int (*rg_set_fn)(void *, const uint32_t *, size_t, const void *, size_t);
typedef int (*rg_set_binary_fn)(void *, const uint32_t *, size_t, const size_t *, const uint8_t *const *, size_t);

/* A value last set to a connected input: reals as d (Float32 widened), signed integers as i,
 * unsigned ones and Booleans as u; Strings and Binaries in last_bytes/last_size. */
typedef union {
    double d;
    int64_t i;
    uint64_t u;
} rg_value;

/* A growable byte buffer (the arena of String and Binary copies, the CSV text). */
typedef struct {
    char *data;
    size_t size, used;
} rg_bytes;

typedef struct {
    int n_instances;
    rg_do_step_fn *do_step;  /* per FMU */
    void **instance;
    const bool *event_mode;  /* an event of an FMU without Event Mode does not stop the loop */
    bool *flags;             /* 4 per FMU: eventHandlingNeeded, terminateSimulation, earlyReturn */
    double *last_time;       /* 1 per FMU: lastSuccessfulTime */
    const int32_t *step_note; /* per FMU: the note of its fmi3DoStep */
    int n_reads;
    rg_get_fn *get;          /* per read: its fmi3Get<Type> (NULL for K_BINARY) */
    rg_get_binary_fn *get_binary; /* per read: fmi3GetBinary for K_BINARY, else NULL */
    void **read_instance;
    const uint32_t **vrs;
    const size_t *count;
    const int *kind;
    void **buffer;           /* where each fmi3Get writes (the master's own buffers) */
    size_t **sizes;          /* per read: fmi3GetBinary's valueSizes (K_BINARY only) */
    const int32_t *read_note; /* per read: the note of its call */
    uint64_t **copies;       /* per read of Strings or Binaries: the arena offsets of its values' copies */
    int n_ops;
    const int *op;           /* after a step, in order: r >= 0 reads r, -1 - g sets group g */
    int n_sets;              /* groups: the changed inputs of one target FMU and type, from one source */
    rg_set_fn *set;          /* per group: its fmi3Set<Type> (NULL for K_BINARY) */
    rg_set_binary_fn *set_binary;
    void **set_instance;
    const int *set_kind;
    const int32_t *set_note;
    const int *set_first;    /* per group: its first link */
    const int *set_count;    /* and how many */
    int n_links;
    const int *link_read;    /* per link: the read and the index in it of the source's value */
    const int *link_index;
    const uint32_t *link_vr; /* the target input */
    rg_value *last;          /* per link: the value last set */
    bool *last_valid;        /* false until the input is first set */
    char **last_bytes;       /* Strings (NUL-terminated) and Binaries: malloc'd copies */
    size_t *last_size;
    uint32_t *set_vrs;       /* scratch for one Set call: as many as the largest group */
    rg_value *set_values;
    const uint8_t **set_pointers;
    size_t *set_sizes;
    int n_columns;           /* recorded columns after time and superdense */
    const int *column_read;  /* per column: its read (-1: a constant), the index in it */
    const int *column_index;
    const char *const *column_text; /* the constant's cell: "0" (a clock), "" (a clocked value) */
    int mode;
    int width;               /* slots per row (MODE_SLOTS): the columns that are read */
    int32_t *note_call;      /* the master's call notes */
    double *note_time;
    rg_bytes arena;          /* String and Binary copies: of a chunk (MODE_SLOTS) or of a row */
    rg_bytes text;           /* the CSV lines of a chunk (MODE_TEXT) */
} rg_stretch;
