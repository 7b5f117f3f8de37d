/* The schema of the interface adapters: how robogen.cosim.interfaces configures one (cffi reads
 * this file, so no preprocessor lines here; adapt.c includes it).
 *
 * An adapter is an FMI 3.0 Co-Simulation instance in front of an FMU that offers another
 * interface: FMI 2.0 Co-Simulation, Model Exchange (FMI 2.0 or 3.0) behind an integrator, or FMI
 * 3.0 Scheduled Execution. The adapter library exports the fmi3 Co-Simulation functions the master
 * calls (fmi3DoStep, fmi3Get<Type>, fmi3UpdateDiscreteStates, ...), each taking an adapter where
 * the standard has an fmi3Instance; rga_instantiate makes one. To the master's loops (the Python
 * reference and the engine) an adapter is one more FMI 3.0 Co-Simulation instance: they call it
 * through the same function pointers and never ask what is behind it. */

/* What the adapter is in front of. */
enum rga_kind { RGA_FMI2_CS = 0, RGA_FMI2_ME, RGA_FMI3_ME, RGA_FMI3_SE };

/* How a Model Exchange FMU is integrated. */
enum rga_solver {
    RGA_CVODE = 0, /* SUNDIALS CVode (BDF, Newton, dense), root finding on the event indicators */
    RGA_EULER      /* explicit Euler at a fixed step; a state event at the first step past a sign change */
};

typedef struct {
    int kind;                       /* enum rga_kind */
    const char *binary;             /* the FMU's shared object */
    const char *sundials_core;      /* SUNDIALS' libraries (fmpy's), for CVode */
    const char *sundials_cvode;
    int solver;                     /* enum rga_solver */
    double tolerance;               /* CVode's relative tolerance (absolute: it times each state's nominal) */
    double euler_step;              /* Euler's step */
    int n_states, n_indicators;     /* FMI 2.0 Model Exchange: from the model description (FMI 3.0: the FMU says) */
    bool completed_step;            /* Model Exchange: call completedIntegratorStep after every integrator step */
    int n_partitions;               /* Scheduled Execution: its input clocks, each a model partition ... */
    const uint32_t *partition_vr;
    const uint32_t *partition_priority; /* ... activated in the order of their priority (lower first), then vr */
} rga_config;

/* A new adapter of this configuration and its instance of the FMU (an fmi3Instance to the adapter
 * library's fmi3 functions), or NULL with the reason in error. The log callback has the signature
 * of fmi3LogMessageCallback; an FMI 2.0 FMU's messages reach it formatted. */
void *rga_instantiate(const rga_config *config, const char *name, const char *token, const char *resources,
                      bool visible, bool logging, void *environment, void *log, char *error, size_t error_size);

/* Statistics of an integrator: steps taken, right-hand sides evaluated, root-finding calls. */
void rga_statistics(void *adapter, long *steps, long *rhs, long *roots);
