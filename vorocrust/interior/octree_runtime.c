/* One MPI + sc + p4est start per process (see octree_runtime.h). */
#include "octree_runtime.h"

#include <mpi.h>
#include <p4est_base.h>
#include <sc.h>
#include <stdlib.h>

/* Open MPI's start-up leaves allocations behind on purpose (and unloads the
 * components that made them, so their stacks cannot be matched by a
 * suppression): under AddressSanitizer the leak checker is switched off
 * while MPI starts and stops (for this thread; tests/lsan.supp covers
 * MPI's own threads). */
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#define LEAK_CHECK_OFF() __lsan_disable()
#define LEAK_CHECK_ON() __lsan_enable()
#else
#define LEAK_CHECK_OFF() ((void)0)
#define LEAK_CHECK_ON() ((void)0)
#endif

static int started, we_started_mpi;

static void runtime_stop(void)
{
    sc_finalize();
    if (we_started_mpi) {
        int done = 0;
        MPI_Finalized(&done);
        if (!done) {
            LEAK_CHECK_OFF();
            MPI_Finalize();
            LEAK_CHECK_ON();
        }
    }
}

static void set_if_unset(const char *name, const char *value)
{
    if (!getenv(name))
        setenv(name, value, 0);
}

int vc_octree_runtime_start(vc_error *err)
{
    if (started)
        return 0;
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
        /* A lone process (not launched by mpirun): Open MPI's singleton
         * start would otherwise spawn a daemon and probe the network
         * transports (about 0.3 s; 0.02 s with these). The user's own
         * settings win. */
        if (!getenv("OMPI_COMM_WORLD_SIZE")) {
            set_if_unset("OMPI_MCA_ess_singleton_isolated", "1");
            set_if_unset("OMPI_MCA_pml", "ob1");
            set_if_unset("OMPI_MCA_btl", "self");
        }
        LEAK_CHECK_OFF();
        int rc = MPI_Init(NULL, NULL);
        LEAK_CHECK_ON();
        if (rc != MPI_SUCCESS)
            return vc_error_set(err, VC_EINTERNAL, "MPI_Init failed (error %d): the octree "
                                "interior needs MPI; use --interior lattice", rc);
        we_started_mpi = 1;
    }
    /* every forest lives on this process alone; sc_init registers an MPI
     * error handler, which MPI keeps to the end */
    LEAK_CHECK_OFF();
    sc_init(MPI_COMM_SELF, 0, 0, NULL, SC_LP_ERROR);
    LEAK_CHECK_ON();
    p4est_init(NULL, SC_LP_ERROR);
    started = 1;
    atexit(runtime_stop);
    return 0;
}
